#pragma once
// Choosing a sensor mount (paper section 3.3 with Fig. 5, section 4.2 with
// Fig. 7): the robot walks straight through random step fields with a
// perfect pose, its trunk gliding level at the mount's height above the
// floor (the gait's speed, none of its jolts), and for each mount we
// measure what the paper argues with:
//
// - unobserved fraction: of the floor the sensor sweeps ahead of the robot
//   in the strip its feet use (|y| <= corridor_half_width_m) over the step
//   field, the share of cells no measurement ever reached (occlusions
//   behind blocks; no fill-in);
// - mean predicted height uncertainty: the error part of Delta z_max
//   (eq. 6 / eq. 8) averaged over the measured points in that strip;
// - stripe width: the lateral extent of one measurement's points within
//   stripe_max_range_m, averaged over measurements;
// - look-ahead: how far ahead of the trunk the measurements in the strip
//   lie (median per measurement, averaged);
// - URG only: the share of ranges to surfaces from -0.10 to +0.15 m that
//   fall in 0.2-0.9 m (urg_share_in_range_interval).
//
// and a score that combines them (MountScoreOptions). Results are from the
// simulator.
#include <cstdint>
#include <functional>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include <Eigen/Core>

#include "stridemap/core/progress.hpp"
#include "stridemap/experiments/walk.hpp"
#include "stridemap/experiments/walk_sensor.hpp"
#include "stridemap/sim/step_field.hpp"

namespace stridemap {

struct NamedMount {
  std::string name;
  SensorMount mount;
  /// Structured light only: the sheet angle beta [rad]; unset for the URG.
  std::optional<double> sheet_angle_rad;
};

/// Fig. 7: "fig7a" 16 cm / 15 deg, "fig7b" 26 cm / 20 deg, "fig7c" 26 cm /
/// 35 deg (the one Messor got).
std::vector<NamedMount> paper_urg_mounts();
/// Fig. 5 as we read it (the paper gives only the changes, not the base):
/// "fig5a" the base, beta = 60 deg, alpha = 0; "fig5b" beta reduced by
/// 10 deg to 50; "fig5c" the base tilted by alpha = 10 deg. Camera 0.174 m
/// high, Ragno's optics otherwise (sensors/structured_light.hpp). A base of
/// 55 deg, which would make Ragno's final 45 deg / 10 deg the two changes
/// together, leaves fig5b's stripe on flat ground below the image (row 506
/// of 480) at this height, so it cannot be the paper's base here.
std::vector<NamedMount> paper_structured_light_mounts();

/// How the score ranks mounts. A mount whose stripe is narrower than
/// min_stripe_width_m (the feet must all land on known ground, Fig. 4c:
/// Messor's middle feet stand 0.46 m apart) or whose look-ahead is shorter
/// than min_look_ahead_m (ahead of the front feet at 0.18 m) scores 0;
/// otherwise
///   score = (1 - unobserved) * share * 1 / (1 + mean uncertainty / uncertainty_scale_m)
/// with share the URG's favourable-range share (1 for structured light):
/// see everything, at ranges the sensor measures well, with small errors.
struct MountScoreOptions {
  double min_stripe_width_m = 0.5;
  double min_look_ahead_m = 0.25;
  double uncertainty_scale_m = 0.01;
};

struct MountAnalysisOptions {
  StepFieldOptions field{};
  int fields = 2;  ///< step fields walked per mount (seeds seed, seed + 1, ...)
  std::uint64_t seed = 1;
  GaitOptions gait{};
  double cell_size_m = 0.01;
  UpdateOptions update{};
  /// The strip of the feet [m].
  double corridor_half_width_m = 0.30;
  /// Floor farther than this from the sensor does not count as seen ground
  /// ahead [m]; 4 m, the URG's specified range.
  double max_ground_range_m = 4.0;
  /// Points within this range make the stripe width [m]; 0.9 m, the end of
  /// the URG's favourable interval.
  double stripe_max_range_m = 0.9;
  MountScoreOptions score{};
  /// The sweep: every height x every pitch (alpha), as the sensor's own
  /// mount otherwise (beta stays the base's for structured light).
  std::vector<double> sweep_heights_m;
  std::vector<double> sweep_pitches_rad;
  /// Told the mounts analysed so far (the named ones, then the sweep's).
  ProgressCallback progress{};

  /// Throws InputError for an empty sweep grid, a non-finite or negative
  /// option, fields < 1.
  void validate() const;
};

struct MountMetrics {
  NamedMount mount;
  bool sees_ground = false;  ///< false: no ray meets the floor ahead; the rest is 0
  double unobserved_fraction = 0.0;
  double mean_height_uncertainty_m = 0.0;
  double stripe_width_m = 0.0;
  double look_ahead_m = 0.0;
  std::optional<double> favourable_range_share;  ///< URG only
  std::size_t ground_cells = 0;                  ///< swept floor cells scored
  double score = 0.0;
};

struct MountAnalysisResult {
  std::string sensor;
  std::vector<MountMetrics> named;
  /// sweep(i, j): pitch i, height j (row-major in that order).
  std::vector<MountMetrics> sweep;
  std::size_t heights = 0, pitches = 0;
  /// Index into `sweep` of the best score (the first of equal ones).
  std::size_t best = 0;
  const MountMetrics& at(std::size_t pitch, std::size_t height) const { return sweep[pitch * heights + height]; }
};

/// Builds the sensor for one mount on one scene.
using MountSensorFactory =
    std::function<std::unique_ptr<WalkSensor>(const Scene& scene, const NamedMount& mount, const UpdateOptions& update)>;
/// The share the URG metric adds (nothing for sensors without one).
using MountRangeShare = std::function<std::optional<double>(const NamedMount& mount)>;

/// The named mounts, then the sweep. Each named mount is checked to see
/// the ground before any walk starts (InputError "sensor mount <name>:
/// ..."); sweep mounts that cannot are reported with sees_ground = false.
MountAnalysisResult run_mount_analysis(const std::vector<NamedMount>& named, const MountSensorFactory& make_sensor,
                                       const MountRangeShare& range_share, const MountAnalysisOptions& options);

/// The metrics of one mount (the walks over options.fields step fields).
MountMetrics analyse_mount(const NamedMount& mount, const MountSensorFactory& make_sensor,
                           const MountRangeShare& range_share, const MountAnalysisOptions& options);

}  // namespace stridemap
