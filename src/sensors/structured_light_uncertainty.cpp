#include "stridemap/sensors/structured_light_uncertainty.hpp"

#include <cmath>
#include <cstdio>
#include <limits>
#include <string>

#include "stridemap/core/error.hpp"

namespace stridemap {
namespace {

constexpr double kMaxCellsPerSide = 4000.0;

void require_positive(double value, const char* name) {
  if (std::isfinite(value) && value > 0.0) return;
  char text[160];
  std::snprintf(text, sizeof text, "uncertainty map options: %s must be a positive number of metres, got %g", name,
                value);
  throw InputError(text);
}

int cell_count(double extent_m, double cell_size_m, const char* name) {
  const double cells = std::ceil(extent_m / cell_size_m - 1e-9);
  if (cells > kMaxCellsPerSide) {
    char text[200];
    std::snprintf(text, sizeof text,
                  "uncertainty map options: %s / cell_size_m gives %.0f cells on a side, more than %.0f; use larger "
                  "cells or a smaller area",
                  name, cells, kMaxCellsPerSide);
    throw InputError(text);
  }
  return static_cast<int>(cells < 1.0 ? 1.0 : cells);
}

}  // namespace

std::optional<PointUncertainty> pixel_point_uncertainty(const StructuredLightModel& model, double u_px, double v_px,
                                                        bool include_parameter_errors) {
  CameraPointPartials d;
  if (model.back_project(u_px, v_px, d) != StripePointStatus::valid) return std::nullopt;
  const StructuredLightParameters& p = model.parameters();
  Eigen::Vector3d bound = d.d_column.cwiseAbs() * p.column_error_px + d.d_row.cwiseAbs() * p.row_error_px;
  if (include_parameter_errors) {
    bound += d.d_baseline.cwiseAbs() * p.baseline_error_m + d.d_sheet_angle.cwiseAbs() * p.sheet_angle_error_rad +
             d.d_half_fov_vertical.cwiseAbs() * p.half_fov_vertical_error_rad;
  }
  return PointUncertainty{bound.x(), bound.y(), bound.z()};
}

UncertaintyMaps structured_light_uncertainty_maps(const StructuredLightModel& model,
                                                  const UncertaintyMapOptions& options) {
  require_positive(options.cell_size_m, "cell_size_m");
  require_positive(options.max_depth_m, "max_depth_m");
  if (!std::isfinite(options.half_width_m) || options.half_width_m < 0.0) {
    char text[160];
    std::snprintf(text, sizeof text, "uncertainty map options: half_width_m must be a number >= 0, got %g",
                  options.half_width_m);
    throw InputError(text);
  }
  const double half_width =
      options.half_width_m > 0.0 ? options.half_width_m : options.max_depth_m * model.tan_half_fov_horizontal();
  const double cell = options.cell_size_m;
  const int depth_cells = cell_count(options.max_depth_m, cell, "max_depth_m");
  const int half_columns = cell_count(half_width, cell, "half_width_m");

  UncertaintyMaps maps;
  maps.cell_size_m = cell;
  maps.first_depth_m = 0.5 * cell;
  maps.first_lateral_m = (0.5 - half_columns) * cell;
  const float nan = std::numeric_limits<float>::quiet_NaN();
  maps.x_uncertainty_m = Eigen::MatrixXf::Constant(depth_cells, 2 * half_columns, nan);
  maps.z_uncertainty_m = Eigen::MatrixXf::Constant(depth_cells, 2 * half_columns, nan);

  const double cot_beta = model.cot_sheet_angle();
  const double baseline = model.parameters().baseline_m;
  for (int i = 0; i < depth_cells; ++i) {
    const double depth = maps.first_depth_m + i * cell;
    for (int j = 0; j < 2 * half_columns; ++j) {
      // The sheet fixes y_c for a depth; the point's pixel then tells whether
      // the camera sees it and gives the derivatives there.
      const Eigen::Vector3d point(maps.first_lateral_m + j * cell, depth * cot_beta - baseline, depth);
      const auto pixel = model.project(point);
      if (!pixel || !model.in_image(pixel->x(), pixel->y())) continue;
      const auto bound = pixel_point_uncertainty(model, pixel->x(), pixel->y(), options.include_parameter_errors);
      if (!bound) continue;
      maps.x_uncertainty_m(i, j) = static_cast<float>(bound->x_m);
      maps.z_uncertainty_m(i, j) = static_cast<float>(bound->z_m);
    }
  }
  return maps;
}

}  // namespace stridemap
