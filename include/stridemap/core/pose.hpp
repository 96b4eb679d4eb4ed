#pragma once
// Robot trunk pose and sensor mount (paper section 5.2, eq. 5; design.md 3).
//
// Map frame M: X forward at start, Y left, Z up. Positive pitch tilts the
// nose (and a forward-looking sensor) down; positive roll lifts the left side.
#include <numbers>

namespace stridemap {

/// Pose of the trunk in the map frame, as the mapper is given it.
struct TrunkPose {
  double x_m = 0.0;  ///< horizontal position of the trunk reference point [m]
  double y_m = 0.0;  ///< [m]
  double yaw_rad = 0.0;    ///< heading theta_r, counter-clockwise from +X [rad]
  double pitch_rad = 0.0;  ///< phi_r, positive nose down [rad]
  double roll_rad = 0.0;   ///< psi_r, positive left side up [rad]
  /// h_ref of eq. (9): terrain elevation under the robot, read from the map
  /// already built (0 on the flat start area) [m].
  double reference_elevation_m = 0.0;
  /// Change of the sensor height d_z from the mount's nominal height, as leg
  /// kinematics report it while the trunk bobs [m].
  double height_change_m = 0.0;
};

/// How the range sensor is fixed to the trunk.
struct SensorMount {
  /// d_z: nominal sensor height above the ground under the robot [m].
  /// Default: the paper's final Messor mount (Fig. 8c).
  double height_m = 0.26;
  /// alpha: fixed pitch of the sensor relative to the trunk, positive
  /// towards the ground [rad]. Default 35 deg (Fig. 8c).
  double pitch_rad = 35.0 * std::numbers::pi / 180.0;
  double forward_offset_m = 0.0;  ///< sensor origin ahead of the trunk reference point [m]
  double lateral_offset_m = 0.0;  ///< sensor origin left of the trunk reference point [m]
};

}  // namespace stridemap
