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

class PlanarScanPoints {
 public:
  /// `cos_angle` / `sin_angle` hold cos and sin of scan.angle_rad (the
  /// caller keeps them between scans); all four must outlive this object.
  PlanarScanPoints(const PlanarScan& scan, const double* cos_angle, const double* sin_angle, const TrunkPose& pose,
                   const SensorMount& mount, const UpdateOptions& options)
      : scan_(scan),
        cos_(cos_angle),
        sin_(sin_angle),
        options_(options),
        at_front_(beam_elevation_partials(1.0, 0.0, pose.pitch_rad, pose.roll_rad, mount)),
        at_left_(beam_elevation_partials(1.0, std::numbers::pi / 2, pose.pitch_rad, pose.roll_rad, mount)),
        lever_(sensor_origin_elevation_partials(pose, mount)),  // zero without pose z
        gamma_rad_(scan_plane_inclination_rad(pose.pitch_rad, pose.roll_rad, mount)) {
    const Eigen::Matrix3d rotation = sensor_to_map_rotation(pose, mount);
    forward_ = rotation.col(0);  // map direction of a beam at t = 0
    left_ = rotation.col(1);     // ... and at t = 90 deg
  }

  std::size_t size() const { return scan_.range_m.size(); }
  double inclination_rad() const { return gamma_rad_; }

  PointStatus point(std::size_t i, SensorPoint& out) const {
    const double r = scan_.range_m[i];
    const double dr = scan_.range_error_m[i];
    if (!std::isfinite(r) || r <= 0.0) return PointStatus::invalid_range;
    if (!std::isfinite(scan_.angle_rad[i]) || !std::isfinite(dr) || dr < 0.0) return PointStatus::invalid_beam;
    const double ct = cos_[i], st = sin_[i];
    out.offset_m = r * (ct * forward_ + st * left_);
    ElevationPartials partials;
    partials.d_range = ct * at_front_.d_range + st * at_left_.d_range;
    partials.d_pitch_m_per_rad = lever_.d_pitch_m_per_rad + r * (ct * at_front_.d_pitch_m_per_rad + st * at_left_.d_pitch_m_per_rad);
    partials.d_roll_m_per_rad = lever_.d_roll_m_per_rad + r * (ct * at_front_.d_roll_m_per_rad + st * at_left_.d_roll_m_per_rad);
    partials.d_alpha_m_per_rad = r * (ct * at_front_.d_alpha_m_per_rad + st * at_left_.d_alpha_m_per_rad);
    out.height_error_m = elevation_error_bound_m(partials, dr, options_);
    out.range_m = r;
    return PointStatus::ok;
  }

 private:
  const PlanarScan& scan_;
  const double* cos_;
  const double* sin_;
  const UpdateOptions& options_;
  ElevationPartials at_front_, at_left_, lever_;
  double gamma_rad_;
  Eigen::Vector3d forward_, left_;
};

}  // namespace stridemap
