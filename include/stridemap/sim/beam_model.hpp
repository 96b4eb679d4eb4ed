#pragma once
// How one laser beam meets the scene and what returns to the receiver,
// before the sensor's electronics add their errors. This is the seam for
// mixed pixels: SingleRayBeamModel casts one ray along the beam axis; a
// footprint model samples the beam's cross-section with sub-rays
// and sums their phasors, reading a range between, before or behind the
// surfaces it touched. UrgSimulator applies systematic error, noise,
// dropouts and quantisation to whatever echo the model returns.
#include <cstdint>
#include <optional>
#include <random>

#include <Eigen/Core>

#include "stridemap/sim/scene_ray_caster.hpp"

namespace stridemap {

/// Ground-truth label of a simulated beam; the filters never see it.
enum class BeamLabel : std::uint8_t {
  clean,    ///< the range belongs to a surface the beam touched
  mixed,    ///< the range is far from every surface the footprint touched
  dropped,  ///< the sensor reported an error code instead of a range
};

/// One beam in the map frame. The three axes form a right-handed frame:
/// direction x sweep_axis = plane_normal.
struct BeamRequest {
  Eigen::Vector3d origin_m = Eigen::Vector3d::Zero();  ///< sensor origin
  Eigen::Vector3d direction = Eigen::Vector3d::UnitX();  ///< unit beam axis
  /// Unit vector in the scan plane, perpendicular to the beam, pointing the
  /// way the mirror turns (towards the next step): the axis the footprint is
  /// smeared along during one measurement.
  Eigen::Vector3d sweep_axis = Eigen::Vector3d::UnitY();
  Eigen::Vector3d plane_normal = Eigen::Vector3d::UnitZ();  ///< unit normal of the scan plane
  double step_angle_rad = 0.0;  ///< angle between neighbouring beams [rad]
  double max_range_m = 0.0;     ///< surfaces farther than this return nothing [m]
};

/// What reaches the receiver.
struct BeamEcho {
  bool has_return = false;  ///< false: no surface within max_range_m
  double range_m = 0.0;     ///< range the phase says (single ray: the true range) [m]
  /// Returned modulation amplitude, normalised so that a white Lambertian
  /// target (reflectance 1) seen head-on at 1 m gives 1.
  double amplitude = 0.0;
  /// clean or mixed; the simulator turns error codes into dropped.
  BeamLabel label = BeamLabel::clean;
  /// Set when the model decides that the sensor itself rejects the beam
  /// (e.g. code 8, "intensity difference of two waves", when the two
  /// modulation frequencies disagree): sent as the raw value unchanged, and
  /// the beam is labelled dropped. Must be below 20 (a code, not a range).
  std::optional<std::uint32_t> sensor_error_code;
};

/// Lambertian return of a surface: reflectance * cos(incidence) / range^2,
/// in the normalisation of BeamEcho::amplitude. Non-positive cosines (the
/// back of a surface) return nothing.
double lambertian_amplitude(double reflectance, double cos_incidence, double range_m);

class BeamModel {
 public:
  virtual ~BeamModel() = default;
  /// Called once per beam from UrgSimulator::scan, in beam order. rng is
  /// the scan's generator (seeded per scan), for models that sample.
  /// Implementations may keep scratch storage but must not allocate once it
  /// has grown.
  virtual BeamEcho trace(const SceneRayCaster& scene, const BeamRequest& beam, std::mt19937_64& rng) = 0;
  /// The label the most recently traced beam would get had its phase read
  /// range_m instead (UrgSimulator asks it when the receiver shifts a
  /// reading): mixed when range_m is farther than the model's tolerance
  /// from every surface the beam touched.
  virtual BeamLabel label_for_range(double range_m) const = 0;
  /// Whether UrgSimulator applies the receiver's range-intensity coupling
  /// (UrgSimOptions::receiver) to this model's echoes. The coupling is part
  /// of the mixed-measurement physics, so a model of the ideal sensor says
  /// no (SingleRayBeamModel by default): "mixed pixels off" stays free of
  /// readings off their surface.
  virtual bool takes_receiver_coupling() const { return true; }
};

/// SingleRayBeamModel's tolerance for label_for_range [m]: the footprint
/// model's default (FootprintBeamOptions::mixed_tolerance_m).
inline constexpr double single_ray_mixed_tolerance_m = 0.015;

/// The beam as an infinitely thin ray: the echo of the nearest surface on
/// its axis. Labels clean, unless the receiver's coupling (which it takes
/// only when constructed with_receiver_coupling) moves a reading off it.
class SingleRayBeamModel final : public BeamModel {
 public:
  explicit SingleRayBeamModel(bool with_receiver_coupling = false) : with_receiver_coupling_(with_receiver_coupling) {}
  BeamEcho trace(const SceneRayCaster& scene, const BeamRequest& beam, std::mt19937_64& rng) override;
  BeamLabel label_for_range(double range_m) const override;
  bool takes_receiver_coupling() const override { return with_receiver_coupling_; }

 private:
  bool with_receiver_coupling_ = false;
  double last_range_m_ = 0.0;
};

}  // namespace stridemap
