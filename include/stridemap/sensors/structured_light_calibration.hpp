#pragma once
// Calibration of the camera-emitter pair (paper section 3.2, ref. [14]: a
// two-stage procedure): the camera's intrinsics (tau_c, gamma_c or the focal
// length, image size) come from an ordinary camera calibration and the
// configuration; this is the second stage, b and beta from images of a flat
// target standing across the optical axis at known distances.
//
// On such a target z_c is the distance D, so eq. (1) gives the stripe's row
//
//   v(D) = R_ver / 2 * (1 - (b / (D + delta) - cot(beta)) / tan(tau_c)),
//
// the same in every column. delta is an optional offset of the distance
// scale (a ruler read from the housing instead of the optical centre); it is
// fitted only on request. Each target contributes one observation, the mean
// row of its stripe (after dropping rows more than 3 px from its median), so
// that the residual variance and the covariance describe errors between
// targets, not the pixel scatter along one stripe (which is reported too).
//
// Non-linear least squares in (b, beta[, delta]) by Eigen's
// Levenberg-Marquardt with the analytic Jacobian, started from the linear
// solution in (b, cot beta); covariance s^2 (J^T J)^-1 with
// s^2 = RSS / (targets - parameters).
#include <cstddef>
#include <span>
#include <string>
#include <vector>

#include <Eigen/Core>

#include "stridemap/sensors/structured_light.hpp"
#include "stridemap/sensors/structured_light_mapping.hpp"

namespace stridemap {

/// One image of the target: its distance along the optical axis and the
/// stripe detected in it.
struct CalibrationTargetImage {
  std::string name;          ///< for messages and the report (e.g. the file)
  double distance_m = 0.0;   ///< D, from the optical centre (or the ruler's zero, see delta)
  std::vector<StripePixel> stripe;
};

struct StructuredLightCalibrationOptions {
  /// Also fit delta, the offset added to every distance [m].
  bool fit_distance_offset = false;
  /// Rows farther than this from the median row of a target are outliers [px].
  double outlier_distance_px = 3.0;
  int max_iterations = 200;
};

struct CalibrationTargetFit {
  std::string name;
  double distance_m = 0.0;
  std::size_t points = 0;           ///< stripe pixels used
  std::size_t outliers = 0;         ///< dropped
  double observed_row_px = 0.0;     ///< mean row of the stripe
  double fitted_row_px = 0.0;       ///< v(D) with the fitted parameters
  double residual_px = 0.0;         ///< observed - fitted
  double scatter_px = 0.0;          ///< RMS of the rows about their mean
};

struct StructuredLightCalibration {
  double baseline_m = 0.0;
  double sheet_angle_rad = 0.0;
  double distance_offset_m = 0.0;   ///< 0 unless fitted
  /// Covariance of (b [m], beta [rad][, delta [m]]).
  Eigen::MatrixXd covariance;
  double baseline_sigma_m = 0.0;
  double sheet_angle_sigma_rad = 0.0;
  double distance_offset_sigma_m = 0.0;
  double baseline_sheet_angle_correlation = 0.0;
  double rms_residual_px = 0.0;     ///< over the targets
  double residual_sigma_px = 0.0;   ///< s = sqrt(RSS / degrees_of_freedom)
  int degrees_of_freedom = 0;
  int iterations = 0;
  std::vector<CalibrationTargetFit> targets;
};

/// Fits b and beta (and delta) keeping the intrinsics of `camera` (tau_c,
/// R_ver); its b and beta are the fallback start when the linear solution is
/// unusable. Throws InputError naming the target or the problem: fewer
/// targets than parameters + 1, a non-finite or non-positive distance, two
/// targets at the same distance, a target without stripe pixels or with
/// non-finite ones, or a fit that leaves the valid range (b <= 0, beta
/// outside (0, 90) deg).
StructuredLightCalibration calibrate_baseline_and_sheet_angle(const StructuredLightParameters& camera,
                                                              std::span<const CalibrationTargetImage> targets,
                                                              const StructuredLightCalibrationOptions& options = {});

/// v(D) of the header comment.
double target_stripe_row_px(const StructuredLightParameters& camera, double baseline_m, double sheet_angle_rad,
                            double distance_m);

}  // namespace stridemap
