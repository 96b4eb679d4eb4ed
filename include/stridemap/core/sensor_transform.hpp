#pragma once
// Sensor-to-map transform of eq. (5) and the quantities eq. (6)-(7) derive
// from it (docs/mapping.md "Frames").
//
// Sensor frame S: beam i points along (cos t_i, sin t_i, 0) before tilting,
// t = 0 straight ahead, positive t to the left. The composed rotation is
//   R = Rz(yaw) * Ry(pitch) * Rx(roll) * M,   M = Rz(mount yaw) * Ry(alpha) * Rx(mount roll),
// the paper's Rot(X, phi) Rot(Y', psi) Rot(X'', alpha) renamed to a frame with
// X forward (the paper's X is lateral), extended by the mount's roll and yaw
// (M = Ry(alpha) for the paper's mount). The trunk's yaw does not change
// elevations, so the tilt part T = Ry(pitch) Rx(roll) M is what eq. (6)
// differentiates.
//
// The overloads taking a bare alpha are the paper's mount (no mount roll or
// yaw); the ones taking a SensorMount honour the full mount and give the
// same doubles, bit for bit, when its roll and yaw are zero.
#include <Eigen/Core>

#include "stridemap/core/pose.hpp"

namespace stridemap {

/// Rx(a), Ry(a) and Rz(a) from cos a and sin a already made: the matrices
/// of Eigen's AngleAxisd(a, axis).toRotationMatrix(), bit for bit (each
/// entry rounded as there, zeros' signs included), so that a scan computes
/// each angle's sine and cosine once for every rotation and partial.
Eigen::Matrix3d rotation_about_x(double cos_a, double sin_a);
Eigen::Matrix3d rotation_about_y(double cos_a, double sin_a);
Eigen::Matrix3d rotation_about_z(double cos_a, double sin_a);

/// M = Rz(mount.yaw_rad) * Ry(mount.pitch_rad) * Rx(mount.roll_rad): the
/// sensor frame's axes in the trunk frame.
Eigen::Matrix3d mount_rotation(const SensorMount& mount);

/// T = Ry(pitch) * Rx(roll) * Ry(alpha).
Eigen::Matrix3d tilt_rotation(double pitch_rad, double roll_rad, double alpha_rad);
/// T = Ry(pitch) * Rx(roll) * mount_rotation(mount).
Eigen::Matrix3d tilt_rotation(double pitch_rad, double roll_rad, const SensorMount& mount);
/// The same from M = mount_rotation(mount) already made (a mapper's mount
/// is fixed, so it keeps M): the same matrix, bit for bit.
Eigen::Matrix3d tilt_rotation(double pitch_rad, double roll_rad, const Eigen::Matrix3d& mount_rotation);

/// Full sensor-to-map rotation Rz(yaw) * T.
Eigen::Matrix3d sensor_to_map_rotation(const TrunkPose& pose, const SensorMount& mount);
/// The same from T = tilt_rotation(pitch, roll, mount) already made (a
/// scan's geometry needs T for gamma too): the same matrix, bit for bit.
Eigen::Matrix3d sensor_to_map_rotation(double yaw_rad, const Eigen::Matrix3d& tilt);

/// Sensor origin in the map frame.
/// Pose without z (the paper): trunk position plus the mount offset turned
/// by the heading only, at height h_ref + d_z + height change (the paper's
/// h_m = z_m + d_z + h_ref); leg kinematics already contain what trunk pitch
/// and roll do to the sensor height.
/// Pose with z: (x, y, z) + Rz(yaw) Ry(pitch) Rx(roll) (forward, lateral, d_z),
/// the mount as a rigid transform; h_ref and the height change are unused.
Eigen::Vector3d sensor_origin_in_map(const TrunkPose& pose, const SensorMount& mount);
/// The same with cos and sin of pose.yaw_rad already made (a scan needs
/// them in several places): the same vector, bit for bit.
Eigen::Vector3d sensor_origin_in_map(const TrunkPose& pose, const SensorMount& mount, double cos_yaw,
                                     double sin_yaw);

/// A point of the sensor frame, in the map frame.
Eigen::Vector3d sensor_point_to_map(const Eigen::Vector3d& point_in_sensor, const TrunkPose& pose,
                                    const SensorMount& mount);

/// gamma of eq. (7): the inclination of the scan plane about the lateral
/// axis, from the composed rotation as atan2(T(0,2), T(2,2)) (the tilt of
/// the plane's normal towards +X). For zero roll it is pitch + alpha.
double scan_plane_inclination_rad(double pitch_rad, double roll_rad, double alpha_rad);
/// The same for the full mount (T with mount roll and yaw).
double scan_plane_inclination_rad(double pitch_rad, double roll_rad, const SensorMount& mount);
/// The same from T = tilt_rotation(pitch, roll, mount) already made.
double scan_plane_inclination_rad(const Eigen::Matrix3d& tilt);

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
/// The same for the full mount: derivatives with respect to trunk pitch,
/// trunk roll and the mount's pitch alpha, the mount's roll and yaw held.
ElevationPartials beam_elevation_partials(double range_m, double beam_angle_rad, double pitch_rad,
                                          double roll_rad, const SensorMount& mount);
/// beam_elevation_partials(1, 0, ...) and beam_elevation_partials(1, pi/2,
/// ...) at once (what a planar scan's beams are combinations of), with the
/// sines and cosines of pitch, roll and the mount made once: the same
/// doubles, bit for bit.
void unit_beam_elevation_partials(double pitch_rad, double roll_rad, const SensorMount& mount,
                                  ElevationPartials& at_front, ElevationPartials& at_left);
/// The same with the sines and cosines of pitch and roll already made.
void unit_beam_elevation_partials(double pitch_rad, double roll_rad, double sin_pitch, double cos_pitch,
                                  double sin_roll, double cos_roll, const SensorMount& mount,
                                  ElevationPartials& at_front, ElevationPartials& at_left);

/// The third row of T (a sensor-frame vector's height in the map frame) and
/// its derivatives with respect to trunk pitch, trunk roll and alpha: the
/// elevation partials of any point fixed in the sensor frame (the laser's
/// beams, the structured-light camera's points) are these rows times it.
struct ElevationRows {
  Eigen::RowVector3d row, d_pitch, d_roll, d_alpha;
};
ElevationRows elevation_rows(double pitch_rad, double roll_rad, const SensorMount& mount);

/// How the sensor origin's height moves with trunk pitch and roll
/// (d_pitch_m_per_rad, d_roll_m_per_rad; z_m is the origin's height above
/// the trunk reference point). Zero for a pose without z: there the sensor
/// height comes from leg kinematics, not from the trunk's attitude. With z,
/// the mount's lever arm turns with the trunk, and an attitude error moves
/// every point by this much on top of its beam_elevation_partials.
ElevationPartials sensor_origin_elevation_partials(const TrunkPose& pose, const SensorMount& mount);

}  // namespace stridemap
