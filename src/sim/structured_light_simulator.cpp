#include "stridemap/sim/structured_light_simulator.hpp"

#include <cmath>
#include <string>

#include "stridemap/core/error.hpp"
#include "stridemap/core/sensor_transform.hpp"

namespace stridemap {
namespace {

void check_projector_option(const char* field, std::optional<std::string> problem) {
  if (problem) throw InputError(std::string("structured light simulator options: ") + field + ": " + *problem);
}

}  // namespace

std::uint64_t mix_seed(std::uint64_t x) {
  x += 0x9E3779B97F4A7C15ULL;
  x = (x ^ (x >> 30)) * 0xBF58476D1CE4E5B9ULL;
  x = (x ^ (x >> 27)) * 0x94D049BB133111EBULL;
  return x ^ (x >> 31);
}

const char* to_string(StripeColumnLabel label) {
  switch (label) {
    case StripeColumnLabel::visible: return "visible";
    case StripeColumnLabel::no_surface: return "no surface";
    case StripeColumnLabel::hidden_from_camera: return "hidden from the camera";
    case StripeColumnLabel::outside_image: return "outside the image";
    case StripeColumnLabel::outside_fan: return "outside the fan";
  }
  return "unknown";
}

void StructuredLightSimOptions::validate() const {
  check_projector_option("max_range_m", scene_rules::positive(max_range_m));
  const double fan_deg = fan_half_angle_rad * 180.0 / std::numbers::pi;
  if (!(std::isfinite(fan_half_angle_rad) && fan_deg > 0.0 && fan_deg < 90.0)) {
    check_projector_option("fan_half_angle_rad",
                 "must lie strictly between 0 and 90 deg, got " + scene_rules::format_number(fan_deg) + " deg");
  }
  check_projector_option("row_noise_sigma_px", scene_rules::non_negative(row_noise_sigma_px));
  check_projector_option("occlusion_tolerance_m", scene_rules::non_negative(occlusion_tolerance_m));
}

Eigen::Vector3d column_emitter_direction(const StructuredLightModel& model, double u_px) {
  const double column_factor = 1.0 - 2.0 * u_px / model.parameters().image_width_px;
  return Eigen::Vector3d(column_factor * model.tan_half_fov_horizontal(), model.cot_sheet_angle(), 1.0).normalized();
}

StructuredLightSimulator::StructuredLightSimulator(const Scene& scene, const StructuredLightParameters& parameters,
                                                   const StructuredLightSimOptions& options, std::uint64_t seed)
    : caster_(scene), model_(parameters), options_(options), seed_(seed) {
  options_.validate();
}

void StructuredLightSimulator::reset(std::uint64_t seed) {
  seed_ = seed;
  frame_index_ = 0;
}

StructuredLightSensorPose StructuredLightSimulator::sensor_pose(const TrunkPose& pose) const {
  const StructuredLightParameters& p = model_.parameters();
  const Eigen::Matrix3d rotation = sensor_to_map_rotation(pose, p.mount);
  StructuredLightSensorPose out;
  out.camera_origin_m = sensor_origin_in_map(pose, p.mount);
  // Camera axes in the sensor frame (forward, left, up): x_c -> left,
  // y_c -> down, z_c -> forward (camera_to_sensor_frame).
  out.camera_axes_in_map.col(0) = rotation.col(1);
  out.camera_axes_in_map.col(1) = -rotation.col(2);
  out.camera_axes_in_map.col(2) = rotation.col(0);
  out.emitter_origin_m = out.camera_origin_m + out.camera_axes_in_map * Eigen::Vector3d(0.0, -p.baseline_m, 0.0);
  // The sheet's camera-frame normal (0, sin beta, -cos beta), as in
  // StructuredLightModel::distance_from_sheet_m.
  const double sin_beta = std::sin(p.sheet_angle_rad), cos_beta = std::cos(p.sheet_angle_rad);
  out.sheet_normal = out.camera_axes_in_map * Eigen::Vector3d(0.0, sin_beta, -cos_beta);
  out.sheet_offset_m = p.baseline_m * sin_beta - out.sheet_normal.dot(out.camera_origin_m);
  return out;
}

void StructuredLightSimulator::simulate(const TrunkPose& pose, StructuredLightFrameTruth& out) {
  if (!pose_is_finite(pose)) {
    throw InputError("structured light simulator: the pose of frame " + std::to_string(frame_index_) +
                     " has a non-finite field");
  }
  rng_.seed(mix_seed(seed_ ^ mix_seed(frame_index_)));
  ++frame_index_;
  std::normal_distribution<double> gaussian(0.0, 1.0);

  const StructuredLightParameters& p = model_.parameters();
  const int width = p.image_width_px;
  out.sensor = sensor_pose(pose);
  out.columns.assign(static_cast<std::size_t>(width), StripeColumnTruth{});
  out.stripe.clear();
  out.visible = out.no_surface = out.hidden_from_camera = out.outside_image = out.outside_fan = 0;
  const StructuredLightSensorPose& s = out.sensor;
  // The fan's centre ray lies in the camera's y_c-z_c plane; a column's ray
  // leaves it sideways by atan(|n_u| tan(gamma_c) sin(beta)).
  const double fan_limit = std::tan(options_.fan_half_angle_rad);
  const double sin_beta = std::sin(p.sheet_angle_rad);

  for (int i = 0; i < width; ++i) {
    StripeColumnTruth& column = out.columns[static_cast<std::size_t>(i)];
    column.u_px = i + 0.5;
    const double column_factor = 1.0 - 2.0 * column.u_px / width;
    if (std::abs(column_factor) * model_.tan_half_fov_horizontal() * sin_beta > fan_limit) {
      column.label = StripeColumnLabel::outside_fan;
      ++out.outside_fan;
      continue;
    }
    const Eigen::Vector3d direction = s.camera_axes_in_map * column_emitter_direction(model_, column.u_px);
    const std::optional<RayHit> lit = caster_.cast(s.emitter_origin_m, direction, options_.max_range_m);
    if (!lit) {
      column.label = StripeColumnLabel::no_surface;
      ++out.no_surface;
      continue;
    }
    column.point_m = lit->point_m;
    column.normal = lit->normal;
    column.reflectance = lit->reflectance;
    column.object_index = lit->object_index;
    column.emitter_range_m = lit->range_m;
    column.cos_incidence = -lit->normal.dot(direction);
    column.camera_point_m = s.to_camera(lit->point_m);
    const Eigen::Vector3d to_point = lit->point_m - s.camera_origin_m;
    column.camera_range_m = to_point.norm();
    const Eigen::Vector3d view = to_point / column.camera_range_m;
    column.cos_view = -lit->normal.dot(view);

    const std::optional<Eigen::Vector2d> pixel = model_.project(column.camera_point_m);
    if (!pixel || !model_.in_image(column.u_px, (*pixel)[1])) {
      column.label = StripeColumnLabel::outside_image;
      if (pixel) column.v_px = (*pixel)[1];
      ++out.outside_image;
      continue;
    }
    column.v_px = (*pixel)[1];
    bool hidden = !(column.cos_view > 0.0);
    if (!hidden) {
      const std::optional<RayHit> blocker =
          caster_.cast(s.camera_origin_m, view, column.camera_range_m - options_.occlusion_tolerance_m);
      hidden = blocker.has_value();
    }
    if (hidden) {
      column.label = StripeColumnLabel::hidden_from_camera;
      ++out.hidden_from_camera;
      continue;
    }
    column.label = StripeColumnLabel::visible;
    ++out.visible;
    double row = column.v_px;
    if (options_.row_noise_sigma_px > 0.0) row += options_.row_noise_sigma_px * gaussian(rng_);
    out.stripe.push_back({column.u_px, row});
  }
}

}  // namespace stridemap
