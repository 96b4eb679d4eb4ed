#include "stridemap/pipeline/point_cloud_sensor.hpp"

#include <cmath>
#include <string>

#include "stridemap/core/error.hpp"
#include "stridemap/core/sensor_transform.hpp"

namespace stridemap {

PointCloudSensor::PointCloudSensor(const PointCloudSensorOptions& options) : options_(options) {
  if (!(std::isfinite(options_.sigma_scale) && options_.sigma_scale > 0.0)) {
    throw InputError("point sensor: sigma_scale must be a positive number, got " +
                     std::to_string(options_.sigma_scale));
  }
}

void PointCloudSensor::set_frame(double time_s, std::span<const Eigen::Vector3d> points_m,
                                 std::span<const double> height_sigma_m) {
  if (points_m.size() != height_sigma_m.size()) {
    throw InputError("point frame at t=" + std::to_string(time_s) + " s: " + std::to_string(points_m.size()) +
                     " points but " + std::to_string(height_sigma_m.size()) + " sigmas; there must be one per point");
  }
  points_ = points_m;
  sigma_ = height_sigma_m;
}

void PointCloudSensor::to_points(const TrunkPose& pose, const SensorMount& mount, const UpdateOptions& update,
                                 PointBatch& batch) {
  batch.clear();
  last_ = {};
  last_.points = points_.size();
  batch.gamma_rad = scan_plane_inclination_rad(pose.pitch_rad, pose.roll_rad, mount);
  const Eigen::Matrix3d rotation = sensor_to_map_rotation(pose, mount);
  // Tilting the trunk by a small angle moves a point's height by at most
  // its horizontal distance times that angle.
  const double tilt_error_rad = update.max_pitch_error_rad + update.max_roll_error_rad + update.max_mount_pitch_error_rad;
  for (std::size_t i = 0; i < points_.size(); ++i) {
    const Eigen::Vector3d& p = points_[i];
    const double sigma = sigma_[i];
    if (!p.allFinite() || !std::isfinite(sigma) || sigma < 0.0) {
      ++last_.not_finite;
      continue;
    }
    SensorPoint& out = batch.points.emplace_back();
    out.offset_m = rotation * p;
    out.range_m = p.norm();
    out.height_error_m = options_.sigma_scale * sigma + std::hypot(out.offset_m.x(), out.offset_m.y()) * tilt_error_rad;
    ++last_.converted;
  }
}

}  // namespace stridemap
