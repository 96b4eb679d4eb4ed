#include "stridemap/sim/structured_light_image.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>
#include <string>

#include "stridemap/core/error.hpp"
#include "stridemap/core/terrain_mapper.hpp"

namespace stridemap {
namespace {

// Beyond this many 1/e^2 half thicknesses from the sheet's centre plane the
// laser light is below 1e-21 of its peak.
constexpr double kSheetReach = 5.0;

void check(const char* field, std::optional<std::string> problem) {
  if (problem) throw InputError(std::string("structured light image options: ") + field + ": " + *problem);
}

std::optional<std::string> fraction(double value) {
  if (std::isfinite(value) && value >= 0.0 && value <= 1.0) return std::nullopt;
  return "must lie between 0 and 1, got " + scene_rules::format_number(value);
}

// Separable Gaussian blur with edges clamped; `out` and `in` must differ.
void gaussian_blur(const std::vector<float>& in, std::vector<float>& out, std::vector<float>& scratch, int width,
                   int height, double sigma_px) {
  out = in;
  if (!(sigma_px > 0.0)) return;
  const int radius = static_cast<int>(std::ceil(3.0 * sigma_px));
  std::vector<float> kernel(static_cast<std::size_t>(2 * radius + 1));
  double total = 0.0;
  for (int t = -radius; t <= radius; ++t) {
    kernel[static_cast<std::size_t>(t + radius)] = static_cast<float>(std::exp(-0.5 * t * t / (sigma_px * sigma_px)));
    total += kernel[static_cast<std::size_t>(t + radius)];
  }
  for (float& k : kernel) k = static_cast<float>(k / total);
  scratch.assign(in.size(), 0.0f);
  const auto at = [width](int x, int y) { return static_cast<std::size_t>(y) * width + x; };
  for (int y = 0; y < height; ++y) {
    for (int x = 0; x < width; ++x) {
      float sum = 0.0f;
      for (int t = -radius; t <= radius; ++t) {
        sum += kernel[static_cast<std::size_t>(t + radius)] * in[at(std::clamp(x + t, 0, width - 1), y)];
      }
      scratch[at(x, y)] = sum;
    }
  }
  for (int y = 0; y < height; ++y) {
    for (int x = 0; x < width; ++x) {
      float sum = 0.0f;
      for (int t = -radius; t <= radius; ++t) {
        sum += kernel[static_cast<std::size_t>(t + radius)] * scratch[at(x, std::clamp(y + t, 0, height - 1))];
      }
      out[at(x, y)] = sum;
    }
  }
}

}  // namespace

void StripeImageOptions::validate() const {
  check("ambient.illuminance_lux", scene_rules::non_negative(ambient.illuminance_lux));
  check("ambient.diffuse_fraction", fraction(ambient.diffuse_fraction));
  check("ambient.background_reflectance", fraction(ambient.background_reflectance));
  check("ambient.view_range_m", scene_rules::positive(ambient.view_range_m));
  check("laser.power_w", scene_rules::non_negative(laser.power_w));
  check("laser.half_thickness_m", scene_rules::positive(laser.half_thickness_m));
  check("laser.divergence_rad", scene_rules::non_negative(laser.divergence_rad));
  check("laser.red_lux_per_w_per_m2", scene_rules::non_negative(laser.red_lux_per_w_per_m2));
  check("laser.green_leak", fraction(laser.green_leak));
  check("laser.blue_leak", fraction(laser.blue_leak));
  check("camera.target_mean_dn", scene_rules::positive(camera.target_mean_dn));
  check("camera.auto_exposure_limit_lux", scene_rules::positive(camera.auto_exposure_limit_lux));
  const auto within = [](double value, bool ok, const char* range) -> std::optional<std::string> {
    if (ok) return std::nullopt;
    return std::string("must be ") + range + ", got " + std::to_string(value);
  };
  check("camera.highlight_limit_dn",
        within(camera.highlight_limit_dn, camera.highlight_limit_dn >= 0.0 && camera.highlight_limit_dn <= 255.0,
               "from 0 (off) to 255 DN"));
  check("camera.highlight_fraction",
        within(camera.highlight_fraction, camera.highlight_fraction > 0.0 && camera.highlight_fraction < 1.0,
               "above 0 and below 1"));
  check("camera.fixed_gain_dn_per_lux", scene_rules::positive(camera.fixed_gain_dn_per_lux));
  check("camera.electrons_per_dn", scene_rules::positive(camera.electrons_per_dn));
  check("camera.read_noise_dn", scene_rules::non_negative(camera.read_noise_dn));
  check("camera.psf_sigma_px", scene_rules::non_negative(camera.psf_sigma_px));
  if (camera.sub_rows < 1 || camera.sub_rows > 64) {
    check("camera.sub_rows", "must be a whole number from 1 to 64, got " + std::to_string(camera.sub_rows));
  }
}

StructuredLightImageRenderer::StructuredLightImageRenderer(const Scene& scene,
                                                           const StructuredLightParameters& parameters,
                                                           const StripeImageOptions& options,
                                                           const StructuredLightSimOptions& geometry,
                                                           std::uint64_t seed)
    : geometry_(scene, parameters, geometry, seed), options_(options), seed_(seed) {
  options_.validate();
}

void StructuredLightImageRenderer::set_ambient(const AmbientLight& ambient) {
  StripeImageOptions changed = options_;
  changed.ambient = ambient;
  changed.validate();
  options_ = changed;
}

void StructuredLightImageRenderer::reset(std::uint64_t seed) {
  seed_ = seed;
  frame_index_ = 0;
  geometry_.reset(seed);
}

StructuredLightImageRenderer::SurfaceSample StructuredLightImageRenderer::sample(
    const StructuredLightSensorPose& sensor, double u_px, double v_px) const {
  const StructuredLightModel& model = geometry_.model();
  const double column_factor = 1.0 - 2.0 * u_px / model.parameters().image_width_px;
  const double row_factor = 1.0 - 2.0 * v_px / model.parameters().image_height_px;
  // The pinhole ray that eq. (1) inverts: y_c = -z_c n_v tan(tau_c).
  const Eigen::Vector3d in_camera(column_factor * model.tan_half_fov_horizontal(),
                                  -row_factor * model.tan_half_fov_vertical(), 1.0);
  const Eigen::Vector3d direction = sensor.camera_axes_in_map * in_camera.normalized();
  SurfaceSample out;
  if (const auto hit = geometry_.ray_caster().cast(sensor.camera_origin_m, direction, options_.ambient.view_range_m)) {
    out.point = hit->point_m;
    out.normal = hit->normal;
    out.reflectance = hit->reflectance;
    out.hit = true;
  }
  return out;
}

double StructuredLightImageRenderer::laser_irradiance(const StructuredLightSensorPose& sensor,
                                                      const SurfaceSample& s) const {
  if (!s.hit) return 0.0;
  const LaserStripeOptions& laser = options_.laser;
  const Eigen::Vector3d to_point = s.point - sensor.emitter_origin_m;
  const double range = to_point.norm();
  if (!(range > 0.0) || range > geometry_.options().max_range_m) return 0.0;
  const Eigen::Vector3d direction = to_point / range;
  const double thickness = std::hypot(laser.half_thickness_m, laser.divergence_rad * range);
  const double offset = sensor.sheet_distance_m(s.point);
  if (std::abs(offset) > kSheetReach * thickness) return 0.0;
  const Eigen::Vector3d in_camera = sensor.camera_axes_in_map.transpose() * direction;
  const double fan_half = geometry_.options().fan_half_angle_rad;
  if (!(in_camera.z() > 0.0) || std::abs(in_camera.x()) > std::tan(fan_half) * std::hypot(in_camera.y(), in_camera.z())) {
    return 0.0;
  }
  const double cos_incidence = -s.normal.dot(direction);
  if (!(cos_incidence > 0.0)) return 0.0;
  const double tolerance = geometry_.options().occlusion_tolerance_m;
  if (geometry_.ray_caster().cast(sensor.emitter_origin_m, direction, range - tolerance)) return 0.0;
  const double line_density_w_per_m = laser.power_w / (2.0 * fan_half * range);
  const double peak_per_m = std::sqrt(2.0 / std::numbers::pi) / thickness;
  return line_density_w_per_m * peak_per_m * std::exp(-2.0 * offset * offset / (thickness * thickness)) * cos_incidence;
}

StripeImageStats StructuredLightImageRenderer::render(const TrunkPose& pose, std::vector<std::uint8_t>& rgb,
                                                      StructuredLightFrameTruth* truth) {
  if (!pose_is_finite(pose)) {
    throw InputError("structured light image: the pose of frame " + std::to_string(frame_index_) +
                     " has a non-finite field");
  }
  if (truth) geometry_.simulate(pose, *truth);
  rng_.seed(mix_seed(seed_ ^ mix_seed(frame_index_) ^ 0x5EED1A5E));
  ++frame_index_;

  const StructuredLightParameters& p = geometry_.model().parameters();
  const int width = p.image_width_px, height = p.image_height_px;
  const std::size_t pixels = static_cast<std::size_t>(width) * static_cast<std::size_t>(height);
  const StructuredLightSensorPose sensor = geometry_.sensor_pose(pose);
  const AmbientLight& ambient = options_.ambient;
  const LaserStripeOptions& laser = options_.laser;
  const CameraSensorOptions& camera = options_.camera;
  samples_.resize(pixels);
  ambient_.resize(pixels);
  sheet_distance_m_.resize(pixels);
  half_thickness_m_.resize(pixels);
  laser_.assign(pixels, 0.0f);

  for (int k = 0; k < height; ++k) {
    for (int i = 0; i < width; ++i) {
      const std::size_t at = static_cast<std::size_t>(k) * width + i;
      const SurfaceSample s = sample(sensor, i + 0.5, k + 0.5);
      samples_[at] = s;
      double signal = ambient.background_reflectance * ambient.illuminance_lux * ambient.diffuse_fraction;
      if (s.hit) {
        const double shade = ambient.diffuse_fraction + (1.0 - ambient.diffuse_fraction) * std::max(0.0, s.normal.z());
        signal = s.reflectance * ambient.illuminance_lux * shade;
        sheet_distance_m_[at] = static_cast<float>(sensor.sheet_distance_m(s.point));
        const double range = (s.point - sensor.emitter_origin_m).norm();
        half_thickness_m_[at] = static_cast<float>(std::hypot(laser.half_thickness_m, laser.divergence_rad * range));
      }
      ambient_[at] = static_cast<float>(signal);
    }
  }

  // Laser light, integrated over the pixel's height where the sheet passes:
  // near its centre plane, or where it crosses between two rows.
  const int sub_rows = camera.sub_rows;
  for (int k = 0; k < height; ++k) {
    for (int i = 0; i < width; ++i) {
      const std::size_t at = static_cast<std::size_t>(k) * width + i;
      if (!samples_[at].hit) continue;
      const double d = sheet_distance_m_[at];
      bool near = std::abs(d) < kSheetReach * half_thickness_m_[at];
      for (int neighbour : {k - 1, k + 1}) {
        if (near || neighbour < 0 || neighbour >= height) continue;
        const std::size_t n = static_cast<std::size_t>(neighbour) * width + i;
        near = samples_[n].hit && (d > 0.0) != (sheet_distance_m_[n] > 0.0);
      }
      if (!near) continue;
      double sum = 0.0;
      for (int j = 0; j < sub_rows; ++j) {
        const SurfaceSample s = sub_rows == 1 ? samples_[at] : sample(sensor, i + 0.5, k + (j + 0.5) / sub_rows);
        sum += laser_irradiance(sensor, s) * s.reflectance;
      }
      laser_[at] = static_cast<float>(sum / sub_rows * laser.red_lux_per_w_per_m2);
    }
  }
  gaussian_blur(laser_, blurred_, blur_scratch_, width, height, camera.psf_sigma_px);

  StripeImageStats stats;
  double green_sum = 0.0;
  for (std::size_t at = 0; at < pixels; ++at) green_sum += ambient_[at] + laser.green_leak * blurred_[at];
  stats.mean_green_signal_lux = green_sum / static_cast<double>(pixels);
  if (camera.auto_exposure) {
    const double max_gain = camera.target_mean_dn / (0.5 * camera.auto_exposure_limit_lux);
    stats.gain_dn_per_lux =
        stats.mean_green_signal_lux > 0.0 ? std::min(max_gain, camera.target_mean_dn / stats.mean_green_signal_lux)
                                          : max_gain;
    if (camera.highlight_limit_dn > 0.0) {
      highlight_scratch_.assign(ambient_.begin(), ambient_.end());
      const auto rank = static_cast<std::ptrdiff_t>((1.0 - camera.highlight_fraction) *
                                                    static_cast<double>(highlight_scratch_.size() - 1));
      std::nth_element(highlight_scratch_.begin(), highlight_scratch_.begin() + rank, highlight_scratch_.end());
      const double highlight_lux = highlight_scratch_[static_cast<std::size_t>(rank)];
      if (highlight_lux > 0.0) stats.gain_dn_per_lux = std::min(stats.gain_dn_per_lux, camera.highlight_limit_dn / highlight_lux);
    }
  } else {
    stats.gain_dn_per_lux = camera.fixed_gain_dn_per_lux;
  }

  last_gain_dn_per_lux_ = stats.gain_dn_per_lux;
  rgb.resize(3 * pixels);
  std::normal_distribution<double> gaussian(0.0, 1.0);
  const double leaks[3] = {1.0, laser.green_leak, laser.blue_leak};
  for (std::size_t at = 0; at < pixels; ++at) {
    stats.peak_laser_signal_lux = std::max(stats.peak_laser_signal_lux, static_cast<double>(blurred_[at]));
    if (blurred_[at] * stats.gain_dn_per_lux >= 1.0) ++stats.laser_pixels;
    bool saturated = false;
    for (int c = 0; c < 3; ++c) {
      double dn = stats.gain_dn_per_lux * (ambient_[at] + leaks[c] * blurred_[at]);
      if (camera.enable_noise) {
        const double electrons = std::max(0.0, dn * camera.electrons_per_dn);
        dn += std::sqrt(electrons) / camera.electrons_per_dn * gaussian(rng_) + camera.read_noise_dn * gaussian(rng_);
      }
      const double clipped = std::clamp(std::round(dn), 0.0, 255.0);
      saturated |= clipped >= 255.0;
      rgb[3 * at + c] = static_cast<std::uint8_t>(clipped);
    }
    stats.saturated_pixels += saturated;
  }
  return stats;
}

std::ptrdiff_t StructuredLightImageRenderer::last_frame_pixel(int u_px, int v_px) const {
  const StructuredLightParameters& p = geometry_.model().parameters();
  if (u_px < 0 || v_px < 0 || u_px >= p.image_width_px || v_px >= p.image_height_px) return -1;
  const std::size_t at = static_cast<std::size_t>(v_px) * p.image_width_px + u_px;
  return at < blurred_.size() && at < ambient_.size() ? static_cast<std::ptrdiff_t>(at) : -1;
}

double StructuredLightImageRenderer::laser_signal_dn(int u_px, int v_px) const {
  const std::ptrdiff_t at = last_frame_pixel(u_px, v_px);
  return at >= 0 ? last_gain_dn_per_lux_ * blurred_[static_cast<std::size_t>(at)] : 0.0;
}

double StructuredLightImageRenderer::laser_signal_to_noise(int u_px, int v_px) const {
  const std::ptrdiff_t at = last_frame_pixel(u_px, v_px);
  if (at < 0) return 0.0;
  const CameraSensorOptions& camera = options_.camera;
  const double laser_dn = last_gain_dn_per_lux_ * blurred_[static_cast<std::size_t>(at)];
  const double red_dn = last_gain_dn_per_lux_ * (ambient_[static_cast<std::size_t>(at)] + blurred_[static_cast<std::size_t>(at)]);
  const double noise_dn = std::sqrt(red_dn / camera.electrons_per_dn + camera.read_noise_dn * camera.read_noise_dn);
  if (!(noise_dn > 0.0)) return laser_dn > 0.0 ? std::numeric_limits<double>::infinity() : 0.0;
  return laser_dn / noise_dn;
}

}  // namespace stridemap
