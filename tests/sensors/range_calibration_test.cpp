#include "stridemap/sensors/range_calibration.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <random>
#include <string>
#include <vector>

#include "stridemap/core/error.hpp"

namespace stridemap {
namespace {

// A plausible URG systematic error over 0.05..1 m: +30 mm near the sensor,
// about 0 at 0.5 m, -41 mm at 1 m (the alternating-sign reading of eq. 4).
const RangeCalibration known_cubic{{0.0386, -0.18, 0.3, -0.2}};

std::vector<double> evenly_spaced(double first, double last, std::size_t count) {
  std::vector<double> values(count);
  for (std::size_t i = 0; i < count; ++i) {
    values[i] = first + (last - first) * static_cast<double>(i) / static_cast<double>(count - 1);
  }
  return values;
}

std::vector<double> true_ranges(const std::vector<double>& measured, double noise_m,
                                std::uint64_t seed) {
  std::mt19937_64 generator(seed);
  std::normal_distribution<double> noise(0.0, noise_m);
  std::vector<double> truth;
  for (double r : measured) truth.push_back(known_cubic.corrected_m(r) + noise(generator));
  return truth;
}

std::string fit_error(const std::vector<double>& measured, const std::vector<double>& truth) {
  try {
    fit_range_calibration(measured, truth);
  } catch (const InputError& e) {
    return e.what();
  }
  ADD_FAILURE() << "expected an InputError";
  return {};
}

TEST(RangeCalibration, DefaultIsNoCorrection) {
  const RangeCalibration none;
  EXPECT_EQ(none.correction_m(0.7), 0.0);
  EXPECT_EQ(none.corrected_m(0.7), 0.7);
}

TEST(RangeCalibration, CorrectionIsTheCubic) {
  const RangeCalibration calibration{{0.01, 0.02, -0.03, 0.04}};
  for (double r : {0.0, 0.3, 1.0, 2.5}) {
    const double expected = 0.01 + 0.02 * r - 0.03 * r * r + 0.04 * r * r * r;
    EXPECT_NEAR(calibration.correction_m(r), expected, 1e-15) << r;
    EXPECT_NEAR(calibration.corrected_m(r), r + expected, 1e-15) << r;
  }
}

TEST(RangeCalibrationFit, NoiseFreeDataIsFittedExactly) {
  for (std::size_t count : {4u, 5u, 50u}) {
    const auto measured = evenly_spaced(0.05, 1.0, count);
    const auto truth = true_ranges(measured, 0.0, 1);
    const RangeCalibrationFit fit = fit_range_calibration(measured, truth);
    for (std::size_t k = 0; k < 4; ++k) {
      EXPECT_NEAR(fit.calibration.coefficients[k], known_cubic.coefficients[k], 1e-9)
          << "count " << count << " k " << k;
    }
    ASSERT_EQ(fit.residuals_m.size(), count);
    EXPECT_LT(fit.rms_residual_m, 1e-12);
    EXPECT_LT(fit.max_abs_residual_m, 1e-12);
  }
}

TEST(RangeCalibrationFit, RecoversKnownCubicFromNoisyData) {
  const double noise_m = 0.002;
  const auto measured = evenly_spaced(0.05, 1.0, 200);
  const auto truth = true_ranges(measured, noise_m, 20240611);
  const RangeCalibrationFit fit = fit_range_calibration(measured, truth);

  // Four standard deviations of each coefficient, measured over 2000 seeds
  // with this design (200 pairs, 2 mm noise): 0.8 mm, 0.0062, 0.013 1/m,
  // 0.0083 1/m^2.
  const double tolerance[4] = {0.0032, 0.025, 0.053, 0.033};
  for (std::size_t k = 0; k < 4; ++k) {
    EXPECT_NEAR(fit.calibration.coefficients[k], known_cubic.coefficients[k], tolerance[k]) << k;
  }
  // What matters to a user: the corrected range over the fitted interval.
  for (double r : evenly_spaced(0.05, 1.0, 96)) {
    EXPECT_NEAR(fit.calibration.corrected_m(r), known_cubic.corrected_m(r), 0.0015) << r;
  }
  // Residuals are the noise: rms near sigma, consistent with the vector.
  EXPECT_NEAR(fit.rms_residual_m, noise_m, 0.3 * noise_m);
  double sum_squares = 0.0;
  double max_abs = 0.0;
  for (std::size_t i = 0; i < measured.size(); ++i) {
    EXPECT_NEAR(fit.residuals_m[i], truth[i] - fit.calibration.corrected_m(measured[i]), 1e-15);
    sum_squares += fit.residuals_m[i] * fit.residuals_m[i];
    max_abs = std::max(max_abs, std::abs(fit.residuals_m[i]));
  }
  EXPECT_NEAR(fit.rms_residual_m, std::sqrt(sum_squares / 200.0), 1e-15);
  EXPECT_EQ(fit.max_abs_residual_m, max_abs);
  EXPECT_GT(fit.max_abs_residual_m, 2.0 * noise_m);
}

TEST(RangeCalibrationFit, WellConditionedForMillimetreSizedNumbers) {
  // The same data in millimetres: the fit must still be exact (a naive normal
  // equation solve of a Vandermonde matrix with entries up to 1e9 is not).
  std::vector<double> measured_mm = evenly_spaced(50.0, 1000.0, 30);
  std::vector<double> truth_mm;
  for (double r : measured_mm) {
    truth_mm.push_back(r + 38.6 - 0.18 * r + 0.3e-3 * r * r - 0.2e-6 * r * r * r);
  }
  const RangeCalibrationFit fit = fit_range_calibration(measured_mm, truth_mm);
  EXPECT_NEAR(fit.calibration.coefficients[0], 38.6, 1e-8);
  EXPECT_NEAR(fit.calibration.coefficients[1], -0.18, 1e-10);
  EXPECT_NEAR(fit.calibration.coefficients[2], 0.3e-3, 1e-13);
  EXPECT_NEAR(fit.calibration.coefficients[3], -0.2e-6, 1e-16);
  EXPECT_LT(fit.max_abs_residual_m, 1e-9);
}

TEST(RangeCalibrationFit, BadInputIsRejected) {
  const auto measured = evenly_spaced(0.1, 0.9, 6);
  const auto truth = true_ranges(measured, 0.0, 1);

  std::string message = fit_error(measured, std::vector<double>(truth.begin(), truth.end() - 1));
  EXPECT_NE(message.find("6 measured ranges but 5 true ranges"), std::string::npos) << message;

  message = fit_error({0.1, 0.2, 0.3}, {0.1, 0.2, 0.3});
  EXPECT_NE(message.find("3 (measured, true) pairs"), std::string::npos) << message;
  EXPECT_NE(message.find("at least 4"), std::string::npos) << message;

  message = fit_error({}, {});
  EXPECT_NE(message.find("0 (measured, true) pairs"), std::string::npos) << message;

  auto with_nan = truth;
  with_nan[3] = std::numeric_limits<double>::quiet_NaN();
  message = fit_error(measured, with_nan);
  EXPECT_NE(message.find("pair 3"), std::string::npos) << message;
  EXPECT_NE(message.find("not finite"), std::string::npos) << message;

  auto with_inf = measured;
  with_inf[0] = std::numeric_limits<double>::infinity();
  message = fit_error(with_inf, truth);
  EXPECT_NE(message.find("pair 0"), std::string::npos) << message;

  message = fit_error({0.1, 0.2, 0.3, 0.3, 0.2, 0.1}, {0.1, 0.2, 0.3, 0.3, 0.2, 0.1});
  EXPECT_NE(message.find("only 3 distinct measured ranges"), std::string::npos) << message;
}

}  // namespace
}  // namespace stridemap
