#include "stridemap/experiments/attitude_calibration.hpp"

#include <cmath>
#include <string>

#include <gtest/gtest.h>

#include "stridemap/core/error.hpp"
#include "stridemap/experiments/urg_walk_sensor.hpp"

namespace stridemap {
namespace {

constexpr double kDeg = 3.14159265358979323846 / 180.0;

// The URG's range-dependent systematic error (a cubic, docs/urg04lx.md)
// tilts the floor between near and far stances like a pitch bias; off, the
// fit must find the IMU's biases alone.
AttitudeCalibration calibrate(const PoseErrorOptions& errors, std::uint64_t seed, bool mixed_pixels,
                              bool systematic_range_error = false) {
  const Scene floor = flat_calibration_floor(0.35);
  UrgWalkSensorOptions urg;
  urg.sim.enable_systematic_error = systematic_range_error;
  // The receiver's lagging gain control reads the floor long on the side
  // the scan leaves it (the echo weakens beam by beam there) and barely
  // short on the other: a roll of about -0.046 deg with this floor, which
  // the fit rightly reports; these tests are about the IMU and the cubic.
  urg.sim.receiver.enabled = false;
  urg.mixed_pixels = mixed_pixels;
  if (mixed_pixels) urg.filters = {ScanFilterKind::range_clustering, ScanFilterKind::scan_sequence};
  MapperOptions mapper;
  UrgWalkSensor sensor(floor, urg, mapper.update, seed);
  return calibrate_attitude_on_flat_floor(sensor, errors, GaitOptions{}, mapper, seed);
}

TEST(AttitudeCalibration, FindsTheImuBiasesOnAFlatFloorDespiteTheNoise) {
  // The defaults (-0.3 / +0.3 deg, 0.2 deg noise, 2 mm legs) and the
  // opposite signs, with and without the paper's scan filters. A simulated
  // unit's own range errors tilt its floor a little too (up to 0.07 deg
  // seen), the same with or without an IMU bias: the fit finds the chain's
  // tilt, and the IMU's bias is its change.
  for (const double sign : {1.0, -1.0}) {
    PoseErrorOptions errors;
    errors.imu_pitch_bias_rad *= sign;
    errors.imu_roll_bias_rad *= sign;
    PoseErrorOptions unbiased = errors;
    unbiased.imu_pitch_bias_rad = unbiased.imu_roll_bias_rad = 0.0;
    for (const std::uint64_t seed : {1u, 2u, 3u}) {
      const AttitudeCalibration c = calibrate(errors, seed, seed == 2);
      const AttitudeCalibration unit = calibrate(unbiased, seed, seed == 2);
      EXPECT_NEAR(c.pitch_bias_rad - unit.pitch_bias_rad, errors.imu_pitch_bias_rad, 0.03 * kDeg) << sign << " " << seed;
      EXPECT_NEAR(c.roll_bias_rad - unit.roll_bias_rad, errors.imu_roll_bias_rad, 0.03 * kDeg) << sign << " " << seed;
      EXPECT_NEAR(c.pitch_bias_rad, errors.imu_pitch_bias_rad, 0.1 * kDeg) << sign << " seed " << seed;
      EXPECT_NEAR(c.roll_bias_rad, errors.imu_roll_bias_rad, 0.1 * kDeg) << sign << " seed " << seed;
      EXPECT_NEAR(c.height_offset_m, 0.0, 0.002);
      EXPECT_GT(c.points, 1000u);
      EXPECT_LT(c.residual_rms_m, 0.01);  // the URG's range noise, not a tilt
    }
  }
}

TEST(AttitudeCalibration, AnUnbiasedImuIsLeftAloneAndTheRangeErrorShowsAsPitch) {
  const AttitudeCalibration c = calibrate(PoseErrorOptions::none(), 4, false);
  EXPECT_NEAR(c.pitch_bias_rad, 0.0, 0.03 * kDeg);
  EXPECT_NEAR(c.roll_bias_rad, 0.0, 0.03 * kDeg);
  // With the systematic range error the fitted pitch is the sensor chain's:
  // the IMU bias plus the tilt the error gives the floor (about -0.18 deg),
  // the same with and without an IMU bias.
  const AttitudeCalibration chain = calibrate(PoseErrorOptions::none(), 4, false, true);
  EXPECT_LT(chain.pitch_bias_rad, -0.1 * kDeg);
  EXPECT_NEAR(chain.roll_bias_rad, 0.0, 0.03 * kDeg);
  PoseErrorOptions biased = PoseErrorOptions::none();
  biased.imu_pitch_bias_rad = -0.3 * kDeg;
  EXPECT_NEAR(calibrate(biased, 4, false, true).pitch_bias_rad - chain.pitch_bias_rad, -0.3 * kDeg, 0.03 * kDeg);
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
