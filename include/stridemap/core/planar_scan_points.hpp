#pragma once
// The error model of a tilted 2D range scanner (eq. 6 without the motion
// terms): a beam's point and |dz/dr| Dr + |dz/dpsi| Dpsi + |dz/dphi| Dphi +
// |dz/dalpha| Dalpha. The partial derivatives are linear in (cos t, sin t)
// with coefficients fixed for the scan, so they are evaluated once at
// t = 0 and 90 deg and each beam costs a few multiplications. A source of
// points for TerrainMapper::integrate_scan (core/sensor_point.hpp).
#include <cmath>
#include <cstddef>
#include <numbers>

#include <Eigen/Core>

#include "stridemap/core/map_update.hpp"
#include "stridemap/core/planar_scan.hpp"
#include "stridemap/core/pose.hpp"
#include "stridemap/core/sensor_point.hpp"
#include "stridemap/core/sensor_transform.hpp"

namespace stridemap {

/// What a planar scanner's beams share within one scan: the map directions
/// of a beam at t = 0 and 90 deg and the partials of eq. (6) there (every
/// beam's are a combination of the two), the lever arm's partials and gamma.
struct PlanarBeamGeometry {
  PlanarBeamGeometry(const TrunkPose& pose, const SensorMount& mount)
      : PlanarBeamGeometry(pose, mount, tilt_rotation(pose.pitch_rad, pose.roll_rad, mount), 0) {}
  /// The same with M = mount_rotation(mount) and the heading's cosine and
  /// sine already made (a mapper keeps its fixed mount's M; a scan needs the
  /// heading's elsewhere too); pitch's and roll's are made once for the
  /// rotations and the partials: the same doubles, bit for bit.
  PlanarBeamGeometry(const TrunkPose& pose, const SensorMount& mount, const Eigen::Matrix3d& mount_rotation_m,
                     double cos_yaw, double sin_yaw)
      : lever(sensor_origin_elevation_partials(pose, mount)) {
    const double sp = std::sin(pose.pitch_rad), cp = std::cos(pose.pitch_rad);
    const double sr = std::sin(pose.roll_rad), cr = std::cos(pose.roll_rad);
    // tilt_rotation(pitch, roll, M) and sensor_to_map_rotation(yaw, T).
    const Eigen::Matrix3d tilt = rotation_about_y(cp, sp) * rotation_about_x(cr, sr) * mount_rotation_m;
    gamma_rad = scan_plane_inclination_rad(tilt);
    const Eigen::Matrix3d rotation = rotation_about_z(cos_yaw, sin_yaw) * tilt;
    forward = rotation.col(0);
    left = rotation.col(1);
    unit_beam_elevation_partials(pose.pitch_rad, pose.roll_rad, sp, cp, sr, cr, mount, at_front, at_left);
  }

  /// A valid beam's offset from the sensor origin (map axes) and the
  /// sensor's error part of Delta z_max. The one formula of the scan path:
  /// PlanarScanPoints and the packed path (TerrainMapper) both call it.
  void point(double r, double dr, double ct, double st, const UpdateOptions& options, Eigen::Vector3d& offset_m,
             double& height_error_m) const {
    offset_m = offset(r, ct, st);
    height_error_m = height_error(r, dr, ct, st, options);
  }

  /// The beam's offset alone, as point() forms it (the visibility clean-up
  /// thins the fan by it before it needs the error bound).
  Eigen::Vector3d offset(double r, double ct, double st) const { return r * (ct * forward + st * left); }

  /// The sensor's error part of Delta z_max alone, as point() forms it.
  double height_error(double r, double dr, double ct, double st, const UpdateOptions& options) const {
    ElevationPartials partials;
    partials.d_range = ct * at_front.d_range + st * at_left.d_range;
    partials.d_pitch_m_per_rad = lever.d_pitch_m_per_rad + r * (ct * at_front.d_pitch_m_per_rad + st * at_left.d_pitch_m_per_rad);
    partials.d_roll_m_per_rad = lever.d_roll_m_per_rad + r * (ct * at_front.d_roll_m_per_rad + st * at_left.d_roll_m_per_rad);
    partials.d_alpha_m_per_rad = r * (ct * at_front.d_alpha_m_per_rad + st * at_left.d_alpha_m_per_rad);
    return elevation_error_bound_m(partials, dr, options);
  }

  ElevationPartials at_front, at_left, lever;
  double gamma_rad;
  Eigen::Vector3d forward, left;

 private:
  // T made once for gamma and the rotation (per scan, five rotations fewer);
  // the partials at t = 0 and 90 deg share their sines (the int tells this
  // constructor from the public one taking M).
  PlanarBeamGeometry(const TrunkPose& pose, const SensorMount& mount, const Eigen::Matrix3d& tilt, int)
      : lever(sensor_origin_elevation_partials(pose, mount)),  // zero without pose z
        gamma_rad(scan_plane_inclination_rad(tilt)) {
    unit_beam_elevation_partials(pose.pitch_rad, pose.roll_rad, mount, at_front, at_left);
    const Eigen::Matrix3d rotation = sensor_to_map_rotation(pose.yaw_rad, tilt);
    forward = rotation.col(0);  // map direction of a beam at t = 0
    left = rotation.col(1);     // ... and at t = 90 deg
  }
};

class PlanarScanPoints {
 public:
  /// `cos_angle` / `sin_angle` hold cos and sin of scan.angle_rad (the
  /// caller keeps them between scans); all four must outlive this object.
  PlanarScanPoints(const PlanarScan& scan, const double* cos_angle, const double* sin_angle, const TrunkPose& pose,
                   const SensorMount& mount, const UpdateOptions& options)
      : scan_(scan), cos_(cos_angle), sin_(sin_angle), options_(options), geometry_(pose, mount) {}

  std::size_t size() const { return scan_.range_m.size(); }
  double inclination_rad() const { return geometry_.gamma_rad; }

  PointStatus point(std::size_t i, SensorPoint& out) const {
    const double r = scan_.range_m[i];
    const double dr = scan_.range_error_m[i];
    if (!std::isfinite(r) || r <= 0.0) return PointStatus::invalid_range;
    if (!std::isfinite(scan_.angle_rad[i]) || !std::isfinite(dr) || dr < 0.0) return PointStatus::invalid_beam;
    geometry_.point(r, dr, cos_[i], sin_[i], options_, out.offset_m, out.height_error_m);
    out.range_m = r;
    return PointStatus::ok;
  }

 private:
  const PlanarScan& scan_;
  const double* cos_;
  const double* sin_;
  const UpdateOptions& options_;
  PlanarBeamGeometry geometry_;
};

}  // namespace stridemap
