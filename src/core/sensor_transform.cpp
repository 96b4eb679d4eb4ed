#include "stridemap/core/sensor_transform.hpp"

#include <cmath>

#include <Eigen/Geometry>

namespace stridemap {

Eigen::Matrix3d tilt_rotation(double pitch_rad, double roll_rad, double alpha_rad) {
  const Eigen::Matrix3d pitch = Eigen::AngleAxisd(pitch_rad, Eigen::Vector3d::UnitY()).toRotationMatrix();
  const Eigen::Matrix3d roll = Eigen::AngleAxisd(roll_rad, Eigen::Vector3d::UnitX()).toRotationMatrix();
  const Eigen::Matrix3d alpha = Eigen::AngleAxisd(alpha_rad, Eigen::Vector3d::UnitY()).toRotationMatrix();
  return pitch * roll * alpha;
}

Eigen::Matrix3d sensor_to_map_rotation(const TrunkPose& pose, const SensorMount& mount) {
  const Eigen::Matrix3d yaw = Eigen::AngleAxisd(pose.yaw_rad, Eigen::Vector3d::UnitZ()).toRotationMatrix();
  return yaw * tilt_rotation(pose.pitch_rad, pose.roll_rad, mount.pitch_rad);
}

Eigen::Vector3d sensor_origin_in_map(const TrunkPose& pose, const SensorMount& mount) {
  // The mount offset turns with the heading only: the paper measures the
  // sensor height d_z from leg kinematics, which already contains the effect
  // of trunk pitch and roll on the sensor's height.
  const double c = std::cos(pose.yaw_rad);
  const double s = std::sin(pose.yaw_rad);
  return {pose.x_m + c * mount.forward_offset_m - s * mount.lateral_offset_m,
          pose.y_m + s * mount.forward_offset_m + c * mount.lateral_offset_m,
          pose.reference_elevation_m + mount.height_m + pose.height_change_m};
}

Eigen::Vector3d sensor_point_to_map(const Eigen::Vector3d& point_in_sensor, const TrunkPose& pose,
                                    const SensorMount& mount) {
  return sensor_origin_in_map(pose, mount) + sensor_to_map_rotation(pose, mount) * point_in_sensor;
}

double scan_plane_inclination_rad(double pitch_rad, double roll_rad, double alpha_rad) {
  // The scan plane's normal is T e_z. Moving the sensor forward by d shifts
  // the plane's trace on a vertical face by d n_x / n_z, so gamma is the
  // normal's tilt towards +X. Multiplied out this is the paper's eq. (7).
  const Eigen::Matrix3d t = tilt_rotation(pitch_rad, roll_rad, alpha_rad);
  return std::atan2(t(0, 2), t(2, 2));
}

ElevationPartials beam_elevation_partials(double range_m, double beam_angle_rad, double pitch_rad,
                                          double roll_rad, double alpha_rad) {
  // Third row of T = Ry(pitch) Rx(roll) Ry(alpha), multiplied out by hand:
  //   (-sp ca - cp cr sa,  cp sr,  -sp sa + cp cr ca)
  // and applied to the beam (r cos t, r sin t, 0).
  const double sp = std::sin(pitch_rad), cp = std::cos(pitch_rad);
  const double sr = std::sin(roll_rad), cr = std::cos(roll_rad);
  const double sa = std::sin(alpha_rad), ca = std::cos(alpha_rad);
  const double ct = std::cos(beam_angle_rad), st = std::sin(beam_angle_rad);

  ElevationPartials out;
  out.d_range = ct * (-sp * ca - cp * cr * sa) + st * cp * sr;
  out.z_m = range_m * out.d_range;
  out.d_pitch_m_per_rad = range_m * (ct * (-cp * ca + sp * cr * sa) - st * sp * sr);
  out.d_roll_m_per_rad = range_m * (ct * cp * sr * sa + st * cp * cr);
  out.d_alpha_m_per_rad = range_m * ct * (sp * sa - cp * cr * ca);
  return out;
}

}  // namespace stridemap
