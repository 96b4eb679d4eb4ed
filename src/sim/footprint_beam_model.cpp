#include "stridemap/sim/footprint_beam_model.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>
#include <optional>
#include <string>

#include "stridemap/core/error.hpp"
#include "stridemap/sim/scene_problem.hpp"

namespace stridemap {
namespace {

void check_footprint_option(const char* field, std::optional<std::string> problem) {
  if (problem) throw InputError(std::string("footprint beam model options: ") + field + ": " + *problem);
}

std::optional<std::string> count_in(int value, int low, int high) {
  if (value >= low && value <= high) return std::nullopt;
  return "expected a whole number from " + std::to_string(low) + " to " + std::to_string(high) + ", got " +
         std::to_string(value);
}

double unambiguous_range_m(double frequency_hz) { return speed_of_light_m_per_s / (2.0 * frequency_hz); }

// Share of a Gaussian beam's power between radii a and b, in units of the
// 1/e^2 radius (intensity ~ exp(-2 rho^2), enclosed power 1 - exp(-2 rho^2)).
double gaussian_power_between(double a, double b) {
  const double outer = std::isinf(b) ? 0.0 : std::exp(-2.0 * b * b);
  return std::exp(-2.0 * a * a) - outer;
}

// Overlap of [a0, a1) and [b0, b1).
double overlap(double a0, double a1, double b0, double b1) { return std::max(0.0, std::min(a1, b1) - std::max(a0, b0)); }

}  // namespace

void FootprintBeamOptions::validate() const {
  check_footprint_option("beam_divergence_rad", scene_rules::non_negative(beam_divergence_rad));
  check_footprint_option("exit_diameter_m", scene_rules::non_negative(exit_diameter_m));
  // 30 rings are 2791 sub-rays per instant: far more than any use needs,
  // and a bound that keeps a typo from asking for billions of casts.
  check_footprint_option("footprint_rings", count_in(footprint_rings, 0, 30));
  check_footprint_option("footprint_outer_radius", scene_rules::positive(footprint_outer_radius));
  check_footprint_option("smear_instants", count_in(smear_instants, 1, 64));
  check_footprint_option("fine_frequency_hz", scene_rules::positive(fine_frequency_hz));
  check_footprint_option("coarse_frequency_hz", scene_rules::positive(coarse_frequency_hz));
  if (!(coarse_frequency_hz < fine_frequency_hz)) {
    throw InputError("footprint beam model options: coarse_frequency_hz: expected below fine_frequency_hz (" +
                     scene_rules::format_number(fine_frequency_hz) + "), got " +
                     scene_rules::format_number(coarse_frequency_hz));
  }
  if (wave_timing != WaveTiming::simultaneous && wave_timing != WaveTiming::sequential) {
    throw InputError("footprint beam model options: wave_timing: not one of simultaneous, sequential");
  }
  if (!(max_two_wave_amplitude_ratio > 1.0)) {  // also rejects NaN; infinity allowed
    throw InputError("footprint beam model options: max_two_wave_amplitude_ratio: expected a number above 1, got " +
                     scene_rules::format_number(max_two_wave_amplitude_ratio));
  }
  check_footprint_option("detection_amplitude", scene_rules::non_negative(detection_amplitude));
  check_footprint_option("mixed_tolerance_m", scene_rules::positive(mixed_tolerance_m));
  texture.validate();
}

std::complex<double> echo_phasor(double range_m, double amplitude, double frequency_hz) {
  const double phase = 4.0 * std::numbers::pi * frequency_hz * range_m / speed_of_light_m_per_s;
  return std::polar(amplitude, -phase);
}

WaveReading read_wave(std::complex<double> phasor_sum, double frequency_hz) {
  WaveReading reading;
  reading.amplitude = std::abs(phasor_sum);
  if (reading.amplitude == 0.0) return reading;
  // The echo lags: its phase is minus the argument of the phasor.
  double phase = -std::arg(phasor_sum);
  if (phase < 0.0) phase += 2.0 * std::numbers::pi;
  const double period_m = unambiguous_range_m(frequency_hz);
  reading.range_m = phase / (2.0 * std::numbers::pi) * period_m;
  // A phase of exactly 2 pi after the shift rounds to the period itself.
  if (reading.range_m >= period_m) reading.range_m -= period_m;
  return reading;
}

double unwrap_fine_with_coarse(double fine_range_m, double coarse_range_m, double fine_frequency_hz) {
  const double period_m = unambiguous_range_m(fine_frequency_hz);
  return fine_range_m + std::round((coarse_range_m - fine_range_m) / period_m) * period_m;
}

FootprintBeamModel::FootprintBeamModel(const FootprintBeamOptions& options)
    : options_((options.validate(), options)), texture_(options.texture) {
  const int rings = options_.footprint_rings;
  const auto ring_radius = [&](int k) {
    return rings == 0 ? 0.0 : options_.footprint_outer_radius * k / rings;
  };
  for (int k = 0; k <= rings; ++k) {
    const double inner = k == 0 ? 0.0 : 0.5 * (ring_radius(k - 1) + ring_radius(k));
    const double outer = k == rings ? std::numeric_limits<double>::infinity() : 0.5 * (ring_radius(k) + ring_radius(k + 1));
    const int count = k == 0 ? 1 : 6 * k;
    const double share = gaussian_power_between(inner, outer) / count;
    for (int j = 0; j < count; ++j) {
      const double angle = 2.0 * std::numbers::pi * j / count;
      pattern_.push_back({ring_radius(k) * std::cos(angle), ring_radius(k) * std::sin(angle), share});
    }
  }

  const int n = options_.smear_instants;
  fine_share_.assign(static_cast<std::size_t>(n), 0.0);
  coarse_share_.assign(static_cast<std::size_t>(n), 0.0);
  double fine_total = 0.0, coarse_total = 0.0;
  for (int k = 0; k < n; ++k) {
    const double t0 = static_cast<double>(k) / n, t1 = static_cast<double>(k + 1) / n;
    const bool sequential = options_.wave_timing == WaveTiming::sequential;
    const double fine = sequential ? overlap(t0, t1, 0.0, 0.5) : t1 - t0;
    const double coarse = sequential ? overlap(t0, t1, 0.5, 1.0) : t1 - t0;
    fine_share_[static_cast<std::size_t>(k)] = fine;
    coarse_share_[static_cast<std::size_t>(k)] = coarse;
    fine_total += fine;
    coarse_total += coarse;
  }
  for (double& s : fine_share_) s /= fine_total;
  for (double& s : coarse_share_) s /= coarse_total;
  // The reported beam angle belongs to the fine wave, which fixes the range:
  // a sensor whose angles are calibrated on flat targets centres them on
  // that wave's measurement. With sequential timing the fine wave sees the
  // first half of the step, so the step starts about a quarter step before
  // the beam angle.
  fine_time_centre_ = 0.0;
  for (int k = 0; k < n; ++k) fine_time_centre_ += fine_share_[static_cast<std::size_t>(k)] * (k + 0.5) / n;
  hit_ranges_m_.reserve(pattern_.size() * static_cast<std::size_t>(n));
}

double FootprintBeamModel::footprint_diameter_m(double range_m) const {
  return std::hypot(options_.exit_diameter_m, options_.beam_divergence_rad * range_m);
}

BeamEcho FootprintBeamModel::trace(const SceneRayCaster& scene, const BeamRequest& beam, std::mt19937_64& /*rng*/) {
  hit_ranges_m_.clear();
  std::complex<double> fine_sum(0.0, 0.0), coarse_sum(0.0, 0.0);
  const double waist_radius_m = 0.5 * options_.exit_diameter_m;
  const double half_divergence_rad = 0.5 * options_.beam_divergence_rad;
  const int instants = options_.smear_instants;

  for (int k = 0; k < instants; ++k) {
    const double offset_rad = ((k + 0.5) / instants - fine_time_centre_) * beam.step_angle_rad;
    const double c = std::cos(offset_rad), s = std::sin(offset_rad);
    const Eigen::Vector3d axis = c * beam.direction + s * beam.sweep_axis;
    const Eigen::Vector3d sweep = c * beam.sweep_axis - s * beam.direction;
    const double fine_share = fine_share_[static_cast<std::size_t>(k)];
    const double coarse_share = coarse_share_[static_cast<std::size_t>(k)];
    for (const SubRay& sub : pattern_) {
      // A skew ray: it starts on the waist at (u_sweep, u_normal) and leans
      // perpendicular to that offset, so its distance from the axis grows
      // as |u| sqrt(w0^2 + (theta z / 2)^2), exactly the Gaussian beam's
      // radius (a hyperboloid is ruled by straight lines).
      const Eigen::Vector3d start =
          beam.origin_m + waist_radius_m * (sub.u_sweep * sweep + sub.u_normal * beam.plane_normal);
      const Eigen::Vector3d direction =
          (axis + half_divergence_rad * (sub.u_sweep * beam.plane_normal - sub.u_normal * sweep)).normalized();
      const std::optional<RayHit> hit = scene.cast(start, direction, beam.max_range_m);
      if (!hit) continue;
      const double amplitude =
          sub.power_share * texture_.gain(hit->point_m, hit->object_index) *
          lambertian_amplitude(hit->reflectance, -hit->normal.dot(direction), hit->range_m);
      if (!(amplitude > 0.0)) continue;  // the back of a surface returns nothing
      hit_ranges_m_.push_back(hit->range_m);
      if (fine_share > 0.0) fine_sum += echo_phasor(hit->range_m, fine_share * amplitude, options_.fine_frequency_hz);
      if (coarse_share > 0.0) {
        coarse_sum += echo_phasor(hit->range_m, coarse_share * amplitude, options_.coarse_frequency_hz);
      }
    }
  }

  BeamEcho echo;
  last_ = FootprintDiagnostics{};
  if (hit_ranges_m_.empty()) return echo;
  echo.has_return = true;
  const WaveReading fine = read_wave(fine_sum, options_.fine_frequency_hz);
  const WaveReading coarse = read_wave(coarse_sum, options_.coarse_frequency_hz);
  const auto [nearest, farthest] = std::minmax_element(hit_ranges_m_.begin(), hit_ranges_m_.end());
  last_ = {static_cast<int>(hit_ranges_m_.size()), *nearest, *farthest, fine, coarse};
  echo.amplitude = fine.amplitude;
  echo.range_m = unwrap_fine_with_coarse(fine.range_m, coarse.range_m, options_.fine_frequency_hz);

  const double stronger = std::max(fine.amplitude, coarse.amplitude);
  const double weaker = std::min(fine.amplitude, coarse.amplitude);
  // Written as a product so that a wave without light (weaker = 0) trips
  // any finite limit and an infinite limit never trips.
  if (stronger >= options_.detection_amplitude && stronger > options_.max_two_wave_amplitude_ratio * weaker) {
    echo.sensor_error_code = urg_code_two_wave_difference;
    echo.label = BeamLabel::dropped;
    return echo;
  }

  echo.label = label_for_range(echo.range_m);
  return echo;
}

BeamLabel FootprintBeamModel::label_for_range(double range_m) const {
  double nearest_m = std::numeric_limits<double>::infinity();
  for (const double r : hit_ranges_m_) nearest_m = std::min(nearest_m, std::abs(range_m - r));
  return nearest_m > options_.mixed_tolerance_m ? BeamLabel::mixed : BeamLabel::clean;
}

}  // namespace stridemap
