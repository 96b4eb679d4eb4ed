#include "stridemap/core/sensor_transform.hpp"

#include <cmath>
#include <numbers>

#include <Eigen/Geometry>

namespace stridemap {
namespace {

Eigen::Matrix3d about_x(double angle_rad) {
  return Eigen::AngleAxisd(angle_rad, Eigen::Vector3d::UnitX()).toRotationMatrix();
}
Eigen::Matrix3d about_y(double angle_rad) {
  return Eigen::AngleAxisd(angle_rad, Eigen::Vector3d::UnitY()).toRotationMatrix();
}
Eigen::Matrix3d about_z(double angle_rad) {
  return Eigen::AngleAxisd(angle_rad, Eigen::Vector3d::UnitZ()).toRotationMatrix();
}

// d/da of a rotation R(a) = exp(a [u]x) is R(a) [u]x; these are the [u]x.
Eigen::Matrix3d generator_x() {
  Eigen::Matrix3d g;
  g << 0, 0, 0, 0, 0, -1, 0, 1, 0;
  return g;
}
Eigen::Matrix3d generator_y() {
  Eigen::Matrix3d g;
  g << 0, 0, 1, 0, 0, 0, -1, 0, 0;
  return g;
}

bool is_paper_mount(const SensorMount& mount) { return mount.roll_rad == 0.0 && mount.yaw_rad == 0.0; }

// The paper mount's partials from the sines and cosines of the beam angle,
// pitch, roll and alpha (beam_elevation_partials multiplied out).
ElevationPartials paper_mount_partials(double range_m, double ct, double st, double sp, double cp, double sr,
                                       double cr, double sa, double ca) {
  ElevationPartials out;
  out.d_range = ct * (-sp * ca - cp * cr * sa) + st * cp * sr;
  out.z_m = range_m * out.d_range;
  out.d_pitch_m_per_rad = range_m * (ct * (-cp * ca + sp * cr * sa) - st * sp * sr);
  out.d_roll_m_per_rad = range_m * (ct * cp * sr * sa + st * cp * cr);
  out.d_alpha_m_per_rad = range_m * ct * (sp * sa - cp * cr * ca);
  return out;
}

// The general mount's partials of a unit-range beam (cos t, sin t, 0) from
// elevation_rows.
ElevationPartials rows_partials(const ElevationRows& rows, double range_m, const Eigen::Vector3d& beam) {
  ElevationPartials out;
  out.d_range = (rows.row * beam).value();
  out.z_m = range_m * out.d_range;
  out.d_pitch_m_per_rad = range_m * (rows.d_pitch * beam).value();
  out.d_roll_m_per_rad = range_m * (rows.d_roll * beam).value();
  out.d_alpha_m_per_rad = range_m * (rows.d_alpha * beam).value();
  return out;
}

}  // namespace

// AngleAxis forms sin_axis = s u, cos1 = (1 - c) u and the entries
// cos1_i u_j -/+ sin_axis_k off the diagonal, cos1_i u_i + c on it. For a
// unit axis most of those terms are zeros of known sign; what remains is
// written out here in the same order (0 + s is not s when s is -0, and
// (1 - c) + c is not always 1), and tests compare every bit.
Eigen::Matrix3d rotation_about_x(double c, double s) {
  Eigen::Matrix3d m;
  m << (1.0 - c) + c, 0.0, 0.0,  //
      0.0, c, 0.0 - s,            //
      0.0, 0.0 + s, c;
  return m;
}
Eigen::Matrix3d rotation_about_y(double c, double s) {
  Eigen::Matrix3d m;
  m << c, 0.0, 0.0 + s,      //
      0.0, (1.0 - c) + c, 0.0,  //
      0.0 - s, 0.0, c;
  return m;
}
Eigen::Matrix3d rotation_about_z(double c, double s) {
  Eigen::Matrix3d m;
  m << c, 0.0 - s, 0.0,  //
      0.0 + s, c, 0.0,    //
      0.0, 0.0, (1.0 - c) + c;
  return m;
}

Eigen::Matrix3d mount_rotation(const SensorMount& mount) {
  return about_z(mount.yaw_rad) * about_y(mount.pitch_rad) * about_x(mount.roll_rad);
}

Eigen::Matrix3d tilt_rotation(double pitch_rad, double roll_rad, double alpha_rad) {
  return about_y(pitch_rad) * about_x(roll_rad) * about_y(alpha_rad);
}

Eigen::Matrix3d tilt_rotation(double pitch_rad, double roll_rad, const SensorMount& mount) {
  return tilt_rotation(pitch_rad, roll_rad, mount_rotation(mount));
}

Eigen::Matrix3d tilt_rotation(double pitch_rad, double roll_rad, const Eigen::Matrix3d& mount_rotation) {
  return about_y(pitch_rad) * about_x(roll_rad) * mount_rotation;
}

Eigen::Matrix3d sensor_to_map_rotation(const TrunkPose& pose, const SensorMount& mount) {
  return sensor_to_map_rotation(pose.yaw_rad, tilt_rotation(pose.pitch_rad, pose.roll_rad, mount));
}

Eigen::Matrix3d sensor_to_map_rotation(double yaw_rad, const Eigen::Matrix3d& tilt) { return about_z(yaw_rad) * tilt; }

Eigen::Vector3d sensor_origin_in_map(const TrunkPose& pose, const SensorMount& mount) {
  if (pose.z_m) return sensor_origin_in_map(pose, mount, 0.0, 0.0);  // the trunk rotation has its own
  return sensor_origin_in_map(pose, mount, std::cos(pose.yaw_rad), std::sin(pose.yaw_rad));
}

Eigen::Vector3d sensor_origin_in_map(const TrunkPose& pose, const SensorMount& mount, double cos_yaw,
                                     double sin_yaw) {
  if (pose.z_m) {
    const Eigen::Vector3d lever(mount.forward_offset_m, mount.lateral_offset_m, mount.height_m);
    const Eigen::Matrix3d trunk = about_z(pose.yaw_rad) * about_y(pose.pitch_rad) * about_x(pose.roll_rad);
    return Eigen::Vector3d(pose.x_m, pose.y_m, *pose.z_m) + trunk * lever;
  }
  // The mount offset turns with the heading only: the paper measures the
  // sensor height d_z from leg kinematics, which already contains the effect
  // of trunk pitch and roll on the sensor's height.
  const double c = cos_yaw;
  const double s = sin_yaw;
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

double scan_plane_inclination_rad(double pitch_rad, double roll_rad, const SensorMount& mount) {
  return scan_plane_inclination_rad(tilt_rotation(pitch_rad, roll_rad, mount));
}

double scan_plane_inclination_rad(const Eigen::Matrix3d& tilt) { return std::atan2(tilt(0, 2), tilt(2, 2)); }

ElevationPartials beam_elevation_partials(double range_m, double beam_angle_rad, double pitch_rad,
                                          double roll_rad, double alpha_rad) {
  // Third row of T = Ry(pitch) Rx(roll) Ry(alpha), multiplied out by hand:
  //   (-sp ca - cp cr sa,  cp sr,  -sp sa + cp cr ca)
  // and applied to the beam (r cos t, r sin t, 0).
  const double sp = std::sin(pitch_rad), cp = std::cos(pitch_rad);
  const double sr = std::sin(roll_rad), cr = std::cos(roll_rad);
  const double sa = std::sin(alpha_rad), ca = std::cos(alpha_rad);
  const double ct = std::cos(beam_angle_rad), st = std::sin(beam_angle_rad);
  return paper_mount_partials(range_m, ct, st, sp, cp, sr, cr, sa, ca);
}

ElevationRows elevation_rows(double pitch_rad, double roll_rad, const SensorMount& mount) {
  ElevationRows out;
  if (is_paper_mount(mount)) {
    // T = Ry(pitch) Rx(roll) Ry(alpha) multiplied out by hand, as the
    // structured-light mapping has always computed it (bit for bit).
    const double sp = std::sin(pitch_rad), cp = std::cos(pitch_rad);
    const double sr = std::sin(roll_rad), cr = std::cos(roll_rad);
    const double sa = std::sin(mount.pitch_rad), ca = std::cos(mount.pitch_rad);
    out.row = {-sp * ca - cp * cr * sa, cp * sr, -sp * sa + cp * cr * ca};
    out.d_pitch = {-cp * ca + sp * cr * sa, -sp * sr, -cp * sa - sp * cr * ca};
    out.d_roll = {cp * sr * sa, cp * cr, -cp * sr * ca};
    out.d_alpha = {sp * sa - cp * cr * ca, 0.0, -sp * ca - cp * cr * sa};
    return out;
  }
  // T = Ry(p) Rx(r) Rz(yaw_m) Ry(alpha) Rx(roll_m); each angle's derivative
  // puts its generator right after its own rotation.
  const Eigen::Matrix3d pitch = about_y(pitch_rad), roll = about_x(roll_rad);
  const Eigen::Matrix3d yaw_m = about_z(mount.yaw_rad), alpha = about_y(mount.pitch_rad);
  const Eigen::Matrix3d roll_m = about_x(mount.roll_rad);
  const Eigen::Matrix3d m = yaw_m * alpha * roll_m;
  const Eigen::RowVector3d up = Eigen::RowVector3d::UnitZ();
  out.row = up * pitch * roll * m;
  out.d_pitch = up * pitch * generator_y() * roll * m;
  out.d_roll = up * pitch * roll * generator_x() * m;
  out.d_alpha = up * pitch * roll * yaw_m * alpha * generator_y() * roll_m;
  return out;
}

ElevationPartials beam_elevation_partials(double range_m, double beam_angle_rad, double pitch_rad,
                                          double roll_rad, const SensorMount& mount) {
  // The paper's mount keeps the hand-multiplied form, so that maps built
  // with it do not move by a last bit.
  if (is_paper_mount(mount)) return beam_elevation_partials(range_m, beam_angle_rad, pitch_rad, roll_rad, mount.pitch_rad);
  // Everything is linear in the range: work on the unit beam and scale.
  const ElevationRows rows = elevation_rows(pitch_rad, roll_rad, mount);
  return rows_partials(rows, range_m, Eigen::Vector3d(std::cos(beam_angle_rad), std::sin(beam_angle_rad), 0.0));
}

void unit_beam_elevation_partials(double pitch_rad, double roll_rad, const SensorMount& mount,
                                  ElevationPartials& at_front, ElevationPartials& at_left) {
  unit_beam_elevation_partials(pitch_rad, roll_rad, std::sin(pitch_rad), std::cos(pitch_rad), std::sin(roll_rad),
                               std::cos(roll_rad), mount, at_front, at_left);
}

void unit_beam_elevation_partials(double pitch_rad, double roll_rad, double sp, double cp, double sr, double cr,
                                  const SensorMount& mount, ElevationPartials& at_front, ElevationPartials& at_left) {
  // The beam angles' own cosines and sines, as beam_elevation_partials
  // takes them (cos(pi/2) is not 0 in doubles).
  static const double cos_front = std::cos(0.0), sin_front = std::sin(0.0);
  static const double cos_left = std::cos(std::numbers::pi / 2), sin_left = std::sin(std::numbers::pi / 2);
  if (is_paper_mount(mount)) {
    const double sa = std::sin(mount.pitch_rad), ca = std::cos(mount.pitch_rad);
    at_front = paper_mount_partials(1.0, cos_front, sin_front, sp, cp, sr, cr, sa, ca);
    at_left = paper_mount_partials(1.0, cos_left, sin_left, sp, cp, sr, cr, sa, ca);
    return;
  }
  const ElevationRows rows = elevation_rows(pitch_rad, roll_rad, mount);
  at_front = rows_partials(rows, 1.0, Eigen::Vector3d(cos_front, sin_front, 0.0));
  at_left = rows_partials(rows, 1.0, Eigen::Vector3d(cos_left, sin_left, 0.0));
}

ElevationPartials sensor_origin_elevation_partials(const TrunkPose& pose, const SensorMount& mount) {
  ElevationPartials out;
  if (!pose.z_m) return out;
  const Eigen::Vector3d lever(mount.forward_offset_m, mount.lateral_offset_m, mount.height_m);
  const Eigen::Matrix3d pitch = about_y(pose.pitch_rad), roll = about_x(pose.roll_rad);
  out.z_m = (pitch * (roll * lever)).z();
  out.d_pitch_m_per_rad = (pitch * (generator_y() * (roll * lever))).z();
  out.d_roll_m_per_rad = (pitch * (roll * (generator_x() * lever))).z();
  return out;
}

}  // namespace stridemap
