#include "stridemap/experiments/walk_soak_motion.hpp"

#include <cmath>
#include <cstdio>
#include <numbers>
#include <string>

#include "stridemap/core/error.hpp"
#include "stridemap/sim/hash_mix.hpp"
#include "stridemap/sim/walk_path.hpp"

namespace stridemap {
namespace {

const WalkPath& loop_of(const Scene& scene) {
  if (!scene.walk_path) {
    throw InputError("walk soak: the scene has no walk_path section (docs/scenes.md) for the robot to walk");
  }
  return *scene.walk_path;
}

// A standard normal number from (seed, scan, stream) alone, as the circuit
// draws its own, so that a pose never depends on earlier calls.
double hashed_normal(std::uint64_t seed, std::uint64_t scan, std::uint64_t stream) {
  return hashed_standard_normal(seed ^ mix64(scan * 4 + stream));
}

}  // namespace

WalkSoakMotion::WalkSoakMotion(const Scene& scene, const WalkSoakOptions& options)
    : options_(options), motion_(scene, loop_of(scene), options.gait) {
  const WalkSoakOptions& o = options_;
  if (!(std::isfinite(o.scan_period_s) && o.scan_period_s > 0.0)) {
    throw InputError("walk soak: scan_period_s must be a positive number");
  }
  if (!(std::isfinite(o.estimate_sigma_rad) && o.estimate_sigma_rad >= 0.0)) {
    throw InputError("walk soak: estimate_sigma_rad must be a number >= 0");
  }
  const WalkPath& path = motion_.path();
  const TrunkPose end = motion_.at(motion_.duration_s()).pose;
  const double gap_m = std::hypot(end.x_m - path.start_x_m, end.y_m - path.start_y_m);
  const double turn_rad = std::abs(std::remainder(end.yaw_rad - path.start_yaw_rad, 2.0 * std::numbers::pi));
  if (!(gap_m <= o.loop_tolerance_m && turn_rad <= o.loop_tolerance_rad)) {
    char text[200];
    std::snprintf(text, sizeof text,
                  "walk soak: the walk_path is no closed loop: it ends %.3f m from its start and %.1f deg off "
                  "its starting heading",
                  gap_m, turn_rad * 180.0 / std::numbers::pi);
    throw InputError(text);
  }
}

void WalkSoakMotion::pose_at(std::uint64_t scan, TrunkPose& truth, TrunkPose& estimate) const {
  // Within the lap, so that precision does not wear away over a long run.
  const double lap_s = motion_.duration_s();
  const double time_s = std::fmod(static_cast<double>(scan) * options_.scan_period_s, lap_s);
  truth = motion_.at(time_s).pose;
  estimate = truth;
  estimate.pitch_rad += options_.estimate_sigma_rad * hashed_normal(options_.seed, scan, 0);
  estimate.roll_rad += options_.estimate_sigma_rad * hashed_normal(options_.seed, scan, 1);
}

std::string WalkSoakMotion::describe() const {
  char text[160];
  std::snprintf(text, sizeof text, "walking the scene's loop (%zu segments, %.0f scans a lap), tripod gait",
                motion_.path().segments.size(), scans_per_lap());
  return text;
}

}  // namespace stridemap
