#pragma once
// Spatial uncertainty of structured-light points (paper section 3.2,
// Fig. 3): how far a measured point can be off along x_c and z_c, as a
// function of where it lies in the x_c-z_c plane of the camera.
//
// The uncertainty is the worst-case first-order propagation of the pixel
// errors: Delta x_c = |dx_c/du| Delta u + |dx_c/dv| Delta v and Delta z_c =
// |dz_c/dv| Delta v, with Delta u = column_error_px and Delta v =
// row_error_px of the parameters (0.5 px: a whole-pixel detector). Fig. 3
// is about resolution, so the calibration errors (Delta b, Delta beta,
// Delta tau_c) are left out unless asked for.
#include <optional>

#include <Eigen/Core>

#include "stridemap/sensors/structured_light.hpp"

namespace stridemap {

/// Worst-case errors of one point along the camera axes [m].
struct PointUncertainty {
  double x_m = 0.0;
  double y_m = 0.0;
  double z_m = 0.0;
};

/// The uncertainty of the point measured at pixel (u, v), or nothing when
/// that pixel has no point (see StripePointStatus). With
/// `include_parameter_errors` the terms |d/db| Delta b + |d/dbeta|
/// Delta beta + |d/dtau_c| Delta tau_c are added.
std::optional<PointUncertainty> pixel_point_uncertainty(const StructuredLightModel& model, double u_px, double v_px,
                                                        bool include_parameter_errors = false);

struct UncertaintyMapOptions {
  /// Side of one grid cell in the x_c-z_c plane [m].
  double cell_size_m = 0.005;
  /// The grid covers depths z_c from 0 to this [m].
  double max_depth_m = 1.0;
  /// Half the lateral extent (x_c from -this to +this) [m]; 0 takes
  /// max_depth_m tan(gamma_c), the view's width at the largest depth.
  double half_width_m = 0.0;
  /// Add the calibration errors to the pixel errors (not in Fig. 3).
  bool include_parameter_errors = false;
};

/// Fig. 3's two maps. Cell (i, j) is the sheet point at depth
/// z_c = first_depth_m + i * cell_size_m and lateral position
/// x_c = first_lateral_m + j * cell_size_m (x_c positive to the left, so j
/// grows to the left as in io::render_grid's +Y). NaN where the camera does
/// not see the sheet at that place.
struct UncertaintyMaps {
  Eigen::MatrixXf x_uncertainty_m;
  Eigen::MatrixXf z_uncertainty_m;
  double cell_size_m = 0.0;
  double first_depth_m = 0.0;
  double first_lateral_m = 0.0;
};

/// Throws InputError naming the option for a non-positive or non-finite
/// size, or a grid over 4000 cells on a side.
UncertaintyMaps structured_light_uncertainty_maps(const StructuredLightModel& model,
                                                  const UncertaintyMapOptions& options = {});

}  // namespace stridemap
