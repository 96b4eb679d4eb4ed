#include "stridemap/sim/motion_source.hpp"

#include <cmath>
#include <cstdio>

#include "stridemap/core/error.hpp"
#include "stridemap/sim/cart_rail.hpp"

namespace stridemap {

StaticMotion::StaticMotion(const TrunkPose& pose) : pose_(pose) {
  const double fields[] = {pose.x_m,      pose.y_m,     pose.yaw_rad, pose.pitch_rad, pose.roll_rad,
                           pose.reference_elevation_m, pose.height_change_m};
  for (const double f : fields) {
    if (!std::isfinite(f)) throw InputError("static motion: every pose field must be finite");
  }
}

TrunkPose StaticMotion::pose_at(double) const { return pose_; }

std::string StaticMotion::describe() const {
  char text[160];
  std::snprintf(text, sizeof text, "static at x=%g m y=%g m yaw=%g rad pitch=%g rad roll=%g rad", pose_.x_m,
                pose_.y_m, pose_.yaw_rad, pose_.pitch_rad, pose_.roll_rad);
  return text;
}

CartRailMotion::CartRailMotion(const CartRailPath& path, double scan_period_s)
    : path_(path), scan_period_s_(scan_period_s), poses_(cart_rail_poses(path)) {
  if (!(std::isfinite(scan_period_s) && scan_period_s > 0.0)) {
    throw InputError("cart-rail motion: the scan period must be positive, got " + std::to_string(scan_period_s));
  }
}

TrunkPose CartRailMotion::pose_at(double time_s) const {
  if (!(time_s > 0.0)) return poses_.front();
  // The small margin keeps k * period, computed in floating point, on pose k.
  const double k = std::floor(time_s / scan_period_s_ + 1e-6);
  if (k >= static_cast<double>(poses_.size() - 1)) return poses_.back();
  return poses_[static_cast<std::size_t>(k)];
}

std::string CartRailMotion::describe() const {
  char text[160];
  std::snprintf(text, sizeof text, "cart-rail from x=%g m to x=%g m at y=%g m, %g m per scan", path_.start_x_m,
                path_.end_x_m, path_.y_m, path_.step_m);
  return text;
}

double CartRailMotion::duration_s() const { return static_cast<double>(poses_.size() - 1) * scan_period_s_; }

}  // namespace stridemap
