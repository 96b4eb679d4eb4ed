#include "stridemap/sim/pose_estimate.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <optional>
#include <string>

#include <Eigen/Geometry>

#include "stridemap/core/error.hpp"
#include "stridemap/core/stance_height.hpp"
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
  if (!(foothold_map_sigma_m >= 0.0)) {
    throw InputError("pose error options: foothold_map_sigma_m: expected a number >= 0 (or infinity), got " +
                     format_number(foothold_map_sigma_m));
  }
  if (!(foothold_gate_sigmas > 0.0)) {
    throw InputError("pose error options: foothold_gate_sigmas: expected a number > 0 (or infinity), got " +
                     format_number(foothold_gate_sigmas));
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

namespace {

Eigen::Matrix3d trunk_rotation(const TrunkPose& p) {
  return (Eigen::AngleAxisd(p.yaw_rad, Eigen::Vector3d::UnitZ()) * Eigen::AngleAxisd(p.pitch_rad, Eigen::Vector3d::UnitY()) *
          Eigen::AngleAxisd(p.roll_rad, Eigen::Vector3d::UnitX()))
      .toRotationMatrix();
}

/// The trunk's height change between the last scan on one tripod and the
/// first on the other, which no foot measures (no double support): about
/// what the gait's bob and a 20 % slope move it in a tenth of a second.
constexpr double kTripodSwitchSigma_m = 0.002;

}  // namespace

Eigen::Vector3d PoseEstimator::foot_from_trunk_in_map(const TrunkState& truth,
                                                      const std::pair<Eigen::Matrix3d, Eigen::Matrix3d>& rotations,
                                                      std::size_t f) {
  // The trunk reference point sits h_ref + d_z above the map's zero (eq. 9
  // without the mount); the kinematics measure each foot from it in the
  // trunk frame, with encoder noise, and the IMU's attitude turns that into
  // the map frame.
  const TrunkPose& t = truth.pose;
  const Eigen::Vector3d trunk(t.x_m, t.y_m, t.reference_elevation_m + t.height_change_m);
  const double sigma = options_.leg_height_noise_sigma_m;
  Eigen::Vector3d in_trunk = rotations.first.transpose() * (truth.feet[f].position_m - trunk);
  // One draw per axis, z first: the order GCC gave the three draws when
  // they were constructor arguments (unspecified in C++; clang went x
  // first), so the documented walks stay and every compiler now agrees.
  for (int axis = 2; axis >= 0; --axis) in_trunk[axis] += sigma > 0.0 ? sigma * gaussian_(rng_) : 0.0;
  return rotations.second * in_trunk;
}

bool PoseEstimator::trunk_on_footholds(const TrunkState& truth, const std::array<double, 6>& depth_m, double& z_m,
                                       double& variance_m2) const {
  double sum = 0.0, variance_sum = 0.0;
  int n = 0;
  for (std::size_t f = 0; f < 6; ++f) {
    if (!truth.feet[f].in_stance || !footholds_[f].known) continue;
    sum += footholds_[f].z_m + depth_m[f];
    variance_sum += footholds_[f].variance_m2;
    ++n;
  }
  if (n == 0) return false;
  // The footholds of one tripod share the error of the height they were
  // set from, so their variances do not average down; the encoders' do.
  const double leg_variance = options_.leg_height_noise_sigma_m * options_.leg_height_noise_sigma_m;
  z_m = sum / n;
  variance_m2 = variance_sum / n + leg_variance / n;
  return true;
}

double PoseEstimator::trunk_height_from_footholds(const TrunkState& truth, const TrunkPose& e,
                                                  const ElevationMap& map) {
  const std::pair<Eigen::Matrix3d, Eigen::Matrix3d> rotations{trunk_rotation(truth.pose), trunk_rotation(e)};
  const double sigma = options_.leg_height_noise_sigma_m;
  const double leg_variance = sigma * sigma;
  const double true_trunk_m = truth.pose.reference_elevation_m + truth.pose.height_change_m;
  StanceHeightOptions stance_options;
  stance_options.sole_radius_m = kFootRadius_m;
  stance_options.gate_sigmas = options_.foothold_gate_sigmas;
  stance_options.depth_sigma_m = sigma;
  const StanceHeightReader reader(map, stance_options);
  // The stance feet as the robot knows them: each sole placed by the
  // kinematics and the estimated pose, averaged over its stance (the foot
  // does not move while it stands).
  std::array<StanceFoot, 6> stance{};
  std::array<std::size_t, 6> foot_of{};
  std::array<double, 6> depth{};
  std::size_t standing = 0;
  for (std::size_t f = 0; f < 6; ++f) {
    if (!truth.feet[f].in_stance) {
      soles_[f] = {};  // lifted: it lands on a new foothold
      footholds_[f].known = false;
      continue;
    }
    const Eigen::Vector3d in_map = foot_from_trunk_in_map(truth, rotations, f);
    depth[f] = -in_map.z();
    SoleAverage& sole = soles_[f];
    sole.sum_m += Eigen::Vector2d(e.x_m + in_map.x(), e.y_m + in_map.y());
    ++sole.scans;
    const Eigen::Vector2d at = sole.sum_m / sole.scans;
    stance[standing] = {at.x(), at.y(), depth[f]};
    foot_of[standing++] = f;
  }
  const StanceHeight read = reader.read(map, std::span<const StanceFoot>(stance.data(), standing));
  // Per stance foot: the trunk's height above the map's zero as that foot
  // gives it (foothold height + kinematic depth), its variance, and its
  // error against the truth by cause.
  std::array<double, 6> z{}, v{};
  std::array<HeightReferenceError, 6> parts{};
  std::array<bool, 6> use{};
  int n = 0;
  for (std::size_t k = 0; k < standing; ++k) {
    const StanceFootHeight& foot = read.feet[k];
    if (!foot.used) continue;
    const std::size_t f = foot_of[k];
    z[f] = foot.trunk_z_m;
    v[f] = foot.variance_m2;
    use[f] = true;
    ++n;
    const Eigen::Vector3d& sole_truth = truth.feet[f].position_m;
    const double read_m = foot.ground_m;
    const std::optional<SoleGround> at_truth = reader.ground_under(map, sole_truth.x(), sole_truth.y());
    const double map_at_truth_m = at_truth ? at_truth->height_m : read_m;
    parts[f].placement_m = read_m - map_at_truth_m;
    parts[f].map_m = map_at_truth_m - sole_truth.z();
    parts[f].kinematics_m = depth[f] - (true_trunk_m - sole_truth.z());
  }
  const double gate2 = options_.foothold_gate_sigmas * options_.foothold_gate_sigmas;

  // The prediction: the stance feet's footholds, set as each landed, plus
  // their kinematic depths now. With none known (no double support) the
  // last height stays, less certain by a tripod switch.
  double predicted_m = std::numeric_limits<double>::quiet_NaN(), predicted_variance_m2 = 0.0;
  if (options_.foothold_odometry) {
    if (!trunk_on_footholds(truth, depth, predicted_m, predicted_variance_m2)) {
      predicted_m = trunk_z_m_;
      predicted_variance_m2 = trunk_variance_m2_ + kTripodSwitchSigma_m * kTripodSwitchSigma_m;
    }
    // A zero variance (no encoder noise) would give the map no say at all.
    predicted_variance_m2 = std::max(predicted_variance_m2, 1e-12);
    for (std::size_t f = 0; f < 6; ++f) {
      if (!use[f]) continue;
      const double d = z[f] - predicted_m;
      if (d * d > gate2 * (v[f] + predicted_variance_m2)) use[f] = false, --n;
    }
  }
  feet_from_map_ = n;
  if (n == 0 && !options_.foothold_odometry) return std::numeric_limits<double>::quiet_NaN();

  double weight_sum = options_.foothold_odometry ? 1.0 / predicted_variance_m2 : 0.0;
  double sum = options_.foothold_odometry ? predicted_m * weight_sum : 0.0;
  HeightReferenceError split;
  if (options_.foothold_odometry) split.odometry_m = weight_sum * (predicted_m - true_trunk_m);
  for (std::size_t f = 0; f < 6; ++f) {
    if (!use[f]) continue;
    const double w = 1.0 / v[f];
    weight_sum += w;
    sum += w * z[f];
    split.map_m += w * parts[f].map_m;
    split.placement_m += w * parts[f].placement_m;
    split.kinematics_m += w * parts[f].kinematics_m;
  }
  const double trunk_m = sum / weight_sum;
  for (double* part : {&split.odometry_m, &split.map_m, &split.placement_m, &split.kinematics_m}) *part /= weight_sum;
  split.error_m = trunk_m - true_trunk_m;
  split.feet_read = n;
  height_error_ = split;

  trunk_z_m_ = trunk_m;
  trunk_variance_m2_ = 1.0 / weight_sum;
  // A foot that lands takes its foothold from the height just estimated.
  for (std::size_t f = 0; f < 6; ++f) {
    if (!truth.feet[f].in_stance || footholds_[f].known) continue;
    footholds_[f] = {true, trunk_m - depth[f], trunk_variance_m2_ + leg_variance};
  }
  return trunk_m;
}

double PoseEstimator::trunk_height_from_legs(const TrunkState& truth, const TrunkPose& e, const ElevationMap& map,
                                             const float* fused) {
  const std::pair<Eigen::Matrix3d, Eigen::Matrix3d> rotations{trunk_rotation(truth.pose), trunk_rotation(e)};
  const double sigma = options_.leg_height_noise_sigma_m;
  std::array<double, 6> depth{};
  std::array<Eigen::Vector2d, 6> sole{};
  for (std::size_t f = 0; f < 6; ++f) {
    if (!truth.feet[f].in_stance) {
      footholds_[f].known = false;  // lifted: it lands on a new foothold
      continue;
    }
    const Eigen::Vector3d in_map = foot_from_trunk_in_map(truth, rotations, f);
    depth[f] = -in_map.z();
    sole[f] = Eigen::Vector2d(e.x_m + in_map.x(), e.y_m + in_map.y());
  }
  const double leg_variance = sigma * sigma;
  double predicted = trunk_z_m_, predicted_variance = trunk_variance_m2_ + kTripodSwitchSigma_m * kTripodSwitchSigma_m;
  const bool switched = !trunk_on_footholds(truth, depth, predicted, predicted_variance);
  if (switched && last_time_s_ > stance_start_time_s_) {
    // Across the switch the trunk keeps the climb rate it had over the last
    // stance: a whole step, over which the gait's bob nearly cancels.
    const double rate = (trunk_z_m_ - stance_start_z_m_) / (last_time_s_ - stance_start_time_s_);
    predicted += rate * (truth.time_s - last_time_s_);
  }
  const double map_variance = options_.foothold_map_sigma_m * options_.foothold_map_sigma_m;
  for (std::size_t f = 0; f < 6; ++f) {
    if (!truth.feet[f].in_stance || footholds_[f].known) continue;
    Foothold& h = footholds_[f];
    h = {true, predicted - depth[f], predicted_variance + leg_variance};
    if (!std::isfinite(map_variance)) continue;
    const double from_map = foot_elevation(map, sole[f].x(), sole[f].y(), std::numeric_limits<double>::quiet_NaN(), fused);
    if (!std::isfinite(from_map)) continue;
    ++feet_from_map_;
    const double gain = h.variance_m2 / (h.variance_m2 + map_variance);
    h.z_m += gain * (from_map - h.z_m);
    h.variance_m2 *= 1.0 - gain;
  }
  trunk_on_footholds(truth, depth, trunk_z_m_, trunk_variance_m2_);
  if (switched) {
    stance_start_z_m_ = trunk_z_m_;
    stance_start_time_s_ = truth.time_s;
  }
  last_time_s_ = truth.time_s;
  return trunk_z_m_;
}

TrunkPose PoseEstimator::estimate(const TrunkState& truth, const ElevationMap& map) {
  const TrunkPose& t = truth.pose;
  if (!started_) {
    // The map's zero is the ground the robot starts on: the first footholds
    // are where the trunk truly stands.
    trunk_z_m_ = t.reference_elevation_m + t.height_change_m;
    trunk_variance_m2_ = 0.0;
    stance_start_time_s_ = last_time_s_ = truth.time_s;
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
  height_error_ = {};
  if (options_.reference != ReferenceElevationSource::truth) {
    // The feet the map knows now give the ground; a foot on unknown cells
    // has no say (an old reading of it may be the top of a rock it has left).
    // With fewer than three known feet the ground is not determined and the
    // last h_ref stays (at the first scan: the true ground the robot starts
    // on, which defines the map's zero).
    const float* fused = nullptr;
    if (reads_fused_layer(options_.reference)) {
      const std::optional<std::size_t> layer = map.find_layer("fused_elevation");
      if (!layer || map.layer_spec(*layer).type != LayerType::f32) {
        throw InputError("pose estimate: h_ref from " + std::string(name(options_.reference)) + " needs the map's fused_elevation layer (f32); the map has " +
                         map.layer_names());
      }
      fused = map.data(LayerId<float>{*layer});
    }
    if (options_.reference == ReferenceElevationSource::map_footholds) {
      const std::optional<std::size_t> variance = map.find_layer("fused_variance");
      if (!variance || map.layer_spec(*variance).type != LayerType::f32) {
        throw InputError("pose estimate: h_ref from map-footholds needs the map's fused_variance layer (f32); "
                         "the map has " + map.layer_names());
      }
      const double trunk = trunk_height_from_footholds(truth, e, map);
      // No stance foot on known cells (without odometry): the last h_ref stays.
      if (std::isfinite(trunk)) reference_m_ = trunk - e.height_change_m;
      e.reference_elevation_m = reference_m_;
      if (!std::isfinite(trunk)) {
        const double held = (e.reference_elevation_m + e.height_change_m) - (t.reference_elevation_m + t.height_change_m);
        height_error_ = {held, held, 0.0, 0.0, 0.0, 0};
      }
      return e;
    }
    if (options_.reference == ReferenceElevationSource::legs) {
      e.reference_elevation_m = trunk_height_from_legs(truth, e, map, fused) - e.height_change_m;
      reference_m_ = e.reference_elevation_m;
      return e;
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
