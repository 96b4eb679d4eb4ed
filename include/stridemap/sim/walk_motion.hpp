#pragma once
// The walking robot as a MotionSource: the trunk of sim/trunk_motion.hpp
// walking the scene's walk_path, for the URG emulator and any other
// real-time simulation. The robot stops at the end of its path.
#include <string>

#include "stridemap/sim/motion_source.hpp"
#include "stridemap/sim/trunk_motion.hpp"

namespace stridemap {

class WalkMotion final : public MotionSource {
 public:
  /// Throws InputError when the scene has no walk_path, or when the gait or
  /// the path have a problem (the path leaving the terrain among them).
  WalkMotion(const Scene& scene, const GaitOptions& gait = {});
  /// The true trunk pose at `time_s` (clamped to [0, duration_s()]).
  TrunkPose pose_at(double time_s) const override;
  std::string describe() const override;
  double duration_s() const { return motion_.duration_s(); }

 private:
  TrunkMotion motion_;
};

}  // namespace stridemap
