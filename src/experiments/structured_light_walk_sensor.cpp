#include "stridemap/experiments/structured_light_walk_sensor.hpp"

#include <cmath>
#include <limits>

#include "stridemap/core/error.hpp"
#include "stridemap/core/sensor_transform.hpp"
#include "stridemap/sensors/structured_light_report.hpp"

namespace stridemap {
namespace {

PipelineOptions sl_pipeline_options(const StructuredLightParameters& parameters) {
  PipelineOptions p;
  p.sensor = SensorKind::structured_light;
  p.structured_light = parameters;
  p.mount = parameters.mount;
  return p;
}

}  // namespace

StructuredLightWalkSensor::StructuredLightWalkSensor(const Scene& scene, const StructuredLightWalkSensorOptions& options,
                                                     const UpdateOptions& update, std::uint64_t seed)
    : options_(options),
      update_(update),
      model_(options.parameters),
      floor_geometry_(Scene{}, options.parameters, options.geometry, seed),
      detector_(options.detector),
      image_(options.parameters.image_width_px, options.parameters.image_height_px),
      integrator_(sl_pipeline_options(options.parameters)) {
  if (!(std::isfinite(options_.frame_period_s) && options_.frame_period_s > 0.0)) {
    throw InputError("structured-light walk sensor: frame_period_s must be a positive number");
  }
  if (!(options_.min_confidence >= 0.0 && options_.min_confidence <= 1.0)) {
    throw InputError("structured-light walk sensor: min_confidence must lie in [0, 1]");
  }
  ground_stripe_report(model_, update_);  // a clear error when this mount cannot see the ground
  if (options_.pipeline == StripePipeline::image) {
    renderer_.emplace(scene, options_.parameters, options_.image, options_.geometry, seed);
  } else {
    simulator_.emplace(scene, options_.parameters, options_.geometry, seed);
  }
  for (int i = 0; i < options_.parameters.image_width_px; ++i) {
    column_rays_.push_back(column_emitter_direction(model_, i + 0.5));
  }
}

ScanStats StructuredLightWalkSensor::measure(const TrunkPose& truth, const TrunkPose& estimate, double,
                                             TerrainMapper& mapper) {
  if (renderer_) {
    renderer_->render(truth, image_.rgb, &truth_);
    detector_.detect(image_, detection_);
    detection_.pixels(pixels_, options_.min_confidence);
  } else {
    simulator_->simulate(truth, truth_);
    pixels_ = truth_.stripe;
  }
  // No time: as before the pipeline, the walk's frames come in order by construction.
  return integrator_.push(pixels_, std::nullopt, estimate, mapper).stats;
}

void StructuredLightWalkSensor::floor_trace(const TrunkPose& pose, double floor_elevation_m, double max_range_m,
                                            std::vector<Eigen::Vector2d>& out) const {
  // On a flat floor nothing hides the stripe: each column's emitter ray
  // meets the floor, and the camera sees that point if it lies in the image.
  out.assign(column_rays_.size(), Eigen::Vector2d::Constant(std::numeric_limits<double>::quiet_NaN()));
  const StructuredLightSensorPose sensor = floor_geometry_.sensor_pose(pose);
  const double cos_fan = std::cos(options_.geometry.fan_half_angle_rad);
  const double range_limit = std::min(max_range_m, options_.geometry.max_range_m);
  for (std::size_t i = 0; i < column_rays_.size(); ++i) {
    const Eigen::Vector3d& ray_c = column_rays_[i];
    // The fan's centre ray lies in the camera's y_c-z_c plane.
    if (std::sqrt(ray_c.y() * ray_c.y() + ray_c.z() * ray_c.z()) < cos_fan) continue;
    const Eigen::Vector3d dir = sensor.camera_axes_in_map * ray_c;
    if (dir.z() >= -1e-9) continue;
    const double range = (floor_elevation_m - sensor.emitter_origin_m.z()) / dir.z();
    if (range <= 0.0 || range > range_limit) continue;
    const Eigen::Vector3d point = sensor.emitter_origin_m + range * dir;
    const auto pixel = model_.project(sensor.to_camera(point));
    if (!pixel || !model_.in_image(pixel->x(), pixel->y())) continue;
    out[i] = point.head<2>();
  }
}

}  // namespace stridemap
