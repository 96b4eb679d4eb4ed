#pragma once
// Robot trunk pose and sensor mount (paper section 5.2, eq. 5; design.md 3;
// docs/mapping.md "Frames").
//
// Map frame M: X forward at start, Y left, Z up. Positive pitch tilts the
// nose (and a forward-looking sensor) down; positive roll lifts the left side.
#include <numbers>
#include <optional>

namespace stridemap {

/// Pose of the trunk in the map frame, as the mapper is given it.
struct TrunkPose {
  double x_m = 0.0;  ///< horizontal position of the trunk reference point [m]
  double y_m = 0.0;  ///< [m]
  double yaw_rad = 0.0;    ///< heading theta_r, counter-clockwise from +X [rad]
  double pitch_rad = 0.0;  ///< phi_r, positive nose down [rad]
  double roll_rad = 0.0;   ///< psi_r, positive left side up [rad]
  /// h_ref of eq. (9): terrain elevation under the robot, read from the map
  /// already built (0 on the flat start area) [m]. Sets the sensor height
  /// only when z_m is absent.
  double reference_elevation_m = 0.0;
  /// Change of the sensor height d_z from the mount's nominal height, as leg
  /// kinematics report it while the trunk bobs [m]. Used only when z_m is
  /// absent.
  double height_change_m = 0.0;
  /// Height of the trunk reference point in the map frame, from a full 6-DoF
  /// state estimate [m]. Absent (the default): the paper's model, sensor at
  /// h_ref + d_z + height change. Present: the mount is applied as a rigid
  /// transform to the trunk at (x, y, z, yaw, pitch, roll). An optional
  /// rather than a NaN sentinel, so a NaN from a broken estimator is still
  /// caught as "not finite" instead of meaning "no z".
  std::optional<double> z_m{};
};

/// How the range sensor is fixed to the trunk: a rigid transform from the
/// trunk frame to the sensor frame S, translation (forward_offset_m,
/// lateral_offset_m, height_m) and rotation Rz(yaw_rad) Ry(pitch_rad)
/// Rx(roll_rad). The paper's mount is the case roll = yaw = 0.
struct SensorMount {
  /// d_z: sensor origin above the trunk reference point [m]. In the paper's
  /// model (pose without z) the reference point is on the ground under the
  /// robot, so this is the nominal sensor height above the ground.
  /// Default: the paper's final Messor mount (Fig. 8c).
  double height_m = 0.26;
  /// alpha: fixed pitch of the sensor relative to the trunk, positive
  /// towards the ground [rad]. Default 35 deg (Fig. 8c).
  double pitch_rad = 35.0 * std::numbers::pi / 180.0;
  double forward_offset_m = 0.0;  ///< sensor origin ahead of the trunk reference point [m]
  double lateral_offset_m = 0.0;  ///< sensor origin left of the trunk reference point [m]
  /// Roll of the sensor about its own X axis, applied after alpha,
  /// positive left side up [rad].
  double roll_rad = 0.0;
  /// Yaw of the sensor relative to the trunk, counter-clockwise seen from
  /// above, applied before alpha (a scanner turned to look to the left) [rad].
  double yaw_rad = 0.0;
};

}  // namespace stridemap
