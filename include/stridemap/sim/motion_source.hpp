#pragma once
// Where the simulated robot is at a given time: the seam between the URG
// emulator (and any other real-time simulation) and a motion model. Static
// and cart-on-the-rail motions are here; a walking robot's trunk motion
// plugs in by implementing MotionSource.
#include <memory>
#include <string>
#include <vector>

#include "stridemap/core/pose.hpp"
#include "stridemap/sim/scene.hpp"

namespace stridemap {

class MotionSource {
 public:
  virtual ~MotionSource() = default;
  /// True pose of the trunk at `time_s` seconds after the simulation started.
  /// Must be deterministic: the same time gives the same pose.
  virtual TrunkPose pose_at(double time_s) const = 0;
  /// One line for messages and summaries ("static at x=0 y=0 yaw=0").
  virtual std::string describe() const = 0;
};

/// The trunk stays at one pose.
class StaticMotion final : public MotionSource {
 public:
  /// Throws InputError for a non-finite field.
  explicit StaticMotion(const TrunkPose& pose);
  TrunkPose pose_at(double time_s) const override;
  std::string describe() const override;

 private:
  TrunkPose pose_;
};

/// The cart on the rail (experiment cart-rail): one rail step per scan
/// period, the poses of cart_rail_poses(path); the cart stops at the end.
class CartRailMotion final : public MotionSource {
 public:
  /// Throws InputError for a bad path or a non-positive period.
  CartRailMotion(const CartRailPath& path, double scan_period_s);
  /// Pose k = floor(time / period) of the rail (the last one after the end).
  TrunkPose pose_at(double time_s) const override;
  std::string describe() const override;
  /// Time at which the cart reaches the end of the rail [s].
  double duration_s() const;
  std::size_t positions() const { return poses_.size(); }

 private:
  CartRailPath path_;
  double scan_period_s_;
  std::vector<TrunkPose> poses_;
};

}  // namespace stridemap
