#include "stridemap/sim/cart_rail.hpp"

#include <cmath>
#include <cstddef>

#include "stridemap/core/error.hpp"

namespace stridemap {

std::vector<TrunkPose> cart_rail_poses(const CartRailPath& path) {
  Scene scene_with_rail;
  scene_with_rail.cart_rail = path;
  if (auto problem = scene_with_rail.first_problem()) {
    throw InputError(problem->field_path + ": " + problem->message);
  }
  const double length = path.end_x_m - path.start_x_m;
  const double direction = length < 0.0 ? -1.0 : 1.0;
  // A length that is a whole number of steps up to rounding (1.2 / 0.01)
  // must not lose its last step nor gain a sliver step.
  const double steps = std::abs(length) / path.step_m;
  const auto whole_steps = static_cast<std::size_t>(std::floor(steps + 1e-9));
  const bool end_is_a_step = steps - static_cast<double>(whole_steps) < 1e-9;

  std::vector<TrunkPose> poses;
  poses.reserve(whole_steps + 2);
  for (std::size_t k = 0; k <= whole_steps; ++k) {
    TrunkPose pose;
    pose.x_m = path.start_x_m + direction * static_cast<double>(k) * path.step_m;
    pose.y_m = path.y_m;
    pose.yaw_rad = path.yaw_rad;
    poses.push_back(pose);
  }
  if (end_is_a_step) {
    poses.back().x_m = path.end_x_m;  // exactly, not start + n * step
  } else {
    TrunkPose pose = poses.back();
    pose.x_m = path.end_x_m;
    poses.push_back(pose);
  }
  return poses;
}

}  // namespace stridemap
