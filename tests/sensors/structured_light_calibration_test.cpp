#include "stridemap/sensors/structured_light_calibration.hpp"

#include <cmath>
#include <numbers>
#include <random>

#include <gtest/gtest.h>

#include "stridemap/core/error.hpp"

namespace stridemap {
namespace {

constexpr double kDeg = std::numbers::pi / 180.0;

// A target's stripe: the row of v(D + offset) in every 8th column, with noise.
CalibrationTargetImage target(const StructuredLightParameters& truth, double distance_m, double offset_m = 0.0,
                              double noise_px = 0.0, std::uint64_t seed = 1) {
  std::mt19937_64 rng(seed);
  std::normal_distribution<double> noise(0.0, noise_px > 0.0 ? noise_px : 1.0);
  CalibrationTargetImage image;
  image.name = std::to_string(distance_m);
  image.distance_m = distance_m;
  const double row = target_stripe_row_px(truth, truth.baseline_m, truth.sheet_angle_rad, distance_m + offset_m);
  for (int u = 0; u < truth.image_width_px; u += 8) {
    image.stripe.push_back({u + 0.5, row + (noise_px > 0.0 ? noise(rng) : 0.0)});
  }
  return image;
}

TEST(StructuredLightCalibration, RecoversBaselineAndSheetAngleFromExactRows) {
  StructuredLightParameters truth;  // Ragno: b 120 mm, beta 45 deg
  truth.baseline_m = 0.1234;
  truth.sheet_angle_rad = 47.3 * kDeg;
  std::vector<CalibrationTargetImage> targets;
  for (double d : {0.10, 0.13, 0.16, 0.19, 0.22}) targets.push_back(target(truth, d));
  StructuredLightParameters guess;  // b and beta from the defaults: never used when the linear start works
  const StructuredLightCalibration fit = calibrate_baseline_and_sheet_angle(guess, targets);
  EXPECT_NEAR(fit.baseline_m, 0.1234, 1e-9);
  EXPECT_NEAR(fit.sheet_angle_rad, 47.3 * kDeg, 1e-9);
  EXPECT_LT(fit.rms_residual_px, 1e-6);
  EXPECT_EQ(fit.degrees_of_freedom, 3);
  ASSERT_EQ(fit.targets.size(), 5u);
  EXPECT_EQ(fit.targets[0].points, 80u);
  EXPECT_NEAR(fit.targets[2].fitted_row_px, fit.targets[2].observed_row_px, 1e-6);
}

TEST(StructuredLightCalibration, NoisyRowsGiveAnHonestCovariance) {
  // Row noise of 0.3 px between targets (one draw per target, as a whole
  // stripe shifts): over many repetitions the fitted b and beta scatter as
  // the reported sigmas say.
  const StructuredLightParameters truth;
  const std::vector<double> distances{0.09, 0.11, 0.13, 0.15, 0.17, 0.19, 0.21, 0.23};
  double sum_sq_b = 0.0, sum_sq_beta = 0.0, reported_b = 0.0, reported_beta = 0.0, mean_variance = 0.0;
  const int runs = 300;
  std::mt19937_64 rng(7);
  std::normal_distribution<double> shift(0.0, 0.3);
  for (int run = 0; run < runs; ++run) {
    std::vector<CalibrationTargetImage> targets;
    for (double d : distances) {
      CalibrationTargetImage t = target(truth, d);
      const double s = shift(rng);
      for (StripePixel& p : t.stripe) p.v_px += s;
      targets.push_back(t);
    }
    const StructuredLightCalibration fit = calibrate_baseline_and_sheet_angle(truth, targets);
    sum_sq_b += std::pow(fit.baseline_m - truth.baseline_m, 2);
    sum_sq_beta += std::pow(fit.sheet_angle_rad - truth.sheet_angle_rad, 2);
    reported_b += fit.baseline_sigma_m * fit.baseline_sigma_m;
    reported_beta += fit.sheet_angle_sigma_rad * fit.sheet_angle_sigma_rad;
    mean_variance += fit.residual_sigma_px * fit.residual_sigma_px / runs;
  }
  EXPECT_NEAR(mean_variance, 0.09, 0.015);  // s^2 is unbiased
  EXPECT_NEAR(std::sqrt(sum_sq_b / runs), std::sqrt(reported_b / runs), 0.2 * std::sqrt(reported_b / runs));
  EXPECT_NEAR(std::sqrt(sum_sq_beta / runs), std::sqrt(reported_beta / runs), 0.2 * std::sqrt(reported_beta / runs));
}

TEST(StructuredLightCalibration, FitsADistanceOffsetOnRequest) {
  const StructuredLightParameters truth;
  std::vector<CalibrationTargetImage> targets;
  for (double d : {0.09, 0.12, 0.15, 0.18, 0.21}) targets.push_back(target(truth, d, 0.004));
  const StructuredLightCalibration plain = calibrate_baseline_and_sheet_angle(truth, targets);
  EXPECT_GT(plain.rms_residual_px, 0.05);  // the offset does not fit b and beta alone
  StructuredLightCalibrationOptions options;
  options.fit_distance_offset = true;
  const StructuredLightCalibration fit = calibrate_baseline_and_sheet_angle(truth, targets, options);
  EXPECT_NEAR(fit.distance_offset_m, 0.004, 1e-7);
  EXPECT_NEAR(fit.baseline_m, truth.baseline_m, 1e-7);
  EXPECT_NEAR(fit.sheet_angle_rad, truth.sheet_angle_rad, 1e-6);
  EXPECT_EQ(fit.covariance.rows(), 3);
}

TEST(StructuredLightCalibration, DropsOutlierRows) {
  const StructuredLightParameters truth;
  std::vector<CalibrationTargetImage> targets;
  for (double d : {0.10, 0.14, 0.18, 0.22}) targets.push_back(target(truth, d));
  targets[1].stripe[3].v_px += 40.0;  // a reflection picked up in one column
  const StructuredLightCalibration fit = calibrate_baseline_and_sheet_angle(truth, targets);
  EXPECT_EQ(fit.targets[1].outliers, 1u);
  EXPECT_NEAR(fit.baseline_m, truth.baseline_m, 1e-9);
}

void expect_error(const std::vector<CalibrationTargetImage>& targets, const std::string& text,
                  const StructuredLightCalibrationOptions& options = {}) {
  try {
    calibrate_baseline_and_sheet_angle(StructuredLightParameters{}, targets, options);
    ADD_FAILURE() << "no error for " << text;
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find(text), std::string::npos) << e.what();
  }
}

TEST(StructuredLightCalibration, RejectsUnusableTargets) {
  const StructuredLightParameters truth;
  std::vector<CalibrationTargetImage> two{target(truth, 0.1), target(truth, 0.2)};
  expect_error(two, "at least 3 targets");
  std::vector<CalibrationTargetImage> three{target(truth, 0.1), target(truth, 0.15), target(truth, 0.2)};
  StructuredLightCalibrationOptions offset;
  offset.fit_distance_offset = true;
  expect_error(three, "at least 4 targets", offset);
  auto same = three;
  same[2].distance_m = 0.1;
  expect_error(same, "same distance");
  auto empty = three;
  empty[1].stripe.clear();
  expect_error(empty, "target 2 (0.150000): no stripe pixels");
  auto negative = three;
  negative[0].distance_m = -0.1;
  expect_error(negative, "positive number of metres");
  auto nan = three;
  nan[0].stripe[0].v_px = NAN;
  expect_error(nan, "not finite");
}

}  // namespace
}  // namespace stridemap
