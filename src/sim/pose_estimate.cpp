#include "stridemap/sim/pose_estimate.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <string>

#include "stridemap/core/error.hpp"
#include "stridemap/sim/scene_problem.hpp"

namespace stridemap {

PoseErrorOptions PoseErrorOptions::scaled(double factor) const {
  if (!(std::isfinite(factor) && factor >= 0.0)) {
    throw InputError("pose error options: scale factor: expected a number >= 0, got " +
                     scene_rules::format_number(factor));
  }
  PoseErrorOptions out = *this;
  for (double* v : {&out.imu_pitch_noise_sigma_rad, &out.imu_pitch_bias_rad, &out.imu_roll_noise_sigma_rad,
                    &out.imu_roll_bias_rad, &out.camera_position_noise_sigma_m, &out.camera_yaw_noise_sigma_rad,
                    &out.leg_height_noise_sigma_m}) {
    *v *= factor;
  }
  return out;
}

PoseErrorOptions PoseErrorOptions::none() {
  PoseErrorOptions out = PoseErrorOptions{}.scaled(0.0);
  out.reference = ReferenceElevationSource::truth;
  return out;
}

void PoseErrorOptions::validate() const {
  using namespace scene_rules;
  const std::pair<const char*, double> sigmas[] = {{"imu_pitch_noise_sigma_rad", imu_pitch_noise_sigma_rad},
                                                   {"imu_roll_noise_sigma_rad", imu_roll_noise_sigma_rad},
                                                   {"camera_position_noise_sigma_m", camera_position_noise_sigma_m},
                                                   {"camera_yaw_noise_sigma_rad", camera_yaw_noise_sigma_rad},
                                                   {"leg_height_noise_sigma_m", leg_height_noise_sigma_m}};
  for (const auto& [field, value] : sigmas) {
    if (auto m = non_negative(value)) throw InputError(std::string("pose error options: ") + field + ": " + *m);
  }
  for (const auto& [field, value] : {std::pair<const char*, double>{"imu_pitch_bias_rad", imu_pitch_bias_rad},
                                     std::pair<const char*, double>{"imu_roll_bias_rad", imu_roll_bias_rad}}) {
    if (auto m = finite(value)) throw InputError(std::string("pose error options: ") + field + ": " + *m);
  }
}

PoseEstimator::PoseEstimator(const PoseErrorOptions& options, const GaitOptions& gait, std::uint64_t seed)
    : options_(options), gait_(gait), rng_(seed) {
  options_.validate();
  gait_.validate();
}

double PoseEstimator::foot_elevation(const ElevationMap& map, double x_m, double y_m, double fallback,
                                     const float* fused) const {
  // A foot covers a few centimetres; the median of the known cells under it
  // keeps one stray cell of the max-height rule (eq. 10) from lifting the
  // whole robot.
  const CellIndex centre = map.cell_of(x_m, y_m);
  const int reach = std::clamp(static_cast<int>(std::lround(kFootRadius_m / map.cell_size_m())), 1, kMaxFootReach);
  std::array<float, (2 * kMaxFootReach + 1) * (2 * kMaxFootReach + 1)> known{};
  int count = 0;
  for (int dx = -reach; dx <= reach; ++dx) {
    for (int dy = -reach; dy <= reach; ++dy) {
      if (dx * dx + dy * dy > reach * reach) continue;
      const CellIndex c{centre.x + dx, centre.y + dy};
      if (!map.contains(c)) continue;
      if (fused) {
        // The fused layer knows a cell from its first reading, whatever
        // eq. (9) made of it.
        const float h = fused[map.slot(c)];
        if (h == h) known[static_cast<std::size_t>(count++)] = h;
        continue;
      }
      if (map.state(c) == CellState::unknown) continue;
      // A filled cell has no readings of its own, only its estimate.
      const bool mean = options_.reference == ReferenceElevationSource::map_mean &&
                        map.state(c) == CellState::measured;
      known[static_cast<std::size_t>(count++)] = mean ? map.mean_elevation(c) : map.elevation(c);
    }
  }
  if (count == 0) return fallback;
  std::nth_element(known.begin(), known.begin() + count / 2, known.begin() + count);
  return known[static_cast<std::size_t>(count / 2)];
}

TrunkPose PoseEstimator::estimate(const TrunkState& truth, const ElevationMap& map) {
  const TrunkPose& t = truth.pose;
  if (!started_) {
    reference_m_ = t.reference_elevation_m;
    started_ = true;
  }
  TrunkPose e = t;
  const auto noise = [&](double sigma) { return sigma > 0.0 ? sigma * gaussian_(rng_) : 0.0; };
  e.pitch_rad = t.pitch_rad + options_.imu_pitch_bias_rad + noise(options_.imu_pitch_noise_sigma_rad) -
                pitch_correction_rad_;
  e.roll_rad = t.roll_rad + options_.imu_roll_bias_rad + noise(options_.imu_roll_noise_sigma_rad) -
               roll_correction_rad_;
  e.x_m = t.x_m + noise(options_.camera_position_noise_sigma_m);
  e.y_m = t.y_m + noise(options_.camera_position_noise_sigma_m);
  e.yaw_rad = t.yaw_rad + noise(options_.camera_yaw_noise_sigma_rad);
  e.height_change_m = t.height_change_m + noise(options_.leg_height_noise_sigma_m);

  feet_from_map_ = 0;
  if (options_.reference != ReferenceElevationSource::truth) {
    // The feet the map knows now give the ground; a foot on unknown cells
    // has no say (an old reading of it may be the top of a rock it has left).
    // With fewer than three known feet the ground is not determined and the
    // last h_ref stays (at the first scan: the true ground the robot starts
    // on, which defines the map's zero).
    const float* fused = nullptr;
    if (options_.reference == ReferenceElevationSource::map_fused) {
      const std::optional<std::size_t> layer = map.find_layer("fused_elevation");
      if (!layer || map.layer_spec(*layer).type != LayerType::f32) {
        throw InputError("pose estimate: h_ref from map-fused needs the map's fused_elevation layer (f32); the map has " +
                         map.layer_names());
      }
      fused = map.data(LayerId<float>{*layer});
    }
    const auto feet = foot_positions(gait_, e.x_m, e.y_m, e.yaw_rad);
    double sum = 0.0;
    for (const Eigen::Vector2d& foot : feet) {
      const double h = foot_elevation(map, foot.x(), foot.y(), std::numeric_limits<double>::quiet_NaN(), fused);
      if (!std::isfinite(h)) continue;
      sum += h;
      ++feet_from_map_;
    }
    if (feet_from_map_ >= 3) reference_m_ = sum / feet_from_map_;
    e.reference_elevation_m = reference_m_;
  }
  return e;
}

}  // namespace stridemap
