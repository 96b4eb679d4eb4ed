#pragma once
// What a structured-light configuration can measure (paper section 3.3):
// where the laser sheet lies in the image, where its stripe falls on flat
// ground, how wide it is there, which image rows see the ground, and how
// much trunk pitch the configuration tolerates before the stripe leaves the
// image. docs/structured_light.md shows the Ragno numbers.
//
// Distances on the ground are horizontal and measured from the point on the
// ground under the camera's optical centre; the trunk is level (pitch and
// roll zero, the neutral posture) unless stated.
#include <optional>

#include "stridemap/core/map_update.hpp"
#include "stridemap/sensors/structured_light.hpp"
#include "stridemap/sensors/structured_light_mapping.hpp"

namespace stridemap {

/// One image row's view of the sheet, in the camera frame.
struct SheetRowView {
  double row_px = 0.0;                 ///< v
  double depth_m = 0.0;                ///< z_c
  double vertical_m = 0.0;             ///< y_c (positive below the optical axis)
  double lateral_field_m = 0.0;        ///< width of the view at that depth, 2 z_c tan(gamma_c)
  double depth_per_row_m_per_px = 0.0; ///< |dz_c / dv|: the depth resolution there
};

/// The part of the sheet the camera sees; needs no mount.
struct SheetInView {
  /// z_c where the sheet crosses the optical axis (row R_ver / 2): b tan(beta).
  double axis_crossing_depth_m = 0.0;
  SheetRowView top_row;  ///< v = 0: the sheet's nearest visible point
  /// v = R_ver: the farthest visible point; nothing when the sheet recedes to
  /// infinity inside the image (then see vanishing_row_px).
  std::optional<SheetRowView> bottom_row;
  /// Row where eq. (1)'s denominator is zero; rows below it see no sheet.
  double vanishing_row_px = 0.0;
};

SheetInView sheet_in_view(const StructuredLightModel& model);

/// An end of the visible sheet placed in the trunk's frame.
struct MountedSheetEnd {
  double row_px = 0.0;
  double forward_m = 0.0;               ///< horizontal distance ahead of the camera's foot point
  double height_above_ground_m = 0.0;   ///< negative: below the ground plane
  double lateral_field_m = 0.0;         ///< width of the view there
};

/// The flat-ground view of a mounted sensor.
struct GroundStripeReport {
  /// Image row of the stripe on flat ground: with a level trunk the stripe is
  /// a horizontal line across the whole image width.
  double stripe_row_px = 0.0;
  double stripe_depth_m = 0.0;  ///< z_c of the stripe
  /// Nearest measured ground point: the stripe's centre, straight ahead.
  double nearest_distance_m = 0.0;
  double nearest_slant_range_m = 0.0;  ///< from the optical centre
  /// Length of the stripe on the ground, from image edge to image edge.
  double stripe_width_m = 0.0;
  /// Farthest measured ground point: either end of the stripe.
  double farthest_distance_m = 0.0;
  double farthest_slant_range_m = 0.0;
  /// |dz_m / dv| at the stripe's centre: elevation per image row [m/px].
  double elevation_per_row_m_per_px = 0.0;
  /// Elevation partials at the stripe's centre (the terms of eq. 8).
  StructuredLightElevationPartials centre_partials;
  /// Eq. (8)'s calibration and pixel terms (b, beta, tau_c, v) at the centre.
  double sensor_error_bound_m = 0.0;
  /// Eq. (8)'s pose terms (trunk pitch, roll, alpha) at the centre, with the
  /// bounds of the UpdateOptions given.
  double pose_error_bound_m = 0.0;
  /// Rows below this one look down at the ground (camera rays, with or
  /// without the laser); it lies above the image (< 0) when every row does.
  double horizon_row_px = 0.0;
  /// The sheet's visible ends on the trunk: the top row sees the tallest
  /// obstacle the sensor can measure, the bottom row the deepest hole.
  MountedSheetEnd near_end;
  std::optional<MountedSheetEnd> far_end;  ///< nothing when the sheet vanishes inside the image
  /// Trunk pitch range (positive nose down) over which the flat-ground
  /// stripe stays in the image, with the camera height unchanged; searched
  /// within total tilts of +-89.9 deg.
  double min_trunk_pitch_rad = 0.0;
  double max_trunk_pitch_rad = 0.0;
  /// The stripe was still in view where the search stopped (total tilt
  /// -89.9 or +89.9 deg): the range extends at least that far.
  bool min_pitch_is_search_limit = false;
  bool max_pitch_is_search_limit = false;
};

/// Throws InputError "structured light mount: this geometry cannot see the
/// ground: ..." when the sheet does not descend ahead of the camera or its
/// flat-ground stripe lies outside the image, with what to change.
GroundStripeReport ground_stripe_report(const StructuredLightModel& model, const UpdateOptions& options = {});

/// Depth z_c and row of the flat-ground stripe for a total tilt (alpha +
/// trunk pitch, no roll), or nothing when the sheet does not meet the
/// ground ahead of the camera. The row may lie outside the image.
struct GroundStripeLocation {
  double depth_m = 0.0;
  double row_px = 0.0;
};
std::optional<GroundStripeLocation> ground_stripe_location(const StructuredLightModel& model, double total_tilt_rad);

}  // namespace stridemap
