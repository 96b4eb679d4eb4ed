#include "stridemap/sim/walk_motion.hpp"

#include <cstdio>

#include "stridemap/core/error.hpp"

namespace stridemap {
namespace {

const WalkPath& path_of(const Scene& scene) {
  if (!scene.walk_path) {
    throw InputError("walk motion: the scene has no walk_path section (docs/scenes.md) for the robot to walk");
  }
  return *scene.walk_path;
}

}  // namespace

WalkMotion::WalkMotion(const Scene& scene, const GaitOptions& gait) : motion_(scene, path_of(scene), gait) {}

TrunkPose WalkMotion::pose_at(double time_s) const { return motion_.at(time_s).pose; }

std::string WalkMotion::describe() const {
  char text[160];
  std::snprintf(text, sizeof text, "walking the scene's path: %zu segments in %.1f s",
                motion_.path().segments.size(), motion_.duration_s());
  return text;
}

}  // namespace stridemap
