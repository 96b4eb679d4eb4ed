#include "stridemap/config/scene_yaml.hpp"

#include <algorithm>
#include <cerrno>
#include <charconv>
#include <cstdint>
#include <cstring>
#include <fstream>
#include <initializer_list>
#include <map>
#include <optional>
#include <sstream>
#include <string>
#include <vector>

#include <yaml-cpp/yaml.h>

#include "stridemap/core/error.hpp"
#include "strict_yaml.hpp"
#include "walk_path_reader.hpp"

namespace stridemap {
namespace {

using namespace io_detail;

// Reads one scene document. Remembers the line of every field path it
// reads, so that problems found later on the finished Scene (by the rules
// in sim/, shared with scenes built in code) point at the right line.
class SceneReader : public StrictYamlReader {
 public:
  using StrictYamlReader::StrictYamlReader;

  void check_count(const Fields& fields, const char* name, std::size_t most) const {
    const auto it = fields.find(name);
    if (it == fields.end() || !it->second.value.IsSequence() || it->second.value.size() <= most) return;
    fail(it->second.value, name,
         "expected at most " + std::to_string(most) + " " + name + ", got " + std::to_string(it->second.value.size()));
  }

  Scene read(const YAML::Node& root) {
    if (!root.IsMap()) {
      fail(root, "", "expected a scene (a map with terrain, boxes, cylinders, cart_rail, walk_path), got " + describe(root));
    }
    const auto fields = read_map(root, "", {"terrain", "boxes", "cylinders", "cart_rail", "walk_path"});
    Scene scene;
    const auto terrain = fields.find("terrain");
    if (terrain == fields.end()) fail(root, "terrain", "required section is missing");
    scene.terrain = read_terrain(terrain->second.value);
    // Counted before any object is read: a huge list is refused at once.
    check_count(fields, "boxes", kMaxSceneBoxes);
    check_count(fields, "cylinders", kMaxSceneCylinders);
    if (const auto it = fields.find("boxes"); it != fields.end()) {
      for_each_item(it->second.value, "boxes", [&](const YAML::Node& item, const std::string& path) {
        scene.boxes.push_back(read_box(item, path));
      });
    }
    if (const auto it = fields.find("cylinders"); it != fields.end()) {
      for_each_item(it->second.value, "cylinders", [&](const YAML::Node& item, const std::string& path) {
        scene.cylinders.push_back(read_cylinder(item, path));
      });
    }
    if (const auto it = fields.find("cart_rail"); it != fields.end()) scene.cart_rail = read_rail(it->second.value);
    if (const auto it = fields.find("walk_path"); it != fields.end()) {
      scene.walk_path = read_walk_path(*this, it->second.value, "walk_path");
    }
    if (auto problem = scene.first_problem()) fail_at(problem->field_path, problem->message);
    return scene;
  }

 private:
  void read_extent(const Fields& fields, const std::string& path, double& min_x, double& min_y, double& max_x,
                   double& max_y) {
    const Field* extent = find(fields, "extent");
    if (!extent) return;
    const std::string extent_path = join(path, "extent");
    const auto sub = read_map(extent->value, extent_path, {"min_x_m", "min_y_m", "max_x_m", "max_y_m"});
    min_x = number(sub, extent->value, extent_path, "min_x_m");
    min_y = number(sub, extent->value, extent_path, "min_y_m");
    max_x = number(sub, extent->value, extent_path, "max_x_m");
    max_y = number(sub, extent->value, extent_path, "max_y_m");
  }

  HeightField read_terrain(const YAML::Node& node) {
    const std::string path = "terrain";
    if (!node.IsMap()) fail(node, path, "expected a map of fields, got " + describe(node));
    const YAML::Node kind_node = node["kind"];
    if (!kind_node) fail(node, "terrain.kind", "required field is missing (flat or procedural)");
    const std::string kind = kind_node.IsScalar() ? kind_node.Scalar() : "";
    if (kind == "flat") {
      const auto fields = read_map(node, path, {"kind", "extent", "base_elevation_m", "reflectance"},
                                   {"seed", "amplitude_m", "wavelength_m", "resolution_m", "octaves", "rocks",
                                    "rocks_area"},
                                   "only allowed with kind: procedural");
      HeightField terrain;
      read_extent(fields, path, terrain.min_x_m, terrain.min_y_m, terrain.max_x_m, terrain.max_y_m);
      terrain.base_elevation_m = number(fields, node, path, "base_elevation_m", 0.0);
      terrain.reflectance = number(fields, node, path, "reflectance", 0.5);
      return terrain;
    }
    if (kind != "procedural") fail(kind_node, "terrain.kind", "expected flat or procedural, got " + describe(kind_node));
    const auto fields = read_map(node, path, {"kind", "extent", "base_elevation_m", "reflectance", "seed",
                                              "amplitude_m", "wavelength_m", "resolution_m", "octaves", "rocks",
                                              "rocks_area"});
    ProceduralTerrainOptions options;
    read_extent(fields, path, options.min_x_m, options.min_y_m, options.max_x_m, options.max_y_m);
    options.base_elevation_m = number(fields, node, path, "base_elevation_m", 0.0);
    options.reflectance = number(fields, node, path, "reflectance", 0.5);
    options.amplitude_m = number(fields, node, path, "amplitude_m");
    options.wavelength_m = number(fields, node, path, "wavelength_m");
    options.resolution_m = number(fields, node, path, "resolution_m", options.resolution_m);
    const std::uint64_t octaves = whole_number(fields, node, path, "octaves", static_cast<std::uint64_t>(options.octaves));
    if (octaves < 1 || octaves > 8) {
      fail_at(join(path, "octaves"), "expected a whole number from 1 to 8, got " + std::to_string(octaves));
    }
    options.octaves = static_cast<int>(octaves);
    const std::uint64_t seed = whole_number(fields, node, path, "seed");
    read_rocks(fields, path, options.rocks);
    if (auto problem = options.first_problem()) fail_at(join(path, problem->field_path), problem->message);
    return make_procedural_height_field(options, seed);
  }

  void read_rocks(const Fields& fields, const std::string& path, RockFieldOptions& rocks) {
    if (const Field* list = find(fields, "rocks")) {
      for_each_item(list->value, join(path, "rocks"), [&](const YAML::Node& item, const std::string& at) {
        const auto sub = read_map(item, at, {"count", "min_radius_m", "max_radius_m", "min_height_m", "max_height_m"});
        RockClass c;
        const std::uint64_t count = whole_number(sub, item, at, "count");
        if (count > 100'000) fail_at(join(at, "count"), "expected at most 100000 rocks, got " + std::to_string(count));
        c.count = static_cast<int>(count);
        c.min_radius_m = number(sub, item, at, "min_radius_m");
        c.max_radius_m = number(sub, item, at, "max_radius_m");
        c.min_height_m = number(sub, item, at, "min_height_m");
        c.max_height_m = number(sub, item, at, "max_height_m");
        rocks.classes.push_back(c);
      });
    }
    if (const Field* area = find(fields, "rocks_area")) {
      const std::string at = join(path, "rocks_area");
      const auto sub = read_map(area->value, at, {"min_x_m", "min_y_m", "max_x_m", "max_y_m"});
      rocks.area = std::array<double, 4>{number(sub, area->value, at, "min_x_m"), number(sub, area->value, at, "min_y_m"),
                                         number(sub, area->value, at, "max_x_m"), number(sub, area->value, at, "max_y_m")};
    }
  }

  BoxObject read_box(const YAML::Node& node, const std::string& path) {
    const auto fields = read_map(node, path, {"name", "center_x_m", "center_y_m", "base_elevation_m", "length_m",
                                              "width_m", "height_m", "yaw_rad", "reflectance", "present_from_s",
                                              "present_until_s"});
    BoxObject box;
    box.name = text(fields, node, path, "name");
    box.center_x_m = number(fields, node, path, "center_x_m");
    box.center_y_m = number(fields, node, path, "center_y_m");
    box.base_elevation_m = number(fields, node, path, "base_elevation_m", 0.0);
    box.length_m = number(fields, node, path, "length_m");
    box.width_m = number(fields, node, path, "width_m");
    box.height_m = number(fields, node, path, "height_m");
    box.yaw_rad = number(fields, node, path, "yaw_rad", 0.0);
    box.reflectance = number(fields, node, path, "reflectance", 0.5);
    box.present_from_s = number(fields, node, path, "present_from_s", box.present_from_s);
    box.present_until_s = number(fields, node, path, "present_until_s", box.present_until_s);
    return box;
  }

  CylinderObject read_cylinder(const YAML::Node& node, const std::string& path) {
    const auto fields = read_map(node, path, {"name", "center_x_m", "center_y_m", "base_elevation_m", "radius_m",
                                              "height_m", "reflectance"});
    CylinderObject cylinder;
    cylinder.name = text(fields, node, path, "name");
    cylinder.center_x_m = number(fields, node, path, "center_x_m");
    cylinder.center_y_m = number(fields, node, path, "center_y_m");
    cylinder.base_elevation_m = number(fields, node, path, "base_elevation_m", 0.0);
    cylinder.radius_m = number(fields, node, path, "radius_m");
    cylinder.height_m = number(fields, node, path, "height_m");
    cylinder.reflectance = number(fields, node, path, "reflectance", 0.5);
    return cylinder;
  }

  CartRailPath read_rail(const YAML::Node& node) {
    const std::string path = "cart_rail";
    const auto fields = read_map(node, path, {"start_x_m", "end_x_m", "y_m", "step_m", "yaw_rad"});
    CartRailPath rail;
    rail.start_x_m = number(fields, node, path, "start_x_m");
    rail.end_x_m = number(fields, node, path, "end_x_m");
    rail.y_m = number(fields, node, path, "y_m", 0.0);
    rail.step_m = number(fields, node, path, "step_m");
    rail.yaw_rad = number(fields, node, path, "yaw_rad", 0.0);
    return rail;
  }

};

}  // namespace

Scene parse_scene_yaml(const std::string& text, const std::string& source_name) {
  return SceneReader(source_name).read(load_single_document(text, source_name));
}

Scene load_scene_yaml(const std::string& path) { return parse_scene_yaml(read_text_file(path, "scene file"), path); }

}  // namespace stridemap
