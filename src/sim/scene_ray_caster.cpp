#include "stridemap/sim/scene_ray_caster.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <utility>

namespace stridemap {
namespace {

// Slab test against an axis-aligned box: whether the ray can reach it
// within max_range_m. Conservative (touching counts).
bool may_reach(const Eigen::Vector3d& min_m, const Eigen::Vector3d& max_m, const Eigen::Vector3d& origin,
               const Eigen::Vector3d& dir, double max_range_m) {
  double t_near = 0.0, t_far = max_range_m;
  for (int axis = 0; axis < 3; ++axis) {
    if (dir[axis] == 0.0) {
      if (origin[axis] < min_m[axis] || origin[axis] > max_m[axis]) return false;
      continue;
    }
    double t1 = (min_m[axis] - origin[axis]) / dir[axis];
    double t2 = (max_m[axis] - origin[axis]) / dir[axis];
    if (t1 > t2) std::swap(t1, t2);
    t_near = std::max(t_near, t1);
    t_far = std::min(t_far, t2);
    if (t_near > t_far) return false;
  }
  return true;
}

}  // namespace

SceneRayCaster::SceneRayCaster(Scene scene) : scene_(std::move(scene)) {
  scene_.validate();
  terrain_top_m_ = scene_.terrain.max_sample_height_m();
  // Slightly inflated so that rounding in the rotated corners never culls a
  // ray that grazes an object.
  const double margin = 1e-9;
  for (const BoxObject& box : scene_.boxes) {
    const double c = std::abs(std::cos(box.yaw_rad)), s = std::abs(std::sin(box.yaw_rad));
    const double half_x = 0.5 * (c * box.length_m + s * box.width_m) + margin;
    const double half_y = 0.5 * (s * box.length_m + c * box.width_m) + margin;
    object_bounds_.push_back({Eigen::Vector3d(box.center_x_m - half_x, box.center_y_m - half_y, box.base_elevation_m - margin),
                              Eigen::Vector3d(box.center_x_m + half_x, box.center_y_m + half_y, box.top_m() + margin)});
  }
  for (const CylinderObject& cylinder : scene_.cylinders) {
    const double r = cylinder.radius_m + margin;
    object_bounds_.push_back(
        {Eigen::Vector3d(cylinder.center_x_m - r, cylinder.center_y_m - r, cylinder.base_elevation_m - margin),
         Eigen::Vector3d(cylinder.center_x_m + r, cylinder.center_y_m + r, cylinder.top_m() + margin)});
  }
}

std::optional<RayHit> SceneRayCaster::cast(const Eigen::Vector3d& origin, const Eigen::Vector3d& unit_dir,
                                           double max_range_m) const {
  std::optional<RayHit> best = scene_.terrain.cast_ray(origin, unit_dir, max_range_m, terrain_top_m_);
  // Objects farther than the terrain hit cannot be nearer.
  double reach = best ? best->range_m : max_range_m;
  const int box_count = static_cast<int>(scene_.boxes.size());
  const int object_count = box_count + static_cast<int>(scene_.cylinders.size());
  for (int k = 0; k < object_count; ++k) {
    const Bounds& bounds = object_bounds_[static_cast<std::size_t>(k)];
    if (!may_reach(bounds.min_m, bounds.max_m, origin, unit_dir, reach)) continue;
    std::optional<RayHit> hit = k < box_count
        ? intersect_box(scene_.boxes[static_cast<std::size_t>(k)], origin, unit_dir, reach)
        : intersect_cylinder(scene_.cylinders[static_cast<std::size_t>(k - box_count)], origin, unit_dir, reach);
    if (hit && (!best || hit->range_m < best->range_m)) {
      best = hit;
      best->object_index = k;
      reach = hit->range_m;
    }
  }
  return best;
}

}  // namespace stridemap
