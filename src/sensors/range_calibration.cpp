#include "stridemap/sensors/range_calibration.hpp"

#include <Eigen/Dense>
#include <algorithm>
#include <cmath>
#include <sstream>

#include "stridemap/core/error.hpp"

namespace stridemap {

double RangeCalibration::correction_m(double raw_range_m) const {
  const auto& c = coefficients;
  return c[0] + raw_range_m * (c[1] + raw_range_m * (c[2] + raw_range_m * c[3]));
}

RangeCalibrationFit fit_range_calibration(std::span<const double> measured_m,
                                          std::span<const double> true_m) {
  constexpr std::size_t unknowns = 4;
  if (measured_m.size() != true_m.size()) {
    std::ostringstream message;
    message << "range calibration fit: " << measured_m.size() << " measured ranges but "
            << true_m.size() << " true ranges";
    throw InputError(message.str());
  }
  const std::size_t pairs = measured_m.size();
  if (pairs < unknowns) {
    std::ostringstream message;
    message << "range calibration fit: " << pairs
            << " (measured, true) pairs, a cubic needs at least 4";
    throw InputError(message.str());
  }
  for (std::size_t i = 0; i < pairs; ++i) {
    if (!std::isfinite(measured_m[i]) || !std::isfinite(true_m[i])) {
      std::ostringstream message;
      message << "range calibration fit: pair " << i << " is not finite (measured "
              << measured_m[i] << " m, true " << true_m[i] << " m)";
      throw InputError(message.str());
    }
  }
  std::vector<double> distinct(measured_m.begin(), measured_m.end());
  std::sort(distinct.begin(), distinct.end());
  const auto distinct_count = static_cast<std::size_t>(
      std::unique(distinct.begin(), distinct.end()) - distinct.begin());
  if (distinct_count < unknowns) {
    std::ostringstream message;
    message << "range calibration fit: only " << distinct_count
            << " distinct measured ranges, a cubic needs at least 4";
    throw InputError(message.str());
  }

  // Fitting in s = r / max|r| keeps every Vandermonde column within [-1, 1],
  // so the conditioning depends neither on the unit nor on the span of the data.
  double scale = 0.0;
  for (double r : measured_m) scale = std::max(scale, std::abs(r));
  const auto rows = static_cast<Eigen::Index>(pairs);
  Eigen::MatrixXd design(rows, static_cast<Eigen::Index>(unknowns));
  Eigen::VectorXd correction(rows);
  for (Eigen::Index i = 0; i < rows; ++i) {
    const auto index = static_cast<std::size_t>(i);
    const double s = measured_m[index] / scale;
    design(i, 0) = 1.0;
    design(i, 1) = s;
    design(i, 2) = s * s;
    design(i, 3) = s * s * s;
    correction(i) = true_m[index] - measured_m[index];
  }
  const Eigen::ColPivHouseholderQR<Eigen::MatrixXd> qr(design);
  if (qr.rank() < static_cast<Eigen::Index>(unknowns)) {
    throw InputError(
        "range calibration fit: the measured ranges are too close together to determine a cubic");
  }
  const Eigen::VectorXd scaled = qr.solve(correction);

  RangeCalibrationFit fit;
  double scale_power = 1.0;
  for (std::size_t k = 0; k < unknowns; ++k) {
    fit.calibration.coefficients[k] = scaled(static_cast<Eigen::Index>(k)) / scale_power;
    scale_power *= scale;
  }
  fit.residuals_m.resize(pairs);
  double sum_squares = 0.0;
  for (std::size_t i = 0; i < pairs; ++i) {
    const double residual = true_m[i] - fit.calibration.corrected_m(measured_m[i]);
    fit.residuals_m[i] = residual;
    sum_squares += residual * residual;
    fit.max_abs_residual_m = std::max(fit.max_abs_residual_m, std::abs(residual));
  }
  fit.rms_residual_m = std::sqrt(sum_squares / static_cast<double>(pairs));
  return fit;
}

}  // namespace stridemap
