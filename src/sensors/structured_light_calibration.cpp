#include "stridemap/sensors/structured_light_calibration.hpp"

#include <algorithm>
#include <cmath>
#include <numbers>

#include <Eigen/Dense>

#if defined(__GNUC__)
#pragma GCC diagnostic push
#pragma GCC diagnostic ignored "-Wshadow"
#pragma GCC diagnostic ignored "-Wconversion"
#pragma GCC diagnostic ignored "-Wpedantic"
#endif
#include <unsupported/Eigen/NonLinearOptimization>
#if defined(__GNUC__)
#pragma GCC diagnostic pop
#endif

#include "stridemap/core/error.hpp"

namespace stridemap {
namespace {

constexpr double kRightAngle_rad = std::numbers::pi / 2.0;

std::string target_label(const CalibrationTargetImage& t, std::size_t index) {
  return "calibration target " + std::to_string(index + 1) + (t.name.empty() ? "" : " (" + t.name + ")");
}

// The residuals observed - v(D + delta) and their Jacobian, for Eigen's
// Levenberg-Marquardt (which minimises the sum of squares of operator()).
struct TargetRows {
  using Scalar = double;
  enum { InputsAtCompileTime = Eigen::Dynamic, ValuesAtCompileTime = Eigen::Dynamic };
  using InputType = Eigen::VectorXd;
  using ValueType = Eigen::VectorXd;
  using JacobianType = Eigen::MatrixXd;

  Eigen::VectorXd distances, rows;
  double half_height = 0.0, tan_tau = 0.0;
  int parameters = 2;

  int inputs() const { return parameters; }
  int values() const { return static_cast<int>(rows.size()); }

  double offset(const Eigen::VectorXd& x) const { return parameters == 3 ? x[2] : 0.0; }
  int operator()(const Eigen::VectorXd& x, Eigen::VectorXd& residuals) const {
    const double cot_beta = 1.0 / std::tan(x[1]);
    for (Eigen::Index k = 0; k < rows.size(); ++k) {
      const double depth = distances[k] + offset(x);
      residuals[k] = rows[k] - half_height * (1.0 - (x[0] / depth - cot_beta) / tan_tau);
    }
    return 0;
  }
  int df(const Eigen::VectorXd& x, Eigen::MatrixXd& jacobian) const {
    const double sin_beta = std::sin(x[1]);
    for (Eigen::Index k = 0; k < rows.size(); ++k) {
      const double depth = distances[k] + offset(x);
      // d residual = -d v;  v = H/2 (1 - (b/z - cot beta) / tan tau).
      jacobian(k, 0) = half_height / (tan_tau * depth);
      jacobian(k, 1) = half_height / (tan_tau * sin_beta * sin_beta);
      if (parameters == 3) jacobian(k, 2) = -half_height * x[0] / (tan_tau * depth * depth);
    }
    return 0;
  }
};

// Mean row of a target's stripe without outliers.
CalibrationTargetFit summarise(const CalibrationTargetImage& target, double outlier_px) {
  std::vector<double> rows;
  for (const StripePixel& p : target.stripe) rows.push_back(p.v_px);
  std::vector<double> sorted = rows;
  std::nth_element(sorted.begin(), sorted.begin() + static_cast<std::ptrdiff_t>(sorted.size() / 2), sorted.end());
  const double median = sorted[sorted.size() / 2];
  CalibrationTargetFit fit;
  fit.name = target.name;
  fit.distance_m = target.distance_m;
  double sum = 0.0;
  for (double v : rows) {
    if (std::abs(v - median) > outlier_px) {
      ++fit.outliers;
      continue;
    }
    sum += v;
    ++fit.points;
  }
  fit.observed_row_px = sum / static_cast<double>(fit.points);
  double sum_sq = 0.0;
  for (double v : rows) {
    if (std::abs(v - median) <= outlier_px) sum_sq += (v - fit.observed_row_px) * (v - fit.observed_row_px);
  }
  fit.scatter_px = std::sqrt(sum_sq / static_cast<double>(fit.points));
  return fit;
}

}  // namespace

double target_stripe_row_px(const StructuredLightParameters& camera, double baseline_m, double sheet_angle_rad,
                            double distance_m) {
  return 0.5 * camera.image_height_px *
         (1.0 - (baseline_m / distance_m - 1.0 / std::tan(sheet_angle_rad)) / std::tan(camera.half_fov_vertical_rad));
}

StructuredLightCalibration calibrate_baseline_and_sheet_angle(const StructuredLightParameters& camera,
                                                              std::span<const CalibrationTargetImage> targets,
                                                              const StructuredLightCalibrationOptions& options) {
  camera.validate();
  const int parameters = options.fit_distance_offset ? 3 : 2;
  if (static_cast<int>(targets.size()) < parameters + 1) {
    throw InputError("structured light calibration: " + std::to_string(targets.size()) + " target image(s) given; "
                     "fitting " + std::string(options.fit_distance_offset ? "b, beta and the distance offset" : "b and beta") +
                     " with an uncertainty needs at least " + std::to_string(parameters + 1) +
                     " targets at different distances");
  }
  if (!(options.outlier_distance_px > 0.0) || options.max_iterations < 1) {
    throw InputError("structured light calibration: outlier_distance_px must be > 0 and max_iterations >= 1");
  }
  StructuredLightCalibration result;
  TargetRows problem;
  problem.parameters = parameters;
  problem.half_height = 0.5 * camera.image_height_px;
  problem.tan_tau = std::tan(camera.half_fov_vertical_rad);
  problem.distances.resize(static_cast<Eigen::Index>(targets.size()));
  problem.rows.resize(static_cast<Eigen::Index>(targets.size()));
  for (std::size_t k = 0; k < targets.size(); ++k) {
    const CalibrationTargetImage& t = targets[k];
    const std::string label = target_label(t, k);
    if (!(std::isfinite(t.distance_m) && t.distance_m > 0.0)) {
      throw InputError(label + ": the distance must be a positive number of metres, got " + std::to_string(t.distance_m));
    }
    if (t.stripe.empty()) throw InputError(label + ": no stripe pixels (was the stripe detected?)");
    for (const StripePixel& p : t.stripe) {
      if (!std::isfinite(p.u_px) || !std::isfinite(p.v_px)) throw InputError(label + ": a stripe pixel is not finite");
    }
    for (std::size_t j = 0; j < k; ++j) {
      if (std::abs(targets[j].distance_m - t.distance_m) < 1e-9) {
        throw InputError(label + ": same distance as " + target_label(targets[j], j) +
                         "; every target needs its own distance");
      }
    }
    result.targets.push_back(summarise(t, options.outlier_distance_px));
    problem.distances[static_cast<Eigen::Index>(k)] = t.distance_m;
    problem.rows[static_cast<Eigen::Index>(k)] = result.targets.back().observed_row_px;
  }

  // Start: eq. (1) is linear in (b, cot beta) for delta = 0:
  // n_v tan(tau) = b / D - cot(beta).
  Eigen::MatrixXd a(problem.rows.size(), 2);
  Eigen::VectorXd y(problem.rows.size());
  for (Eigen::Index k = 0; k < problem.rows.size(); ++k) {
    a(k, 0) = 1.0 / problem.distances[k];
    a(k, 1) = -1.0;
    y[k] = (1.0 - problem.rows[k] / problem.half_height) * problem.tan_tau;
  }
  const Eigen::Vector2d linear = a.colPivHouseholderQr().solve(y);
  Eigen::VectorXd x(parameters);
  const bool usable = linear.allFinite() && linear[0] > 0.0 && linear[1] > 0.0;
  x[0] = usable ? linear[0] : camera.baseline_m;
  x[1] = usable ? std::atan(1.0 / linear[1]) : camera.sheet_angle_rad;
  if (parameters == 3) x[2] = 0.0;

  Eigen::LevenbergMarquardt<TargetRows> solver(problem);
  solver.parameters.maxfev = options.max_iterations;
  solver.parameters.xtol = 1e-14;
  solver.parameters.ftol = 1e-14;
  solver.minimize(x);
  result.iterations = static_cast<int>(solver.iter);
  if (!x.allFinite() || !(x[0] > 0.0) || !(x[1] > 0.0 && x[1] < kRightAngle_rad)) {
    throw InputError("structured light calibration: the fit left the valid range (b = " + std::to_string(x[0]) +
                     " m, beta = " + std::to_string(x[1] * 180.0 / std::numbers::pi) +
                     " deg); check the distances and that each image shows the target's stripe");
  }
  result.baseline_m = x[0];
  result.sheet_angle_rad = x[1];
  result.distance_offset_m = parameters == 3 ? x[2] : 0.0;

  Eigen::VectorXd residuals(problem.rows.size());
  problem(x, residuals);
  Eigen::MatrixXd jacobian(problem.rows.size(), parameters);
  problem.df(x, jacobian);
  result.degrees_of_freedom = static_cast<int>(problem.rows.size()) - parameters;
  const double rss = residuals.squaredNorm();
  result.rms_residual_px = std::sqrt(rss / static_cast<double>(problem.rows.size()));
  result.residual_sigma_px = std::sqrt(rss / result.degrees_of_freedom);
  result.covariance = (jacobian.transpose() * jacobian).inverse() * (rss / result.degrees_of_freedom);
  result.baseline_sigma_m = std::sqrt(result.covariance(0, 0));
  result.sheet_angle_sigma_rad = std::sqrt(result.covariance(1, 1));
  if (parameters == 3) result.distance_offset_sigma_m = std::sqrt(result.covariance(2, 2));
  const double denominator = result.baseline_sigma_m * result.sheet_angle_sigma_rad;
  result.baseline_sheet_angle_correlation = denominator > 0.0 ? result.covariance(0, 1) / denominator : 0.0;
  for (std::size_t k = 0; k < result.targets.size(); ++k) {
    CalibrationTargetFit& fit = result.targets[k];
    fit.residual_px = residuals[static_cast<Eigen::Index>(k)];
    fit.fitted_row_px = fit.observed_row_px - fit.residual_px;
  }
  return result;
}

}  // namespace stridemap
