#pragma once
// Simulated Hokuyo URG-04LX: casts every beam of a scan against a scene from
// the true pose and turns the echo into the raw value the sensor would send
// (millimetres, or an error code below 20), with the error model of
// research/algorithms.md 5.7:
//
//   r_out = r + e_sys(r) + b(A) + s_agc + n,  n ~ N(0, sigma(A)),
//           quantised to 1 mm
//
//   A        amplitude of the echo, reflectance * cos(incidence) / r^2,
//            normalised to 1 for a white target head-on at 1 m
//   e_sys    systematic error, a cubic in the true range (see below)
//   b(A)     range-intensity coupling, amplitude_bias_m_per_decade per
//            decade of weakening below noise_reference_amplitude (off by
//            default: its size for the URG is not published)
//   s_agc    range-intensity coupling through the receiver's gain control,
//            which lags one beam behind (sim/receiver_gain.hpp; on by
//            default, for beam models that take it: the footprint model,
//            not the ideal single ray): the first beam after an amplitude
//            step larger than the limiter's headroom reads behind (weaker)
//            or in front (stronger). A beam it moves farther than the beam
//            model's tolerance from every surface it touched is labelled
//            mixed.
//   sigma(A) range_noise_sigma_m * max(1, (noise_reference_amplitude / A)^0.5):
//            the phase noise of a shot-noise-limited receiver falls with the
//            square root of the collected signal, so weak returns (dark,
//            grazing or far targets) read noisier; strong returns stay at the
//            base sigma, the floor set by the electronics.
//
// Error codes: no surface within DMAX, or a range beyond DMAX after the
// errors -> 0 ("object possibly at 22 m", what a real unit sends facing
// nothing); A below dropout_amplitude_threshold -> 1 ("low intensity");
// a range below DMIN -> 19 ("non-measurable").
#include <array>
#include <cstdint>
#include <memory>
#include <random>
#include <vector>

#include "stridemap/core/pose.hpp"
#include "stridemap/sensors/urg04lx.hpp"
#include "stridemap/sim/beam_model.hpp"
#include "stridemap/sim/receiver_gain.hpp"
#include "stridemap/sim/scene.hpp"
#include "stridemap/sim/scene_ray_caster.hpp"

namespace stridemap {

/// Raw error codes the simulator emits (scip.md A.11).
inline constexpr std::uint32_t urg_code_no_return = 0;
inline constexpr std::uint32_t urg_code_weak_return = 1;
inline constexpr std::uint32_t urg_code_not_measurable = 19;

struct UrgSimOptions {
  /// Standard deviation of the range noise for strong returns [m]
  /// (algorithms.md 5.7: 3 mm below 1 m at high intensity).
  double range_noise_sigma_m = 0.003;
  /// Amplitude at and above which the noise stays at range_noise_sigma_m.
  /// 1 = a white target head-on at 1 m.
  double noise_reference_amplitude = 1.0;
  /// e_sys(r) = c0 + c1 r + c2 r^2 + c3 r^3, r the true range in metres,
  /// result in metres. The default reads 6 mm long at 0, crosses zero near
  /// 0.4 m, is 5.7 mm short at 1 m and -6.2 mm at 1.2 m, crosses zero again
  /// near 2.4 m and peaks at +14.8 mm near 4.6 m: at most 57 % of the spec
  /// envelope (10 mm to 1 m, 1 % beyond) from 20 mm to 5.6 m. Because the
  /// error is a small cubic of the true range, the correction as a cubic of
  /// the measured range (RangeCalibration, `stridemap calibrate-range`) is
  /// -e_sys to within e_sys * e_sys' (at most 0.13 mm, near zero range): the
  /// fit comes out close to the negated coefficients and corrects the
  /// systematic error to within 0.1 mm (tested).
  std::array<double, 4> systematic_error_coefficients{0.006, -0.021, 0.0105, -0.0012};
  /// Echoes with an amplitude below this become error code 1. 0.02 keeps a
  /// white target beyond DMAX and a grey (0.5) one to 5 m head-on, and drops
  /// grey ground seen at 85 deg incidence beyond about 1.5 m and a black
  /// (0.05) target head-on beyond about 1.6 m.
  double dropout_amplitude_threshold = 0.02;
  /// b(A) per decade of amplitude below noise_reference_amplitude [m];
  /// positive: weaker echoes read farther. 0 = off.
  double amplitude_bias_m_per_decade = 0.0;
  /// Range-intensity coupling through the AGC (on by default; enabled =
  /// false gives the readings of the simpler model without it).
  ReceiverGainOptions receiver{};
  /// true: round to the nearest millimetre, as the sensor does. false: the
  /// raw values are still whole millimetres (the wire format), but rounded
  /// stochastically (floor(r_mm + U[0, 1))), which is unbiased on average,
  /// for studies that must not see the quantisation steps.
  bool quantize_to_mm = true;
  bool enable_noise = true;
  bool enable_systematic_error = true;
  bool enable_dropouts = true;

  /// Throws InputError naming the field.
  void validate() const;
};

class UrgSimulator {
 public:
  /// Copies the scene; single-ray beam model.
  UrgSimulator(const Scene& scene, const UrgParameters& params, const UrgSimOptions& options,
               std::uint64_t seed);
  /// With another beam model (e.g. a footprint model for mixed pixels).
  UrgSimulator(const Scene& scene, const UrgParameters& params, const UrgSimOptions& options,
               std::uint64_t seed, std::unique_ptr<BeamModel> beam_model);

  /// Simulates one scan from the TRUE pose: out.values_mm gets one raw
  /// value per step first_step..last_step (cluster 1), labels (if given) one
  /// label per beam. Scan k (counting from 0 since construction or reset)
  /// draws its noise from a generator seeded by (seed, k) only, so the same
  /// seed and the same sequence of calls give identical output. Reuses the
  /// storage of out and labels.
  void scan(const TrunkPose& pose, const SensorMount& mount, double time_s, UrgRawScan& out,
            std::vector<BeamLabel>* labels = nullptr);

  /// Restarts the scan counter with a new seed.
  void reset(std::uint64_t seed);
  std::uint64_t scans_simulated() const { return scan_index_; }

  const Scene& scene() const { return caster_.scene(); }
  const UrgParameters& parameters() const { return params_; }
  const UrgSimOptions& options() const { return options_; }

  /// e_sys(range) of the options (0 when disabled) [m].
  double systematic_error_m(double true_range_m) const;
  /// sigma(A) of the options (0 when noise is disabled) [m].
  double noise_sigma_m(double amplitude) const;
  /// b(A) of the options [m].
  double amplitude_bias_m(double amplitude) const;

 private:
  SceneRayCaster caster_;
  UrgParameters params_;
  UrgSimOptions options_;
  std::unique_ptr<BeamModel> beam_model_;
  std::uint64_t seed_ = 0;
  std::uint64_t scan_index_ = 0;
  std::vector<double> cos_angle_, sin_angle_;  ///< per beam, sensor frame
  std::mt19937_64 rng_;
  ReceiverGain receiver_gain_;
};

}  // namespace stridemap
