#pragma once
// The walking robot as a SoakMotion: the tripod-gait trunk of
// sim/trunk_motion.hpp walking the scene's walk_path round and round (the
// path must be a closed loop: it ends where it starts, with the same
// heading, so that lap after lap joins without a jump).
//
// The estimate is the truth plus the IMU's pitch and roll noise, drawn from
// the scan index alone; h_ref is the true ground. The map-fed h_ref of the
// rocky walk (sim/pose_estimate.hpp) depends on every scan before, which a
// SoakMotion must not: the soak checks the pipeline's bookkeeping and
// memory over a long run, the rocky walk the estimator's errors.
#include <string>

#include "stridemap/experiments/soak.hpp"
#include "stridemap/sim/trunk_motion.hpp"

namespace stridemap {

struct WalkSoakOptions {
  GaitOptions gait{};
  /// Time between scans [s]: the URG-04LX's 10 Hz.
  double scan_period_s = 0.1;
  /// Standard deviation of the estimate's pitch and roll errors [rad].
  double estimate_sigma_rad = 0.002;
  /// How far the path's end may lie from its start, in position [m] and
  /// heading [rad], for it to count as a loop.
  double loop_tolerance_m = 0.01;
  double loop_tolerance_rad = 0.01;
  std::uint64_t seed = 1;
};

class WalkSoakMotion final : public SoakMotion {
 public:
  /// Throws InputError when the scene has no walk_path, the path is no
  /// closed loop, or the gait or path have a problem.
  WalkSoakMotion(const Scene& scene, const WalkSoakOptions& options = {});
  void pose_at(std::uint64_t scan, TrunkPose& truth, TrunkPose& estimate) const override;
  std::string describe() const override;
  /// Scans per lap of the path.
  double scans_per_lap() const { return motion_.duration_s() / options_.scan_period_s; }

 private:
  WalkSoakOptions options_;
  TrunkMotion motion_;
};

}  // namespace stridemap
