#include "stridemap/sim/calibration_target.hpp"

#include <cmath>
#include <cstdio>
#include <limits>
#include <string>

#include "stridemap/core/error.hpp"
#include "stridemap/core/sensor_transform.hpp"

namespace stridemap {
namespace {

std::string mm(double metres) {
  char text[32];
  std::snprintf(text, sizeof text, "%.1f mm", metres * 1000.0);
  return text;
}

}  // namespace

SensorMount calibration_bench_mount() { return SensorMount{0.5, 0.0, 0.0, 0.0}; }

TargetDepthRange target_depth_range(const StructuredLightModel& model) {
  TargetDepthRange range;
  range.nearest_m = model.sheet_depth_at_row_m(0.0).value_or(std::numeric_limits<double>::infinity());
  range.farthest_m = model.sheet_depth_at_row_m(model.parameters().image_height_px)
                         .value_or(std::numeric_limits<double>::infinity());
  return range;
}

Scene calibration_target_scene(const StructuredLightParameters& parameters, const TrunkPose& pose, double distance_m) {
  const StructuredLightModel model(parameters);
  if (parameters.mount.pitch_rad != 0.0 || parameters.mount.roll_rad != 0.0 || parameters.mount.yaw_rad != 0.0 ||
      pose.pitch_rad != 0.0 || pose.roll_rad != 0.0) {
    throw InputError("calibration target: the target stands across the optical axis of a level sensor; the mount "
                     "pitch, roll and yaw and the trunk's pitch and roll must be 0");
  }
  if (!(std::isfinite(distance_m) && distance_m > 0.0)) {
    throw InputError("calibration target: the distance must be a positive number of metres, got " +
                     std::to_string(distance_m));
  }
  const TargetDepthRange range = target_depth_range(model);
  if (distance_m < range.nearest_m || distance_m > range.farthest_m) {
    throw InputError("calibration target: at " + mm(distance_m) + " the stripe would lie outside the image; this " +
                     "sensor sees it on a target from " + mm(range.nearest_m) + " to " +
                     (std::isfinite(range.farthest_m) ? mm(range.farthest_m) : std::string("infinity")));
  }
  Scene scene;
  scene.terrain.base_elevation_m = 0.0;
  scene.terrain.reflectance = 0.3;
  const Eigen::Vector3d camera = sensor_origin_in_map(pose, parameters.mount);
  const Eigen::Vector3d heading(std::cos(pose.yaw_rad), std::sin(pose.yaw_rad), 0.0);
  const double thickness_m = 0.05;
  BoxObject wall;
  wall.name = "target";
  const Eigen::Vector3d centre = camera + (distance_m + 0.5 * thickness_m) * heading;
  wall.center_x_m = centre.x();
  wall.center_y_m = centre.y();
  wall.length_m = thickness_m;
  wall.width_m = 4.0;
  wall.height_m = camera.z() + 2.0;
  wall.yaw_rad = pose.yaw_rad;
  wall.reflectance = calibration_target_reflectance;
  scene.terrain.min_x_m = std::min(camera.x(), centre.x()) - 3.0;
  scene.terrain.max_x_m = std::max(camera.x(), centre.x()) + 3.0;
  scene.terrain.min_y_m = std::min(camera.y(), centre.y()) - 3.0;
  scene.terrain.max_y_m = std::max(camera.y(), centre.y()) + 3.0;
  scene.boxes.push_back(wall);
  scene.validate();
  return scene;
}

}  // namespace stridemap
