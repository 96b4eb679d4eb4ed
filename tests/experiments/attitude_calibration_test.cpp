#include "stridemap/experiments/attitude_calibration.hpp"

#include <cmath>
#include <string>

#include <gtest/gtest.h>

#include "stridemap/core/error.hpp"
#include "stridemap/experiments/urg_walk_sensor.hpp"

namespace stridemap {
namespace {

constexpr double kDeg = 3.14159265358979323846 / 180.0;

AttitudeCalibration calibrate(const PoseErrorOptions& errors, std::uint64_t seed, bool mixed_pixels) {
  const Scene floor = flat_calibration_floor(0.35);
  UrgWalkSensorOptions urg;
  urg.mixed_pixels = mixed_pixels;
  if (mixed_pixels) urg.filters = {ScanFilterKind::range_clustering, ScanFilterKind::scan_sequence};
  MapperOptions mapper;
  UrgWalkSensor sensor(floor, urg, mapper.update, seed);
  return calibrate_attitude_on_flat_floor(sensor, errors, GaitOptions{}, mapper, seed);
}

TEST(AttitudeCalibration, FindsTheImuBiasesOnAFlatFloorDespiteTheNoise) {
  // The defaults (-0.3 / +0.3 deg, 0.2 deg noise, 2 mm legs) and the
  // opposite signs, with the paper's scan filters (their one-scan delay).
  for (const double sign : {1.0, -1.0}) {
    PoseErrorOptions errors;
    errors.imu_pitch_bias_rad *= sign;
    errors.imu_roll_bias_rad *= sign;
    for (const std::uint64_t seed : {1u, 2u, 3u}) {
      const AttitudeCalibration c = calibrate(errors, seed, seed == 2);
      EXPECT_NEAR(c.pitch_bias_rad, errors.imu_pitch_bias_rad, 0.03 * kDeg) << sign << " seed " << seed;
      EXPECT_NEAR(c.roll_bias_rad, errors.imu_roll_bias_rad, 0.03 * kDeg) << sign << " seed " << seed;
      EXPECT_NEAR(c.height_offset_m, 0.0, 0.002);
      EXPECT_GT(c.points, 1000u);
      EXPECT_LT(c.residual_rms_m, 0.01);  // the URG's range noise, not a tilt
    }
  }
}

TEST(AttitudeCalibration, AnUnbiasedImuIsLeftAlone) {
  const AttitudeCalibration c = calibrate(PoseErrorOptions::none(), 4, false);
  EXPECT_NEAR(c.pitch_bias_rad, 0.0, 0.03 * kDeg);
  EXPECT_NEAR(c.roll_bias_rad, 0.0, 0.03 * kDeg);
}

TEST(AttitudeCalibration, RefusesStancesThatCannotWork) {
  const Scene floor = flat_calibration_floor(0.35);
  MapperOptions mapper;
  UrgWalkSensor sensor(floor, UrgWalkSensorOptions{}, mapper.update, 1);
  AttitudeCalibrationOptions options;
  options.pitches_rad = {0.1};
  try {
    calibrate_attitude_on_flat_floor(sensor, PoseErrorOptions{}, GaitOptions{}, mapper, 1, options);
    FAIL() << "accepted unpaired stances";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("pair up"), std::string::npos) << e.what();
  }
  options = {};
  options.imu_readings_per_stance = 0;
  EXPECT_THROW(calibrate_attitude_on_flat_floor(sensor, PoseErrorOptions{}, GaitOptions{}, mapper, 1, options),
               InputError);
  // Stances that look at the sky see no floor.
  options = {};
  options.pitches_rad = {-0.49, -0.49, -0.49, -0.49};
  options.height_changes_m = {0.2, 0.2, 0.2, 0.2};
  options.max_range_m = 0.3;
  try {
    calibrate_attitude_on_flat_floor(sensor, PoseErrorOptions{}, GaitOptions{}, mapper, 1, options);
    FAIL() << "fitted without a floor";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("do not see the floor"), std::string::npos) << e.what();
  }
}

}  // namespace
}  // namespace stridemap
