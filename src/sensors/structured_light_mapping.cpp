#include "stridemap/sensors/structured_light_mapping.hpp"

#include <cmath>

#include <Eigen/Geometry>

#include "stridemap/core/max_elevation_change.hpp"
#include "stridemap/core/sensor_transform.hpp"

namespace stridemap {
namespace {

// Stands in for "any change is plausible" (a yaw jump beyond a quarter turn
// between frames makes Fig. 10's term infinite). Finite, so that
// integrate_points does not count the point as invalid, and far beyond any
// elevation a map holds.
constexpr double kUnboundedElevationChange_m = 1.0e6;

StructuredLightElevationPartials partials_from_rows(const CameraPointPartials& p, const ElevationRows& rows) {
  const Eigen::Vector3d s = camera_to_sensor_frame(p.point);
  StructuredLightElevationPartials out;
  out.z_m = rows.row * s;
  out.d_baseline = rows.row * camera_to_sensor_frame(p.d_baseline);
  out.d_sheet_angle_m_per_rad = rows.row * camera_to_sensor_frame(p.d_sheet_angle);
  out.d_half_fov_vertical_m_per_rad = rows.row * camera_to_sensor_frame(p.d_half_fov_vertical);
  out.d_row_m_per_px = rows.row * camera_to_sensor_frame(p.d_row);
  out.d_pitch_m_per_rad = rows.d_pitch * s;
  out.d_roll_m_per_rad = rows.d_roll * s;
  out.d_alpha_m_per_rad = rows.d_alpha * s;
  return out;
}

bool motion_is_finite(const ScanMotion& motion) {
  return std::isfinite(motion.horizontal_travel_m) && std::isfinite(motion.yaw_change_rad);
}

}  // namespace

StructuredLightElevationPartials structured_light_elevation_partials(const CameraPointPartials& point,
                                                                     double pitch_rad, double roll_rad,
                                                                     double alpha_rad) {
  SensorMount mount;
  mount.pitch_rad = alpha_rad;
  return structured_light_elevation_partials(point, pitch_rad, roll_rad, mount);
}

StructuredLightElevationPartials structured_light_elevation_partials(const CameraPointPartials& point,
                                                                     double pitch_rad, double roll_rad,
                                                                     const SensorMount& mount) {
  return partials_from_rows(point, elevation_rows(pitch_rad, roll_rad, mount));
}

double sheet_inclination_rad(double sheet_angle_rad, double pitch_rad, double roll_rad, double alpha_rad) {
  SensorMount mount;
  mount.pitch_rad = alpha_rad;
  return sheet_inclination_rad(sheet_angle_rad, pitch_rad, roll_rad, mount);
}

double sheet_inclination_rad(double sheet_angle_rad, double pitch_rad, double roll_rad, const SensorMount& mount) {
  // The sheet y_c = z_c cot(beta) - b has the camera-frame normal
  // (0, sin beta, -cos beta), which is (cos beta, 0, sin beta) in the sensor
  // frame after flipping it to point up.
  const Eigen::Vector3d normal_in_sensor(std::cos(sheet_angle_rad), 0.0, std::sin(sheet_angle_rad));
  const Eigen::Vector3d normal = tilt_rotation(pitch_rad, roll_rad, mount) * normal_in_sensor;
  return std::atan2(normal.x(), normal.z());
}

double structured_light_elevation_error_bound_m(const StructuredLightElevationPartials& p,
                                                const StructuredLightParameters& parameters,
                                                const UpdateOptions& options) {
  return std::abs(p.d_baseline) * parameters.baseline_error_m +
         std::abs(p.d_sheet_angle_m_per_rad) * parameters.sheet_angle_error_rad +
         std::abs(p.d_half_fov_vertical_m_per_rad) * parameters.half_fov_vertical_error_rad +
         std::abs(p.d_row_m_per_px) * parameters.row_error_px +
         std::abs(p.d_roll_m_per_rad) * options.max_roll_error_rad +
         std::abs(p.d_pitch_m_per_rad) * options.max_pitch_error_rad +
         std::abs(p.d_alpha_m_per_rad) * options.max_mount_pitch_error_rad;
}

double structured_light_max_elevation_change(const StructuredLightElevationPartials& partials,
                                             const StructuredLightParameters& parameters, double travel_m,
                                             double gamma_rad, const UpdateOptions& options) {
  return std::abs(travel_m * std::tan(gamma_rad)) +
         structured_light_elevation_error_bound_m(partials, parameters, options);
}

namespace {

// The per-pixel part both outputs share: back-projection, the offset from
// the sensor origin and the error part of eq. (8); `emit` takes each point.
template <class Emit>
StripeConversionStats for_each_stripe_point(const StructuredLightModel& model, std::span<const StripePixel> pixels,
                                            const TrunkPose& pose, const SensorMount& mount,
                                            const UpdateOptions& options, Emit&& emit) {
  StripeConversionStats stats;
  stats.pixels = pixels.size();
  if (!pose_is_finite(pose)) {
    stats.pose_rejected = true;
    return stats;
  }
  const StructuredLightParameters& parameters = model.parameters();
  const Eigen::Matrix3d rotation = sensor_to_map_rotation(pose, mount);
  const ElevationRows rows = elevation_rows(pose.pitch_rad, pose.roll_rad, mount);
  const ElevationPartials lever = sensor_origin_elevation_partials(pose, mount);  // zero without pose z
  CameraPointPartials camera;
  SensorPoint point;
  for (const StripePixel& pixel : pixels) {
    switch (model.back_project(pixel.u_px, pixel.v_px, camera)) {
      case StripePointStatus::valid: break;
      case StripePointStatus::not_finite: ++stats.not_finite; continue;
      case StripePointStatus::outside_image: ++stats.outside_image; continue;
      case StripePointStatus::no_intersection: ++stats.no_intersection; continue;
    }
    point.offset_m = rotation * camera_to_sensor_frame(camera.point);
    StructuredLightElevationPartials partials = partials_from_rows(camera, rows);
    partials.d_pitch_m_per_rad += lever.d_pitch_m_per_rad;
    partials.d_roll_m_per_rad += lever.d_roll_m_per_rad;
    point.height_error_m = structured_light_elevation_error_bound_m(partials, parameters, options);
    point.range_m = camera.point.norm();
    emit(point);
    ++stats.converted;
  }
  return stats;
}

}  // namespace

StripeConversionStats stripe_to_sensor_points(const StructuredLightModel& model, std::span<const StripePixel> pixels,
                                              const TrunkPose& pose, const SensorMount& mount,
                                              const UpdateOptions& options, PointBatch& batch) {
  batch.clear();
  batch.gamma_rad = sheet_inclination_rad(model.parameters().sheet_angle_rad, pose.pitch_rad, pose.roll_rad, mount);
  return for_each_stripe_point(model, pixels, pose, mount, options,
                               [&](const SensorPoint& p) { batch.points.push_back(p); });
}

StripeConversionStats stripe_to_map_points(const StructuredLightModel& model, std::span<const StripePixel> pixels,
                                           const TrunkPose& pose, const ScanMotion& motion,
                                           const UpdateOptions& options, std::vector<MapPoint>& points) {
  points.clear();
  const SensorMount& mount = model.parameters().mount;
  if (!motion_is_finite(motion)) {
    StripeConversionStats stats;
    stats.pixels = pixels.size();
    stats.pose_rejected = true;
    return stats;
  }
  const double gamma = sheet_inclination_rad(model.parameters().sheet_angle_rad, pose.pitch_rad, pose.roll_rad, mount);
  const MaxElevationChange bound(motion, gamma, mount, options, pose.yaw_rad);
  const Eigen::Vector3d origin = sensor_origin_in_map(pose, mount);
  return for_each_stripe_point(model, pixels, pose, mount, options, [&](const SensorPoint& p) {
    double dz_max = bound.at(p.height_error_m, p.offset_m);
    if (!(dz_max < kUnboundedElevationChange_m)) dz_max = kUnboundedElevationChange_m;
    points.push_back({origin.x() + p.offset_m.x(), origin.y() + p.offset_m.y(), origin.z() + p.offset_m.z(), dz_max});
  });
}

}  // namespace stridemap
