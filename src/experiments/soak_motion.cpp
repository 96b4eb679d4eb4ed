#include <cmath>
#include <cstdio>
#include <limits>
#include <numbers>
#include <string>

#include "stridemap/core/error.hpp"
#include "stridemap/experiments/soak.hpp"
#include "stridemap/sim/hash_mix.hpp"

namespace stridemap {
namespace {

// A standard normal number from (seed, scan, stream) alone, so that a pose
// never depends on earlier calls.
double normal(std::uint64_t seed, std::uint64_t scan, std::uint64_t stream) {
  return hashed_standard_normal(seed ^ mix64(scan * 4 + stream));
}

}  // namespace

CircuitMotion::CircuitMotion(const Scene& scene, const CircuitOptions& options) : scene_(scene), options_(options) {
  const CircuitOptions& o = options;
  const double fields[] = {o.centre_x_m, o.centre_y_m, o.radius_m, o.step_m, o.sway_amplitude_rad,
                           o.sway_period_scans, o.height_amplitude_m, o.estimate_sigma_rad};
  for (double v : fields) {
    if (!std::isfinite(v)) throw InputError("circuit motion: every field must be finite");
  }
  if (o.radius_m <= 0.0 || o.step_m <= 0.0 || o.sway_period_scans <= 0.0 || o.estimate_sigma_rad < 0.0) {
    throw InputError("circuit motion: radius_m, step_m and sway_period_scans must be > 0, estimate_sigma_rad >= 0");
  }
}

void CircuitMotion::pose_at(std::uint64_t scan, TrunkPose& truth, TrunkPose& estimate) const {
  const CircuitOptions& o = options_;
  const double k = static_cast<double>(scan);
  // Angle along the circle; kept in [0, 2 pi) so that precision does not
  // wear away over a long run.
  const double per_lap = 2.0 * std::numbers::pi * o.radius_m / o.step_m;
  const double angle = 2.0 * std::numbers::pi * std::fmod(k, per_lap) / per_lap;
  const double sway = 2.0 * std::numbers::pi * std::fmod(k, o.sway_period_scans) / o.sway_period_scans;
  truth = TrunkPose{};
  truth.x_m = o.centre_x_m + o.radius_m * std::cos(angle);
  truth.y_m = o.centre_y_m + o.radius_m * std::sin(angle);
  truth.yaw_rad = std::remainder(angle + std::numbers::pi / 2.0, 2.0 * std::numbers::pi);
  truth.pitch_rad = o.sway_amplitude_rad * std::sin(sway);
  truth.roll_rad = o.sway_amplitude_rad * std::cos(sway);
  truth.height_change_m = o.height_amplitude_m * std::sin(2.0 * sway);
  truth.reference_elevation_m = scene_.surface_height_at(truth.x_m, truth.y_m);
  estimate = truth;
  estimate.pitch_rad += o.estimate_sigma_rad * normal(o.seed, scan, 0);
  estimate.roll_rad += o.estimate_sigma_rad * normal(o.seed, scan, 1);
}

std::string CircuitMotion::describe() const {
  char text[160];
  std::snprintf(text, sizeof text, "circuit of radius %.2f m round (%.2f, %.2f), %.1f cm per scan, trunk sway %.1f deg",
                options_.radius_m, options_.centre_x_m, options_.centre_y_m, options_.step_m * 100.0,
                options_.sway_amplitude_rad * 180.0 / std::numbers::pi);
  return text;
}

}  // namespace stridemap
