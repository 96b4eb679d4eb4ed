#include "stridemap/experiments/attitude_calibration.hpp"

#include <cmath>
#include <numbers>
#include <string>

#include <Eigen/Dense>

#include "stridemap/core/error.hpp"
#include "stridemap/core/sensor_transform.hpp"

namespace stridemap {
namespace {

// Where the calibration stands: on the floor's middle, facing +X.
constexpr double kStanceX_m = 0.0, kStanceY_m = 0.0;

struct FloorPoint {
  Eigen::Vector3d in_sensor;
  std::size_t stance = 0;
};

}  // namespace

void AttitudeCalibrationOptions::validate() const {
  if (height_changes_m.size() != pitches_rad.size() || height_changes_m.size() < 2) {
    throw InputError("attitude calibration: height_changes_m and pitches_rad must pair up, at least two stances; got " +
                     std::to_string(height_changes_m.size()) + " and " + std::to_string(pitches_rad.size()));
  }
  for (std::size_t k = 0; k < height_changes_m.size(); ++k) {
    if (!(std::isfinite(height_changes_m[k]) && std::isfinite(pitches_rad[k]) && std::abs(pitches_rad[k]) < 0.5)) {
      throw InputError("attitude calibration: stance [" + std::to_string(k) +
                       "]: height change and pitch must be finite, the pitch within +-0.5 rad");
    }
  }
  if (scans_per_stance < 1 || imu_readings_per_stance < 1) {
    throw InputError("attitude calibration: scans_per_stance and imu_readings_per_stance must be at least 1, got " +
                     std::to_string(scans_per_stance) + " and " + std::to_string(imu_readings_per_stance));
  }
  if (!(std::isfinite(max_range_m) && max_range_m > 0.0)) {
    throw InputError("attitude calibration: max_range_m must be a positive number");
  }
}

AttitudeCalibrationOptions AttitudeCalibrationOptions::wide_stances() {
  constexpr double kTilt_rad = 10.0 * std::numbers::pi / 180.0;
  AttitudeCalibrationOptions o;
  o.height_changes_m = {-0.04, -0.04, -0.04, -0.02, -0.02, -0.02, 0.0, 0.0, 0.0};
  o.pitches_rad = {-kTilt_rad, 0.0, kTilt_rad, -kTilt_rad, 0.0, kTilt_rad, -kTilt_rad, 0.0, kTilt_rad};
  o.scans_per_stance = 10;
  o.imu_readings_per_stance = 1600;
  return o;
}

Scene flat_calibration_floor(double reflectance) {
  Scene floor;
  floor.terrain.min_x_m = -2.0;
  floor.terrain.min_y_m = -2.0;
  floor.terrain.max_x_m = 2.0;
  floor.terrain.max_y_m = 2.0;
  floor.terrain.reflectance = reflectance;
  return floor;
}

AttitudeCalibration calibrate_attitude_on_flat_floor(WalkSensor& sensor, const PoseErrorOptions& errors,
                                                     const GaitOptions& gait, const MapperOptions& mapper_options,
                                                     std::uint64_t seed, const AttitudeCalibrationOptions& options) {
  options.validate();
  PoseErrorOptions standing = errors;
  standing.reference = ReferenceElevationSource::truth;
  PoseEstimator imu(standing, gait, seed);
  MapperOptions fixed = mapper_options;
  fixed.follow_robot = true;
  TerrainMapper mapper(fixed, sensor.mount());
  sensor.set_collect_points(true);

  std::vector<TrunkPose> stance_estimates;
  std::vector<FloorPoint> points;
  const double period = sensor.frame_period_s();
  std::size_t scan = 0;
  const auto collect = [&](std::size_t stance) {
    const TrunkPose& e = stance_estimates[stance];
    const Eigen::Matrix3d rotation = sensor_to_map_rotation(e, sensor.mount());
    const Eigen::Vector3d origin = sensor_origin_in_map(e, sensor.mount());
    for (const ObservedPoint& p : sensor.last_points()) {
      if (!(p.range_m <= options.max_range_m) || !p.map_m.allFinite()) continue;
      points.push_back({rotation.transpose() * (p.map_m - origin), stance});
    }
  };
  for (std::size_t k = 0; k < options.pitches_rad.size(); ++k) {
    TrunkState truth;
    truth.pose.x_m = kStanceX_m;
    truth.pose.y_m = kStanceY_m;
    truth.pose.pitch_rad = options.pitches_rad[k];
    truth.pose.height_change_m = options.height_changes_m[k];
    // Standing still, the robot averages its IMU and leg heights over the
    // stance; every scan of it is placed with that one estimate.
    TrunkPose mean{};
    for (int s = 0; s < options.imu_readings_per_stance; ++s) {
      const TrunkPose e = imu.estimate(truth, mapper.map());
      mean.x_m += e.x_m, mean.y_m += e.y_m, mean.yaw_rad += e.yaw_rad, mean.pitch_rad += e.pitch_rad;
      mean.roll_rad += e.roll_rad, mean.height_change_m += e.height_change_m;
    }
    const double n = options.imu_readings_per_stance;
    mean.x_m /= n, mean.y_m /= n, mean.yaw_rad /= n, mean.pitch_rad /= n, mean.roll_rad /= n;
    mean.height_change_m /= n;
    mean.reference_elevation_m = truth.pose.reference_elevation_m;
    stance_estimates.push_back(mean);
    for (int s = 0; s < options.scans_per_stance; ++s) {
      truth.time_s = static_cast<double>(scan++) * period;
      sensor.measure(truth.pose, mean, truth.time_s, mapper);
      // A filter's one-scan delay hands the previous scan's points back,
      // still from this stance except at its first scan.
      if (s > 0) collect(k);
    }
  }
  sensor.flush(mapper);
  collect(stance_estimates.size() - 1);
  sensor.set_collect_points(false);
  if (points.size() < 100) {
    throw InputError("attitude calibration: only " + std::to_string(points.size()) +
                     " floor points within range; the stances do not see the floor");
  }

  // Gauss-Newton on (pitch bias, roll bias, height offset): the floor's
  // points re-placed with the IMU's readings less the biases lie at z = 0.
  const auto height = [&](const FloorPoint& p, double pitch_bias, double roll_bias) {
    TrunkPose e = stance_estimates[p.stance];
    e.pitch_rad -= pitch_bias;
    e.roll_rad -= roll_bias;
    return sensor_point_to_map(p.in_sensor, e, sensor.mount()).z();
  };
  constexpr double kStep_rad = 1e-5;
  Eigen::Vector3d x = Eigen::Vector3d::Zero();
  double rms = 0.0;
  for (int iteration = 0; iteration < 4; ++iteration) {
    Eigen::Matrix3d normal = Eigen::Matrix3d::Zero();
    Eigen::Vector3d rhs = Eigen::Vector3d::Zero();
    double sum_sq = 0.0;
    for (const FloorPoint& p : points) {
      const double z = height(p, x(0), x(1));
      const Eigen::Vector3d j((height(p, x(0) + kStep_rad, x(1)) - z) / kStep_rad,
                              (height(p, x(0), x(1) + kStep_rad) - z) / kStep_rad, -1.0);
      const double residual = z - x(2);
      normal += j * j.transpose();
      rhs -= j * residual;
      sum_sq += residual * residual;
    }
    rms = std::sqrt(sum_sq / static_cast<double>(points.size()));
    x += normal.ldlt().solve(rhs);
  }
  AttitudeCalibration result;
  result.pitch_bias_rad = x(0);
  result.roll_bias_rad = x(1);
  result.height_offset_m = x(2);
  result.points = points.size();
  result.residual_rms_m = rms;
  return result;
}

}  // namespace stridemap
