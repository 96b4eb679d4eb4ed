#pragma once
// Structured-light points in the map frame: the transform of eq. (5) applied
// to eq. (1)'s points, the elevation partials and Delta z_max of eq. (8), and
// one frame's stripe turned into MapPoints for
// TerrainMapper::integrate_points.
//
// Eq. (8) as printed lists the term in b twice; here each parameter's term
// appears once. Its d tan(gamma) term uses the inclination of the laser
// sheet (90 deg - beta steeper than the camera's optical axis), not that of
// the camera: it is the sheet whose trace climbs a vertical face as the
// robot moves (docs/structured_light.md).
#include <cstddef>
#include <span>
#include <vector>

#include "stridemap/core/map_update.hpp"
#include "stridemap/core/pose.hpp"
#include "stridemap/core/sensor_point.hpp"
#include "stridemap/core/terrain_mapper.hpp"
#include "stridemap/sensors/structured_light.hpp"

namespace stridemap {

/// Elevation of a stripe point and its partial derivatives (the terms of
/// eq. 8 before they are multiplied by the error bounds).
struct StructuredLightElevationPartials {
  /// z_m of the point relative to the camera's optical centre, in the map
  /// frame (elevation = sensor origin height + z_m) [m].
  double z_m = 0.0;
  double d_baseline = 0.0;                       ///< dz_m/db [m/m]
  double d_sheet_angle_m_per_rad = 0.0;          ///< dz_m/dbeta
  double d_half_fov_vertical_m_per_rad = 0.0;    ///< dz_m/dtau_c
  double d_row_m_per_px = 0.0;                   ///< dz_m/dv
  double d_pitch_m_per_rad = 0.0;                ///< dz_m/dphi_r (trunk pitch)
  double d_roll_m_per_rad = 0.0;                 ///< dz_m/dpsi_r (trunk roll)
  double d_alpha_m_per_rad = 0.0;                ///< dz_m/dalpha (mount pitch)
};

/// The partials of z_m = third row of T * camera_to_sensor_frame(p), with
/// T = Ry(pitch) Rx(roll) Ry(alpha) as in core/sensor_transform.hpp.
StructuredLightElevationPartials structured_light_elevation_partials(const CameraPointPartials& point,
                                                                     double pitch_rad, double roll_rad,
                                                                     double alpha_rad);
/// The same for the full mount (its roll and yaw held, alpha = mount.pitch_rad).
StructuredLightElevationPartials structured_light_elevation_partials(const CameraPointPartials& point,
                                                                     double pitch_rad, double roll_rad,
                                                                     const SensorMount& mount);

/// gamma for eq. (8): the tilt towards +X of the laser sheet's normal in the
/// map frame, atan2(n_x, n_z). With no roll it is pitch + alpha + 90 deg -
/// beta; for beta = 90 deg it equals core's scan_plane_inclination_rad.
double sheet_inclination_rad(double sheet_angle_rad, double pitch_rad, double roll_rad, double alpha_rad);
/// The same for the full mount (T with the mount's roll and yaw).
double sheet_inclination_rad(double sheet_angle_rad, double pitch_rad, double roll_rad, const SensorMount& mount);

/// The error part of eq. (8), each term once and as a magnitude:
/// |dz/db| Db + |dz/dbeta| Dbeta + |dz/dtau| Dtau + |dz/dv| Dv (bounds from
/// `parameters`) + |dz/dpsi| Dpsi + |dz/dphi| Dphi + |dz/dalpha| Dalpha
/// (bounds from `options`).
double structured_light_elevation_error_bound_m(const StructuredLightElevationPartials& partials,
                                                const StructuredLightParameters& parameters,
                                                const UpdateOptions& options);

/// Eq. (8): |d tan(gamma)| + the error part above. `travel_m` is
/// d_(k,k+1), including any turning travel of Fig. 10.
double structured_light_max_elevation_change(const StructuredLightElevationPartials& partials,
                                             const StructuredLightParameters& parameters, double travel_m,
                                             double gamma_rad, const UpdateOptions& options);

/// One detected stripe position: column u and sub-pixel row v (see the
/// conventions in structured_light.hpp).
struct StripePixel {
  double u_px = 0.0;
  double v_px = 0.0;
};

/// What happened to one frame's stripe pixels.
struct StripeConversionStats {
  std::size_t pixels = 0;
  std::size_t converted = 0;        ///< became a MapPoint
  std::size_t not_finite = 0;       ///< u or v NaN / infinite, or the point too far to represent
  std::size_t outside_image = 0;    ///< u or v outside the image
  std::size_t no_intersection = 0;  ///< the ray does not meet the sheet in front of the camera
  bool pose_rejected = false;       ///< a pose field was not finite: no point was produced

  /// Counts add up; pose_rejected is set when either side has it.
  StripeConversionStats& operator+=(const StripeConversionStats& other) {
    pixels += other.pixels;
    converted += other.converted;
    not_finite += other.not_finite;
    outside_image += other.outside_image;
    no_intersection += other.no_intersection;
    pose_rejected = pose_rejected || other.pose_rejected;
    return *this;
  }
};

/// The structured-light error model: one frame's stripe as points relative
/// to the sensor origin (map axes) with the error part of eq. (8) as their
/// height error and the sheet's inclination as the batch's gamma, for
/// TerrainMapper::integrate_scan (which adds the motion terms). `mount`
/// places the camera (the mapper's mount). `batch` is refilled; it
/// allocates only while it grows. A non-finite pose gives no points.
StripeConversionStats stripe_to_sensor_points(const StructuredLightModel& model, std::span<const StripePixel> pixels,
                                              const TrunkPose& pose, const SensorMount& mount,
                                              const UpdateOptions& options, PointBatch& batch);

/// Turns one frame's stripe into map-frame points with their Delta z_max
/// (eq. 8), for TerrainMapper::integrate_points(points, pose). The mount is
/// model.parameters().mount; build the TerrainMapper with the same mount and
/// take `motion` from its motion_to(pose), so that d_(k,k+1) and the turning
/// term (Fig. 10, when options.use_turning_term) match the laser path.
/// `points` is cleared and refilled; it allocates only while it grows.
/// Pixels without a point are counted, never passed on as NaN.
StripeConversionStats stripe_to_map_points(const StructuredLightModel& model, std::span<const StripePixel> pixels,
                                           const TrunkPose& pose, const ScanMotion& motion,
                                           const UpdateOptions& options, std::vector<MapPoint>& points);

}  // namespace stridemap
