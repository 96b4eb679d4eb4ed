#include "stridemap/sim/urg_simulator.hpp"

#include <algorithm>
#include <cmath>
#include <numbers>
#include <string>
#include <utility>

#include "stridemap/core/error.hpp"
#include "stridemap/core/sensor_transform.hpp"
#include "stridemap/sim/hash_mix.hpp"

namespace stridemap {
namespace {

// Amplitudes below this are treated as this, so that a zero echo (possible
// only with dropouts disabled) gives a large but finite noise.
constexpr double min_amplitude = 1e-9;

void check_urg_option(const char* field, std::optional<std::string> problem) {
  if (problem) throw InputError(std::string("URG simulator options: ") + field + ": " + *problem);
}

// The AGC cannot settle below the weakest echo the sensor measures; with
// dropouts off (threshold possibly 0) the floor is a tiny positive number.
double receiver_floor_amplitude(const UrgSimOptions& options) {
  options.validate();
  return std::max(options.dropout_amplitude_threshold, min_amplitude);
}

// The coupling acts only on echoes of a model that takes it (BeamModel::
// takes_receiver_coupling): the ideal single ray stays ideal.
ReceiverGainOptions receiver_for(const ReceiverGainOptions& receiver, const BeamModel* model) {
  ReceiverGainOptions used = receiver;
  used.enabled = receiver.enabled && model != nullptr && model->takes_receiver_coupling();
  return used;
}

}  // namespace

void UrgSimOptions::validate() const {
  check_urg_option("range_noise_sigma_m", scene_rules::non_negative(range_noise_sigma_m));
  check_urg_option("noise_reference_amplitude", scene_rules::positive(noise_reference_amplitude));
  for (std::size_t k = 0; k < systematic_error_coefficients.size(); ++k) {
    const std::string field = "systematic_error_coefficients[" + std::to_string(k) + "]";
    check_urg_option(field.c_str(), scene_rules::finite(systematic_error_coefficients[k]));
  }
  check_urg_option("dropout_amplitude_threshold", scene_rules::non_negative(dropout_amplitude_threshold));
  check_urg_option("amplitude_bias_m_per_decade", scene_rules::finite(amplitude_bias_m_per_decade));
  receiver.validate();
}

UrgSimulator::UrgSimulator(const Scene& scene, const UrgParameters& params, const UrgSimOptions& options,
                           std::uint64_t seed)
    : UrgSimulator(scene, params, options, seed, std::make_unique<SingleRayBeamModel>()) {}

UrgSimulator::UrgSimulator(const Scene& scene, const UrgParameters& params, const UrgSimOptions& options,
                           std::uint64_t seed, std::unique_ptr<BeamModel> beam_model)
    : caster_(scene),
      params_(params),
      options_(options),
      beam_model_(std::move(beam_model)),
      seed_(seed),
      receiver_gain_(receiver_for(options.receiver, beam_model_.get()), receiver_floor_amplitude(options)) {
  params_.validate();
  options_.validate();
  if (!beam_model_) throw InputError("URG simulator: no beam model given");
  const int beams = params_.beam_count();
  cos_angle_.resize(static_cast<std::size_t>(beams));
  sin_angle_.resize(static_cast<std::size_t>(beams));
  for (int i = 0; i < beams; ++i) {
    const double angle = params_.step_angle_rad(params_.first_step + i);
    cos_angle_[static_cast<std::size_t>(i)] = std::cos(angle);
    sin_angle_[static_cast<std::size_t>(i)] = std::sin(angle);
  }
}

void UrgSimulator::reset(std::uint64_t seed) {
  seed_ = seed;
  scan_index_ = 0;
}

double UrgSimulator::systematic_error_m(double r) const {
  if (!options_.enable_systematic_error) return 0.0;
  const auto& c = options_.systematic_error_coefficients;
  return c[0] + r * (c[1] + r * (c[2] + r * c[3]));
}

double UrgSimulator::noise_sigma_m(double amplitude) const {
  if (!options_.enable_noise) return 0.0;
  const double ratio = options_.noise_reference_amplitude / std::max(amplitude, min_amplitude);
  return options_.range_noise_sigma_m * std::sqrt(std::max(1.0, ratio));
}

double UrgSimulator::amplitude_bias_m(double amplitude) const {
  if (options_.amplitude_bias_m_per_decade == 0.0) return 0.0;
  const double ratio = options_.noise_reference_amplitude / std::max(amplitude, min_amplitude);
  return options_.amplitude_bias_m_per_decade * std::max(0.0, std::log10(ratio));
}

void UrgSimulator::scan(const TrunkPose& pose, const SensorMount& mount, double time_s, UrgRawScan& out,
                        std::vector<BeamLabel>* labels) {
  const std::size_t beams = cos_angle_.size();
  out.time_s = time_s;
  out.first_step = params_.first_step;
  out.cluster = 1;
  out.values_mm.resize(beams);
  if (labels) labels->resize(beams);

  rng_.seed(mix64(seed_ ^ mix64(scan_index_)));
  ++scan_index_;
  std::normal_distribution<double> gaussian(0.0, 1.0);
  std::uniform_real_distribution<double> dither(0.0, 1.0);

  const Eigen::Matrix3d rotation = sensor_to_map_rotation(pose, mount);
  BeamRequest request;
  request.origin_m = sensor_origin_in_map(pose, mount);
  request.plane_normal = rotation.col(2);
  request.step_angle_rad = 2.0 * std::numbers::pi / params_.steps_per_turn;
  // Trace a little beyond DMAX: the sensor's own errors may pull a surface
  // just beyond it back inside.
  request.max_range_m = params_.max_range_m * 1.02 + 0.05;
  const double min_mm = std::round(params_.min_range_m * 1000.0);
  const double max_mm = std::round(params_.max_range_m * 1000.0);
  receiver_gain_.begin_scan();

  if (!request.origin_m.allFinite() || !rotation.allFinite()) {
    throw InputError("URG simulator: the pose or mount of the scan at t = " + scene_rules::format_number(time_s) +
                     " s has a non-finite field");
  }
  for (std::size_t i = 0; i < beams; ++i) {
    const double c = cos_angle_[i], s = sin_angle_[i];
    request.direction = c * rotation.col(0) + s * rotation.col(1);
    request.sweep_axis = -s * rotation.col(0) + c * rotation.col(1);
    BeamEcho echo = beam_model_->trace(caster_, request, rng_);
    if (!echo.has_return) receiver_gain_.no_echo();

    std::uint32_t value = urg_code_no_return;
    BeamLabel label = BeamLabel::dropped;
    if (echo.sensor_error_code) {
      if (*echo.sensor_error_code >= 20) {
        throw InputError("URG simulator: the beam model returned error code " +
                         std::to_string(*echo.sensor_error_code) + " for beam " + std::to_string(i) +
                         "; codes are below 20");
      }
      value = *echo.sensor_error_code;
    } else if (echo.has_return && options_.enable_dropouts &&
               echo.amplitude < options_.dropout_amplitude_threshold) {
      receiver_gain_.shift_m(echo.amplitude);  // the AGC sees the faint echo too
      value = urg_code_weak_return;
    } else if (echo.has_return) {
      const double shift_m = receiver_gain_.shift_m(echo.amplitude);
      const double phase_range_m = echo.range_m + shift_m;
      // The beam model labels the range the light's phase says; the AGC's
      // shift belongs to the same mixed-measurement error, so the label is
      // asked again for the shifted range.
      if (shift_m != 0.0 && echo.label != BeamLabel::dropped) echo.label = beam_model_->label_for_range(phase_range_m);
      double range_m =
          phase_range_m + systematic_error_m(echo.range_m) + amplitude_bias_m(echo.amplitude);
      if (options_.enable_noise) range_m += noise_sigma_m(echo.amplitude) * gaussian(rng_);
      const double range_mm = range_m * 1000.0;
      const double rounded_mm = options_.quantize_to_mm ? std::round(range_mm) : std::floor(range_mm + dither(rng_));
      if (!std::isfinite(rounded_mm) || rounded_mm > max_mm) {
        value = urg_code_no_return;
      } else if (rounded_mm < min_mm) {
        value = urg_code_not_measurable;
      } else {
        value = static_cast<std::uint32_t>(rounded_mm);
        label = echo.label;
      }
    }
    out.values_mm[i] = value;
    if (labels) (*labels)[i] = label;
  }
}

}  // namespace stridemap
