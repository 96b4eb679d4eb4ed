#pragma once
// Mixed pixels from the physics of a phase-shift (AMCW) scanner such as the
// Hokuyo URG-04LX (docs/mixed_pixels.md).
//
// The beam is not a ray: it has a Gaussian cross-section that grows with
// range, and the mirror turns by one step while a beam is measured. The model
// samples that smeared footprint with sub-rays; every sub-ray that meets a
// surface returns a modulated echo whose phasor is
//
//   w * A * exp(-j 4 pi f r / c)      (w: share of beam power, A: Lambertian
//                                      amplitude, r: range of the hit)
//
// and the receiver measures the phase of the SUM of all phasors, at a fine
// and at a coarse modulation frequency. The fine phase gives the range modulo
// c / (2 f_fine), the coarse phase picks the whole number of fine wavelengths.
// A footprint on one surface reads that surface; a footprint split between
// two surfaces reads between them, or - when the depth gap exceeds half the
// fine unambiguous range - in front of the near one or behind the far one.
//
// Whatever the model returns, UrgSimulator then adds systematic error, the
// range-intensity bias b(A) and noise, drops weak echoes (code 1) and
// quantises; this model only decides what the phase says.
#include <complex>
#include <cstdint>
#include <random>
#include <vector>

#include <Eigen/Core>

#include "stridemap/sim/beam_model.hpp"
#include "stridemap/sim/surface_texture.hpp"

namespace stridemap {

/// Speed of light in vacuum [m/s]; the sensor's range calibration absorbs
/// the 0.03 % by which light is slower in air.
inline constexpr double speed_of_light_m_per_s = 299'792'458.0;

/// Error code the URG-04LX sends for "intensity difference of two waves"
/// (SCIP 2.0 table; scip.md A.11).
inline constexpr std::uint32_t urg_code_two_wave_difference = 8;

/// When the sensor measures its two modulation frequencies.
enum class WaveTiming : std::uint8_t {
  /// Both frequencies from the whole measurement (all smear instants).
  simultaneous,
  /// The fine frequency during the first half of the step, the coarse one
  /// during the second half, while the mirror keeps turning: at an edge the
  /// two waves see different mixtures of the surfaces.
  sequential,
};

/// Parameters of the footprint model. Facts about the URG-04LX are marked
/// as such; everything else is an assumption (algorithms.md 4.1 lists what
/// is not published) chosen as explained on the field.
struct FootprintBeamOptions {
  /// Full divergence angle of the 1/e^2 beam diameter [rad]. The footprint
  /// diameter grows as sqrt(d0^2 + (theta r)^2) (Gaussian beam far from its
  /// waist). 9.5 mrad with d0 = 4 mm gives 19.4 mm at 2 m and 38.2 mm at
  /// 4 m, inside the product data (under 20 mm at 2 m, at most 40 mm at 4 m),
  /// reading its "beam diameter" as the 1/e^2 diameter. At the terrain
  /// ranges of the paper's mount (0.3-1 m) that is 5-10 mm.
  double beam_divergence_rad = 0.0095;
  /// 1/e^2 diameter of the beam where it leaves the sensor [m]. Not
  /// published; 4 mm is typical for a collimated laser-diode beam.
  double exit_diameter_m = 0.004;
  /// The cross-section is sampled on rings at k / footprint_rings of
  /// footprint_outer_radius (k = 0 .. footprint_rings) with 1 sub-ray at the
  /// centre and 6 k sub-rays on ring k: 2 rings give 19 sub-rays. Each ring
  /// carries the Gaussian power of the annulus between the midpoints to its
  /// neighbours (the outermost ring also the tail beyond). 0 = a single ray
  /// on the beam axis.
  int footprint_rings = 2;
  /// Radius of the outermost ring in units of the 1/e^2 radius: 1.0 puts it
  /// where the intensity has fallen to 13.5 %; the power beyond (13.5 %) is
  /// carried by that ring.
  double footprint_outer_radius = 1.0;
  /// Instants at which the footprint is sampled while the mirror turns by
  /// one step (BeamRequest::step_angle_rad along BeamRequest::sweep_axis),
  /// spread evenly over the step. The mirror turns through a step in about
  /// 98 us (100 ms per turn, 1024 steps), so the footprint is elongated by
  /// r * 6.1 mrad along the scan. The instants are placed so that the fine
  /// wave's measurement is centred on the beam's angle (with sequential
  /// timing it covers the first half of the step, so the step runs from
  /// about a quarter step before the beam angle to three quarters after): a
  /// sensor calibrated on flat targets reports the angle at which its range
  /// was measured.
  int smear_instants = 3;
  /// Fine modulation frequency [Hz]: sets the range resolution and the
  /// fine unambiguous range c / (2 f) = 3.0 m. Not published (the paper,
  /// citing Hokuyo, says only that there are two frequencies); 50 MHz is
  /// typical for phase-shift rangefinders of this class, and real URG-04LX
  /// logs agree: the 17 isolated points that read 2.2-2.9 m behind a depth
  /// jump of 0.3-1 m (shared/data/urg04lx_breezyslam) fit a mixture read
  /// one fine period too far only for a period between 2.90 and 3.06 m,
  /// i.e. 49-51.7 MHz (docs/mixed_pixels.md).
  double fine_frequency_hz = 50e6;
  /// Coarse modulation frequency [Hz]: its unambiguous range c / (2 f) =
  /// 22.0 m must exceed every range the sensor can see; 6.8 MHz is chosen
  /// because the URG's error code 0 reads "object possibly at 22 m", the
  /// range at which the coarse phase would wrap. Not published.
  double coarse_frequency_hz = 6.8e6;
  /// Sequential by default: the sensor is a single-receiver design and a
  /// frequency switch within one 98 us step is the cheap way to get two
  /// phases; this is an assumption (algorithms.md 4.3).
  WaveTiming wave_timing = WaveTiming::sequential;
  /// When the two waves' amplitudes differ by more than this factor (either
  /// way), the sensor rejects the beam with code 8 ("intensity difference of
  /// two waves"): the coarse phase no longer describes the same target as
  /// the fine one. A wave that received nothing counts as an infinite
  /// factor. Must be > 1; infinity disables the check (a wave without light
  /// then reads phase 0). The firmware's rule is not published. Real logs
  /// show code 8 at about 4 of 11 500 depth jumps of a horizontal scan
  /// (shared/data/urg04lx_breezyslam); with sequential timing a factor of 30
  /// gives a similar rate in a simulated room, a factor of 4 forty times
  /// more (docs/mixed_pixels.md). In practice it rejects beams where one
  /// wave saw (almost) nothing: a thin object against open space.
  double max_two_wave_amplitude_ratio = 30.0;
  /// Weakest wave amplitude the receiver detects (BeamEcho::amplitude
  /// units). The two waves are compared only when the stronger one reaches
  /// it; a beam whose waves are both weaker is a weak return, which
  /// UrgSimulator turns into code 1 by its own dropout threshold. 0.02 is
  /// that threshold's default (UrgSimOptions::dropout_amplitude_threshold);
  /// keep the two equal. Without this rule, a surface that leaves the
  /// traced range (BeamRequest::max_range_m) during one step would give
  /// code 8 instead of the code 1 its faint echo deserves.
  double detection_amplitude = 0.02;
  /// A beam is labelled mixed when its range (before the sensor's noise and
  /// systematic error) is farther than this from the range of EVERY surface
  /// point its sub-rays touched [m]. 15 mm: above the sensor's 10 mm
  /// accuracy below 1 m, so that a mixed label means an error the filters
  /// could in principle see. A footprint on one slanted surface spans a
  /// band of ranges; since every hit counts, a reading inside that band is
  /// clean whatever the tolerance.
  double mixed_tolerance_m = 0.015;
  /// Reflectance texture of the surfaces within the footprint: each sub-ray
  /// hit's echo is multiplied by the texture's gain at the hit point. On one
  /// surface it changes only the echo's strength; on a footprint split
  /// between two surfaces it moves the mixing proportion from beam to beam,
  /// so mixed readings along an edge scatter between the surfaces (the
  /// scatter of the paper's Fig. 14b). log_sigma = 0 turns it off.
  SurfaceTextureOptions texture{};

  /// Throws InputError "footprint beam model options: <field>: <problem>".
  void validate() const;
};

/// Apparent range and amplitude of a summed phasor at one frequency.
struct WaveReading {
  double range_m = 0.0;    ///< in [0, c / (2 f)); 0 for a zero phasor
  double amplitude = 0.0;  ///< |phasor|, in BeamEcho::amplitude's units
};

/// Phasor of one echo: amplitude * exp(-j 4 pi f r / c).
std::complex<double> echo_phasor(double range_m, double amplitude, double frequency_hz);
/// What a phase meter at frequency_hz reads from the sum of echo phasors.
WaveReading read_wave(std::complex<double> phasor_sum, double frequency_hz);
/// Coarse/fine unwrapping: fine_range_m + n c / (2 f_fine), n the whole
/// number that brings it nearest to coarse_range_m. A result below 0 is
/// possible (a fine reading just below its wrap with a coarse one near 0)
/// and means "non-measurable" to the sensor.
double unwrap_fine_with_coarse(double fine_range_m, double coarse_range_m, double fine_frequency_hz);

/// What the model saw on the last beam it traced, beyond the echo itself:
/// for tests, and for experiments that ask where mixed readings fall
/// relative to the surfaces (between them, in front, behind).
struct FootprintDiagnostics {
  int sub_ray_hits = 0;  ///< sub-ray hits over all instants (0: no return)
  double nearest_hit_m = 0.0;   ///< shortest range of a hit [m]
  double farthest_hit_m = 0.0;  ///< longest range of a hit [m]
  WaveReading fine, coarse;     ///< the two waves before unwrapping
};

class FootprintBeamModel final : public BeamModel {
 public:
  /// Validates the options (InputError) and lays out the sub-ray pattern.
  explicit FootprintBeamModel(const FootprintBeamOptions& options = {});

  /// Deterministic: rng is not used. Allocates nothing.
  BeamEcho trace(const SceneRayCaster& scene, const BeamRequest& beam, std::mt19937_64& rng) override;
  BeamLabel label_for_range(double range_m) const override;

  const FootprintBeamOptions& options() const { return options_; }
  /// Sub-rays per instant (19 with the defaults).
  int sub_rays_per_instant() const { return static_cast<int>(pattern_.size()); }
  /// 1/e^2 footprint diameter at a range [m].
  double footprint_diameter_m(double range_m) const;
  /// About the most recent trace() call.
  const FootprintDiagnostics& last_diagnostics() const { return last_; }

 private:
  struct SubRay {
    double u_sweep = 0, u_normal = 0;  ///< position in units of the 1/e^2 radius
    double power_share = 0;            ///< shares sum to 1 over the pattern
  };
  FootprintBeamOptions options_;
  std::vector<SubRay> pattern_;
  /// Per smear instant: its share of each wave's measurement (each column
  /// sums to 1 over the instants).
  std::vector<double> fine_share_, coarse_share_;
  /// Time within the step, as a fraction, at the fine wave's centre: the
  /// smear instants are placed so that this time is the beam's own angle.
  double fine_time_centre_ = 0.5;
  /// Scratch: range of every sub-ray hit of the current beam; sized once.
  std::vector<double> hit_ranges_m_;
  SurfaceTexture texture_;
  FootprintDiagnostics last_;
};

}  // namespace stridemap
