#pragma once
// Sensor-to-map transform of eq. (5) and the quantities eq. (6)-(7) derive
// from it.
//
// Sensor frame S: beam i points along (cos t_i, sin t_i, 0) before tilting,
// t = 0 straight ahead, positive t to the left. The composed rotation is
//   R = Rz(yaw) * Ry(pitch) * Rx(roll) * Ry(alpha),
// the paper's Rot(X, phi) Rot(Y', psi) Rot(X'', alpha) renamed to a frame with
// X forward (the paper's X is lateral). Yaw does not change elevations, so
// the tilt part T = Ry(pitch) Rx(roll) Ry(alpha) is what eq. (6) differentiates.
#include <Eigen/Core>

#include "stridemap/core/pose.hpp"

namespace stridemap {

/// T = Ry(pitch) * Rx(roll) * Ry(alpha).
Eigen::Matrix3d tilt_rotation(double pitch_rad, double roll_rad, double alpha_rad);

/// Full sensor-to-map rotation Rz(yaw) * T.
Eigen::Matrix3d sensor_to_map_rotation(const TrunkPose& pose, const SensorMount& mount);

/// Sensor origin in the map frame: trunk position plus the yawed mount offset,
/// at height h_ref + d_z (the paper's h_m = z_m + d_z + h_ref).
Eigen::Vector3d sensor_origin_in_map(const TrunkPose& pose, const SensorMount& mount);

/// A point of the sensor frame, in the map frame.
Eigen::Vector3d sensor_point_to_map(const Eigen::Vector3d& point_in_sensor, const TrunkPose& pose,
                                    const SensorMount& mount);

/// gamma of eq. (7): the inclination of the scan plane about the lateral
/// axis, from the composed rotation as atan2(T(0,2), T(2,2)) (the tilt of
/// the plane's normal towards +X). For zero roll it is pitch + alpha.
double scan_plane_inclination_rad(double pitch_rad, double roll_rad, double alpha_rad);

/// z_m of a beam hit relative to the sensor, and its analytic partial
/// derivatives (eq. 6's terms).
struct ElevationPartials {
  double z_m = 0.0;              ///< vertical offset of the hit below/above the sensor [m]
  double d_range = 0.0;          ///< dz/dr [m/m]
  double d_pitch_m_per_rad = 0.0;  ///< dz/dphi_r
  double d_roll_m_per_rad = 0.0;   ///< dz/dpsi_r
  double d_alpha_m_per_rad = 0.0;  ///< dz/dalpha
};

ElevationPartials beam_elevation_partials(double range_m, double beam_angle_rad, double pitch_rad,
                                          double roll_rad, double alpha_rad);

}  // namespace stridemap
