#include "stridemap/sim/scene.hpp"

#include <algorithm>
#include <cmath>
#include <initializer_list>
#include <map>
#include <string>
#include <utility>

#include "stridemap/core/error.hpp"

namespace stridemap {
namespace {

// A rail longer than this many steps is a typo in step_m, not an experiment.
constexpr double max_rail_poses = 10'000'000;

std::optional<SceneProblem> terrain_problem(const HeightField& terrain) {
  using namespace scene_rules;
  const auto problem = [](std::string field, std::string message) {
    return std::optional<SceneProblem>(SceneProblem{"terrain." + std::move(field), "", std::move(message)});
  };
  const std::pair<const char*, double> extent[] = {{"extent.min_x_m", terrain.min_x_m},
                                                   {"extent.min_y_m", terrain.min_y_m},
                                                   {"extent.max_x_m", terrain.max_x_m},
                                                   {"extent.max_y_m", terrain.max_y_m}};
  for (const auto& [field, value] : extent) {
    if (auto message = finite(value)) return problem(field, *message);
  }
  if (!(terrain.max_x_m > terrain.min_x_m)) {
    return problem("extent.max_x_m", "expected a number greater than min_x_m = " + format_number(terrain.min_x_m) +
                                         ", got " + format_number(terrain.max_x_m));
  }
  if (!(terrain.max_y_m > terrain.min_y_m)) {
    return problem("extent.max_y_m", "expected a number greater than min_y_m = " + format_number(terrain.min_y_m) +
                                         ", got " + format_number(terrain.max_y_m));
  }
  if (auto message = finite(terrain.base_elevation_m)) return problem("base_elevation_m", *message);
  if (auto message = positive(terrain.resolution_m)) return problem("resolution_m", *message);
  if (auto message = scene_rules::reflectance(terrain.reflectance)) return problem("reflectance", *message);
  if (terrain.is_flat()) return std::nullopt;

  if (terrain.nx < 2 || terrain.ny < 2) {
    return problem("samples", "expected at least 2 x 2 samples, got nx = " + std::to_string(terrain.nx) +
                                  ", ny = " + std::to_string(terrain.ny));
  }
  const auto expected = static_cast<std::size_t>(terrain.nx) * static_cast<std::size_t>(terrain.ny);
  if (terrain.samples.size() != expected) {
    return problem("samples", "expected nx * ny = " + std::to_string(expected) + " samples, got " +
                                  std::to_string(terrain.samples.size()));
  }
  const double tolerance = 1e-6;
  const double grid_max_x = terrain.min_x_m + (terrain.nx - 1) * terrain.resolution_m;
  const double grid_max_y = terrain.min_y_m + (terrain.ny - 1) * terrain.resolution_m;
  if (std::abs(grid_max_x - terrain.max_x_m) > tolerance) {
    return problem("extent.max_x_m", "expected min_x_m + (nx - 1) * resolution_m = " + format_number(grid_max_x) +
                                         ", got " + format_number(terrain.max_x_m));
  }
  if (std::abs(grid_max_y - terrain.max_y_m) > tolerance) {
    return problem("extent.max_y_m", "expected min_y_m + (ny - 1) * resolution_m = " + format_number(grid_max_y) +
                                         ", got " + format_number(terrain.max_y_m));
  }
  for (std::size_t k = 0; k < terrain.samples.size(); ++k) {
    if (auto message = finite(terrain.samples[k])) return problem("samples[" + std::to_string(k) + "]", *message);
  }
  return std::nullopt;
}

template <typename Object>
std::optional<SceneProblem> object_problem(const Object& object, const std::string& path,
                                           std::initializer_list<std::pair<const char*, double>> finite_fields,
                                           std::initializer_list<std::pair<const char*, double>> positive_fields) {
  const auto problem = [&](const std::string& field, std::string message) {
    return std::optional<SceneProblem>(SceneProblem{path + "." + field, object.name, std::move(message)});
  };
  if (object.name.empty()) return problem("name", "expected a non-empty name");
  for (const auto& [field, value] : finite_fields) {
    if (auto message = scene_rules::finite(value)) return problem(field, *message);
  }
  for (const auto& [field, value] : positive_fields) {
    if (auto message = scene_rules::positive(value)) return problem(field, *message);
  }
  if (auto message = scene_rules::reflectance(object.reflectance)) return problem("reflectance", *message);
  return std::nullopt;
}

std::optional<SceneProblem> rail_problem(const CartRailPath& rail) {
  using namespace scene_rules;
  const auto problem = [](std::string field, std::string message) {
    return std::optional<SceneProblem>(SceneProblem{"cart_rail." + std::move(field), "", std::move(message)});
  };
  const std::pair<const char*, double> fields[] = {
      {"start_x_m", rail.start_x_m}, {"end_x_m", rail.end_x_m}, {"y_m", rail.y_m}, {"yaw_rad", rail.yaw_rad}};
  for (const auto& [field, value] : fields) {
    if (auto message = finite(value)) return problem(field, *message);
  }
  if (auto message = positive(rail.step_m)) return problem("step_m", *message);
  const double poses = std::abs(rail.end_x_m - rail.start_x_m) / rail.step_m;
  if (poses > max_rail_poses) {
    return problem("step_m", "gives " + format_number(std::floor(poses)) + " poses along the rail, more than the limit of " +
                                 format_number(max_rail_poses));
  }
  return std::nullopt;
}

}  // namespace

std::optional<RayHit> Scene::cast_ray(const Eigen::Vector3d& origin, const Eigen::Vector3d& unit_dir,
                                      double max_range_m) const {
  std::optional<RayHit> best = terrain.cast_ray(origin, unit_dir, max_range_m);
  const auto consider = [&](std::optional<RayHit> hit, int index) {
    if (hit && (!best || hit->range_m < best->range_m)) {
      best = hit;
      best->object_index = index;
    }
  };
  const int box_count = static_cast<int>(boxes.size());
  for (int k = 0; k < box_count; ++k) consider(intersect_box(boxes[k], origin, unit_dir, max_range_m), k);
  for (int k = 0; k < static_cast<int>(cylinders.size()); ++k) {
    consider(intersect_cylinder(cylinders[k], origin, unit_dir, max_range_m), box_count + k);
  }
  return best;
}

Scene Scene::at_time(double time_s) const {
  Scene now = *this;
  now.boxes.clear();
  for (const BoxObject& box : boxes) {
    if (box.present_at(time_s)) now.boxes.push_back(box);
  }
  return now;
}

bool Scene::changes_over_time() const {
  return std::any_of(boxes.begin(), boxes.end(), [](const BoxObject& b) { return !b.always_present(); });
}

double Scene::surface_height_at(double x_m, double y_m) const {
  double height = terrain.height_at(x_m, y_m);
  if (std::isnan(height)) return height;
  for (const BoxObject& box : boxes) {
    if (footprint_contains(box, x_m, y_m)) height = std::max(height, box.top_m());
  }
  for (const CylinderObject& cylinder : cylinders) {
    if (footprint_contains(cylinder, x_m, y_m)) height = std::max(height, cylinder.top_m());
  }
  return height;
}

double Scene::max_height_in_rect(double min_x_m, double min_y_m, double max_x_m, double max_y_m) const {
  const Rect2 rect{std::min(min_x_m, max_x_m), std::min(min_y_m, max_y_m), std::max(min_x_m, max_x_m),
                   std::max(min_y_m, max_y_m)};
  double height = terrain.max_height_in_rect(rect.min_x_m, rect.min_y_m, rect.max_x_m, rect.max_y_m);
  if (std::isnan(height)) return height;
  for (const BoxObject& box : boxes) {
    if (footprint_overlaps(box, rect)) height = std::max(height, box.top_m());
  }
  for (const CylinderObject& cylinder : cylinders) {
    if (footprint_overlaps(cylinder, rect)) height = std::max(height, cylinder.top_m());
  }
  return height;
}

std::optional<SceneProblem> Scene::first_problem() const {
  if (auto problem = terrain_problem(terrain)) return problem;
  if (boxes.size() > kMaxSceneBoxes) {
    return SceneProblem{"boxes", "", "expected at most " + std::to_string(kMaxSceneBoxes) + " boxes, got " +
                                         std::to_string(boxes.size())};
  }
  if (cylinders.size() > kMaxSceneCylinders) {
    return SceneProblem{"cylinders", "", "expected at most " + std::to_string(kMaxSceneCylinders) +
                                             " cylinders, got " + std::to_string(cylinders.size())};
  }
  for (std::size_t k = 0; k < boxes.size(); ++k) {
    const BoxObject& b = boxes[k];
    if (auto problem = object_problem(b, "boxes[" + std::to_string(k) + "]",
                                      {{"center_x_m", b.center_x_m}, {"center_y_m", b.center_y_m},
                                       {"base_elevation_m", b.base_elevation_m}, {"yaw_rad", b.yaw_rad}},
                                      {{"length_m", b.length_m}, {"width_m", b.width_m}, {"height_m", b.height_m}})) {
      return problem;
    }
    if (std::isnan(b.present_from_s) || std::isnan(b.present_until_s) || !(b.present_from_s < b.present_until_s)) {
      return SceneProblem{"boxes[" + std::to_string(k) + "].present_until_s", b.name,
                          "expected a time after present_from_s (" + std::to_string(b.present_from_s) + " s), got " +
                              std::to_string(b.present_until_s) + " s"};
    }
  }
  for (std::size_t k = 0; k < cylinders.size(); ++k) {
    const CylinderObject& c = cylinders[k];
    if (auto problem = object_problem(c, "cylinders[" + std::to_string(k) + "]",
                                      {{"center_x_m", c.center_x_m}, {"center_y_m", c.center_y_m},
                                       {"base_elevation_m", c.base_elevation_m}},
                                      {{"radius_m", c.radius_m}, {"height_m", c.height_m}})) {
      return problem;
    }
  }
  if (cart_rail) {
    if (auto problem = rail_problem(*cart_rail)) return problem;
  }
  if (walk_path) {
    if (auto problem = walk_path_extent_problem(*walk_path, terrain)) return problem;
  }
  // Objects are reported by name, so a name must say which one.
  std::map<std::string, std::string> first_use;
  const auto check_name = [&](const std::string& name, const std::string& path) -> std::optional<SceneProblem> {
    const auto [where, inserted] = first_use.emplace(name, path);
    if (inserted) return std::nullopt;
    return SceneProblem{path + ".name", name, "duplicate name \"" + name + "\" (also " + where->second + ".name)"};
  };
  for (std::size_t k = 0; k < boxes.size(); ++k) {
    if (auto problem = check_name(boxes[k].name, "boxes[" + std::to_string(k) + "]")) return problem;
  }
  for (std::size_t k = 0; k < cylinders.size(); ++k) {
    if (auto problem = check_name(cylinders[k].name, "cylinders[" + std::to_string(k) + "]")) return problem;
  }
  return std::nullopt;
}

void Scene::validate() const {
  const auto problem = first_problem();
  if (!problem) return;
  std::string text = "scene: " + problem->field_path;
  if (!problem->object_name.empty()) text += " of \"" + problem->object_name + "\"";
  throw InputError(text + ": " + problem->message);
}

}  // namespace stridemap
