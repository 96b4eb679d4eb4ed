#include "stridemap/sensors/structured_light_report.hpp"

#include <cmath>
#include <cstdio>
#include <string>

#include "stridemap/core/error.hpp"
#include "stridemap/core/sensor_transform.hpp"

namespace stridemap {
namespace {

constexpr double kDegreesPerRadian = 180.0 / std::numbers::pi;
constexpr double kDegToRadian = std::numbers::pi / 180.0;
// The pitch search stays within core's mount limit (|tilt| < 90 deg).
constexpr double kMaxTotalTilt_rad = 89.9 * kDegToRadian;
constexpr double kPitchSearchStep_rad = 0.1 * kDegToRadian;

std::string text(const char* format, double a, double b = 0.0, double c = 0.0) {
  char buffer[256];
  std::snprintf(buffer, sizeof buffer, format, a, b, c);
  return buffer;
}

SheetRowView row_view(const StructuredLightModel& model, double row_px, double depth_m) {
  const StructuredLightParameters& p = model.parameters();
  SheetRowView view;
  view.row_px = row_px;
  view.depth_m = depth_m;
  view.vertical_m = depth_m * model.cot_sheet_angle() - p.baseline_m;
  view.lateral_field_m = 2.0 * depth_m * model.tan_half_fov_horizontal();
  // |dz/dv| = 2 b tan(tau) / (R_ver D^2) with D = b / z.
  view.depth_per_row_m_per_px =
      2.0 * model.tan_half_fov_vertical() * depth_m * depth_m / (p.image_height_px * p.baseline_m);
  return view;
}

// A camera-frame point on the level trunk, relative to the camera.
Eigen::Vector3d level_trunk_offset(const StructuredLightModel& model, const Eigen::Vector3d& camera_point) {
  return tilt_rotation(0.0, 0.0, model.parameters().mount) * camera_to_sensor_frame(camera_point);
}

MountedSheetEnd mounted_end(const StructuredLightModel& model, const SheetRowView& view) {
  const Eigen::Vector3d offset = level_trunk_offset(model, {0.0, view.vertical_m, view.depth_m});
  return {view.row_px, offset.x(), model.parameters().mount.height_m + offset.z(), view.lateral_field_m};
}

bool stripe_in_view(const StructuredLightModel& model, double total_tilt_rad) {
  const auto location = ground_stripe_location(model, total_tilt_rad);
  return location && location->row_px >= 0.0 && location->row_px <= model.parameters().image_height_px;
}

// The trunk pitch, searched from 0 in the direction `sign`, at which the
// flat-ground stripe leaves the image (or the search limit, flagged).
double pitch_limit(const StructuredLightModel& model, double sign, bool& at_search_limit) {
  const double alpha = model.parameters().mount.pitch_rad;
  const double limit = sign * kMaxTotalTilt_rad - alpha;
  double inside = 0.0;
  at_search_limit = false;
  for (;;) {
    double next = inside + sign * kPitchSearchStep_rad;
    if (sign * next >= sign * limit) {
      if (stripe_in_view(model, alpha + limit)) {
        at_search_limit = true;
        return limit;
      }
      next = limit;
    }
    if (!stripe_in_view(model, alpha + next)) {
      double outside = next;
      for (int i = 0; i < 60; ++i) {
        const double middle = 0.5 * (inside + outside);
        (stripe_in_view(model, alpha + middle) ? inside : outside) = middle;
      }
      return inside;
    }
    inside = next;
  }
}

}  // namespace

SheetInView sheet_in_view(const StructuredLightModel& model) {
  const StructuredLightParameters& p = model.parameters();
  SheetInView view;
  view.axis_crossing_depth_m = p.baseline_m / model.cot_sheet_angle();
  view.vanishing_row_px = model.vanishing_row_px();
  // The top row always sees the sheet: its ray climbs and the sheet descends.
  view.top_row = row_view(model, 0.0, *model.sheet_depth_at_row_m(0.0));
  const double bottom = p.image_height_px;
  if (const auto depth = model.sheet_depth_at_row_m(bottom)) view.bottom_row = row_view(model, bottom, *depth);
  return view;
}

std::optional<GroundStripeLocation> ground_stripe_location(const StructuredLightModel& model, double total_tilt_rad) {
  // Level trunk tilted by a: a sheet point (y, z) is at height
  // -sin(a) z - cos(a) y relative to the camera; with y = z cot(beta) - b
  // the ground (-h) is met at z = (h + b cos a) / (sin a + cot(beta) cos a).
  const StructuredLightParameters& p = model.parameters();
  const double s = std::sin(total_tilt_rad), c = std::cos(total_tilt_rad);
  const double numerator = p.mount.height_m + p.baseline_m * c;
  const double denominator = s + model.cot_sheet_angle() * c;
  if (!(numerator > 0.0) || !(denominator > 0.0)) return std::nullopt;
  const double depth = numerator / denominator;
  return GroundStripeLocation{depth, model.row_at_sheet_depth_px(depth)};
}

GroundStripeReport ground_stripe_report(const StructuredLightModel& model, const UpdateOptions& options) {
  const StructuredLightParameters& p = model.parameters();
  const double alpha = p.mount.pitch_rad;
  const double rows = p.image_height_px;
  const std::string cannot = "structured light mount: this geometry cannot see the ground: ";
  const auto location = ground_stripe_location(model, alpha);
  if (!location) {
    throw InputError(cannot + text("the laser sheet does not descend ahead of the camera (it lies %.2f deg below the "
                                   "horizontal: alpha + 90 deg - beta); tilt the sensor further down (larger "
                                   "mount pitch alpha) or make the sheet steeper (smaller beta)",
                                   (alpha + std::numbers::pi / 2 - p.sheet_angle_rad) * kDegreesPerRadian));
  }
  if (location->row_px > rows) {
    throw InputError(cannot + text("the laser stripe on flat ground lies %.3f m ahead of the camera (z_c) but would "
                                   "be seen at image row %.1f, below the image (rows 0 to %.0f); tilt the sensor "
                                   "further down (larger alpha) or make the sheet shallower (larger beta)",
                                   location->depth_m, location->row_px, rows));
  }
  if (location->row_px < 0.0) {
    throw InputError(cannot + text("the laser stripe on flat ground lies %.3f m ahead of the camera (z_c) but would "
                                   "be seen at image row %.1f, above the image (rows 0 to %.0f); tilt the sensor "
                                   "less (smaller alpha) or make the sheet steeper (smaller beta)",
                                   location->depth_m, location->row_px, rows));
  }

  GroundStripeReport report;
  report.stripe_row_px = location->row_px;
  report.stripe_depth_m = location->depth_m;

  CameraPointPartials centre;
  model.back_project(0.5 * p.image_width_px, location->row_px, centre);
  const Eigen::Vector3d centre_offset = level_trunk_offset(model, centre.point);
  report.nearest_distance_m = centre_offset.x();
  report.nearest_slant_range_m = centre.point.norm();

  Eigen::Vector3d edge;
  model.back_project(0.0, location->row_px, edge);
  const Eigen::Vector3d edge_offset = level_trunk_offset(model, edge);
  report.stripe_width_m = 2.0 * edge.x();
  report.farthest_distance_m = std::hypot(edge_offset.x(), edge_offset.y());
  report.farthest_slant_range_m = edge.norm();

  const StructuredLightElevationPartials partials = structured_light_elevation_partials(centre, 0.0, 0.0, alpha);
  report.centre_partials = partials;
  report.elevation_per_row_m_per_px = std::abs(partials.d_row_m_per_px);
  StructuredLightElevationPartials sensor_only = partials;
  sensor_only.d_pitch_m_per_rad = sensor_only.d_roll_m_per_rad = sensor_only.d_alpha_m_per_rad = 0.0;
  report.sensor_error_bound_m = structured_light_elevation_error_bound_m(sensor_only, p, options);
  report.pose_error_bound_m = std::abs(partials.d_pitch_m_per_rad) * options.max_pitch_error_rad +
                              std::abs(partials.d_roll_m_per_rad) * options.max_roll_error_rad +
                              std::abs(partials.d_alpha_m_per_rad) * options.max_mount_pitch_error_rad;

  // A row's ray descends when n_v tan(tau) < tan(alpha) (camera frame, level trunk).
  report.horizon_row_px = 0.5 * rows * (1.0 - std::tan(alpha) / model.tan_half_fov_vertical());

  const SheetInView view = sheet_in_view(model);
  report.near_end = mounted_end(model, view.top_row);
  if (view.bottom_row) report.far_end = mounted_end(model, *view.bottom_row);

  report.min_trunk_pitch_rad = pitch_limit(model, -1.0, report.min_pitch_is_search_limit);
  report.max_trunk_pitch_rad = pitch_limit(model, +1.0, report.max_pitch_is_search_limit);
  return report;
}

}  // namespace stridemap
