#pragma once
// Range calibration of eq. (4) as a cubic with per-unit coefficients
// (design.md 5: the paper's printed coefficients cannot be right, so there is
// no silent default correction), and the least-squares fit of Fig. 6.
#include <array>
#include <span>
#include <vector>

namespace stridemap {

/// corrected = raw + c0 + c1 raw + c2 raw^2 + c3 raw^3, everything in metres.
/// Default: all zero (no correction).
struct RangeCalibration {
  std::array<double, 4> coefficients{0.0, 0.0, 0.0, 0.0};
  double correction_m(double raw_range_m) const;
  double corrected_m(double raw_range_m) const { return raw_range_m + correction_m(raw_range_m); }
};

struct RangeCalibrationFit {
  RangeCalibration calibration;
  std::vector<double> residuals_m;  ///< true - corrected, per input pair
  double rms_residual_m = 0.0;
  double max_abs_residual_m = 0.0;
};

/// Least-squares fit of the cubic correction to (measured, true) range pairs.
/// Throws InputError for mismatched lengths, fewer than 4 pairs, non-finite
/// values, or pairs that cannot determine a cubic (fewer than 4 distinct
/// measured ranges).
RangeCalibrationFit fit_range_calibration(std::span<const double> measured_m,
                                          std::span<const double> true_m);

}  // namespace stridemap
