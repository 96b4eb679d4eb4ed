#pragma once
// The pose the mapper is given while the robot walks: an estimate, never the
// truth (paper sections 5.2, 6.2). As on Messor in the rocky-mockup run:
//
// - pitch and roll from the IMU: truth + a constant bias + white noise;
// - horizontal position and yaw from an external (ceiling) camera: truth +
//   white noise;
// - the sensor height d_z from leg kinematics: the trunk's true height
//   above its feet + white noise (as height_change_m);
// - the reference elevation h_ref read from the map already built, at the
//   feet: eq. (9)'s h_m = z_m + d_z + h_ref.
//
// The simulator scans with the true pose; only the mapper sees this one.
// Every error is an option with a documented default; scaled() gives the
// sweeps of the rocky-walk experiment.
#include <array>
#include <cstdint>
#include <numbers>
#include <random>
#include <utility>
#include <string>

#include "stridemap/core/enum_names.hpp"
#include "stridemap/core/grid_map.hpp"
#include "stridemap/core/pose.hpp"
#include "stridemap/sim/trunk_motion.hpp"

namespace stridemap {

/// Where h_ref comes from.
enum class ReferenceElevationSource : std::uint8_t {
  /// The map at the estimated feet (section 5.2), its elevation layer:
  /// eq. (10)'s highest reading. The default. That reading lies above the
  /// surface by the range noise, and the robot standing on it carries the
  /// bias into everything it measures next: h_ref creeps up as it walks.
  map,
  /// The map at the estimated feet, each cell's mean of the readings eq. (9)
  /// accepted (ElevationMap::mean_elevation): no bias from the noise, so only
  /// the pose errors feed back. Ours, measured against `map`.
  map_mean,
  truth,  ///< the true ground under the feet: a walk with a perfect h_ref
  /// The map at the estimated feet, its fused layer (core/height_fusion.hpp:
  /// variance-weighted readings behind a Mahalanobis gate). The map must
  /// have the layer (the walk declares it and feeds it). Ours.
  map_fused,
  /// Trunk z from leg kinematics + IMU (ours): the stance feet's soles
  /// placed with the kinematics and the IMU's attitude; each foot's
  /// foothold height set when it lands, from the leg odometry's prediction
  /// (the trunk's height less the foot's kinematic depth) fused with the
  /// fused layer under the sole; the trunk stands above its stance feet by
  /// their kinematic depths. Needs the fused layer, like map_fused.
  legs,
  /// The fused layer read where the stance feet really stand (ours): each
  /// stance foot's sole placed with the leg kinematics (encoder noise) and
  /// the estimated pose, averaged over the stance; the trunk stands above
  /// each foothold by that foot's kinematic depth. The feet are weighted by
  /// the layer's variance and the spread of heights under the sole, and a
  /// foot that disagrees with the others beyond a Mahalanobis gate is left
  /// out; so is a sole under which fewer than half the cells are known (a
  /// shadow). With PoseErrorOptions::foothold_odometry, leg odometry
  /// carries the height between readings (no stance foot on known cells,
  /// for many steps under structured light): each foot's foothold is set as
  /// it lands from the estimate, and a reading that disagrees with the
  /// odometry beyond the gate is left out. Needs the fused_elevation and
  /// fused_variance layers.
  map_footholds,
};

/// One scan's error of the estimated trunk height (h_ref + d_z) against the
/// truth [m], split by where it came from: the parts add up to `error_m`.
/// Each map reading's share splits into the map's error under the true
/// sole, the sole misplaced (the map read where the estimate put it), and
/// the kinematic depth; the leg odometry's share is what the prediction
/// carried. The simulator knows the truth; a robot does not.
struct HeightReferenceError {
  double error_m = 0.0;
  double odometry_m = 0.0;
  double map_m = 0.0;
  double placement_m = 0.0;
  double kinematics_m = 0.0;
  int feet_read = 0;
};

/// True for the sources that read the map's fused_elevation layer.
constexpr bool reads_fused_layer(ReferenceElevationSource source) {
  return source == ReferenceElevationSource::map_fused || source == ReferenceElevationSource::legs ||
         source == ReferenceElevationSource::map_footholds;
}

inline constexpr EnumNameTable<ReferenceElevationSource, 6> kReferenceElevationSourceNames{{
    {ReferenceElevationSource::map, "map"},
    {ReferenceElevationSource::map_mean, "map-mean"},
    {ReferenceElevationSource::truth, "truth"},
    {ReferenceElevationSource::map_fused, "map-fused"},
    {ReferenceElevationSource::legs, "legs"},
    {ReferenceElevationSource::map_footholds, "map-footholds"},
}};
/// "map", "map-mean", "truth", "map-fused", "legs" or "map-footholds": the --reference word and
/// summary.json's.
constexpr std::string_view name(ReferenceElevationSource source) {
  return enum_name_in(kReferenceElevationSourceNames, source);
}
template <>
inline ReferenceElevationSource parse_enum_name<ReferenceElevationSource>(std::string_view text) {
  return enum_value_in(kReferenceElevationSourceNames, text, "a reference elevation source");
}

struct PoseErrorOptions {
  /// IMU pitch: standard deviation of the white noise per scan, and a bias
  /// held for the whole walk [rad]. Defaults keep |bias| + 3 sigma (0.9 deg)
  /// within the 1 deg that the mapper's UpdateOptions assume as the
  /// maximum pitch/roll error in eq. (6). The bias is negative (the IMU
  /// reads the nose higher than it is, which lifts the points ahead): the
  /// sign is arbitrary, and this one does not hide the upward drift of an
  /// h_ref read from the map, which the opposite sign would partly cancel
  /// (docs/experiments.md shows both).
  double imu_pitch_noise_sigma_rad = 0.2 * std::numbers::pi / 180.0;
  double imu_pitch_bias_rad = -0.3 * std::numbers::pi / 180.0;
  /// IMU roll, likewise [rad]; the bias lifts the left side.
  double imu_roll_noise_sigma_rad = 0.2 * std::numbers::pi / 180.0;
  double imu_roll_bias_rad = 0.3 * std::numbers::pi / 180.0;
  /// Camera: standard deviation of x and y (each) [m]. 3 mm: about one
  /// pixel of a VGA ceiling camera that sees the 2 x 2 m mock-up.
  double camera_position_noise_sigma_m = 0.003;
  /// Camera: standard deviation of the yaw [rad]; 0.3 deg, the angle a
  /// one-pixel error subtends across a landmark of 0.2 m.
  double camera_yaw_noise_sigma_rad = 0.3 * std::numbers::pi / 180.0;
  /// Leg kinematics: standard deviation of the trunk height above the feet
  /// [m]; 2 mm from joint-encoder resolution over the leg's length.
  double leg_height_noise_sigma_m = 0.002;
  ReferenceElevationSource reference = ReferenceElevationSource::map;
  /// With the `legs` reference: the standard deviation given to the fused
  /// layer's height under a foot as it lands, against the leg odometry's
  /// prediction [m]. Small trusts the map (and its h_ref loop), large the
  /// odometry (and the random walk of its encoder noise); infinity ignores
  /// the map. Not an error of the robot: scaled() keeps it.
  double foothold_map_sigma_m = 0.003;
  /// With the `map_footholds` reference: a stance foot whose trunk height
  /// differs from the other stance feet's by more than this many standard
  /// deviations is left out (> 0; infinity keeps every foot). Not an error
  /// of the robot: scaled() keeps it.
  double foothold_gate_sigmas = 2.5;
  /// With the `map_footholds` reference: leg odometry predicts the trunk's
  /// height and the feet's readings correct it (variance-weighted, gated
  /// against the prediction). Off: each scan's readings alone give the
  /// height and a scan without one keeps the last, while the ground under
  /// the robot may rise or fall. On suits a sensor that leaves the feet on
  /// unknown cells for long (structured light: the rocky walk's default);
  /// off, one that maps under the feet (the URG: its walks' 90th percentile
  /// is lower, the odometry's own drift not added).
  bool foothold_odometry = false;

  /// Every noise sigma and bias times `factor` (>= 0); the reference source
  /// is kept.
  PoseErrorOptions scaled(double factor) const;
  /// No error at all: every sigma and bias 0 and h_ref from the truth.
  static PoseErrorOptions none();
  /// Throws InputError "pose error options: <field>: <problem>" for a
  /// negative or non-finite sigma or a non-finite bias.
  void validate() const;
};

class PoseEstimator {
 public:
  /// Validates the options (and the gait, whose feet h_ref is read at).
  PoseEstimator(const PoseErrorOptions& options, const GaitOptions& gait, std::uint64_t seed);

  /// The estimate for a scan taken in `truth`. `map` is the map built so
  /// far (read for h_ref when the source is one of the map's; for
  /// `map_fused` and `legs` it must hold the fused_elevation layer, for
  /// `map_footholds` fused_variance too, else InputError). The noise comes from
  /// one generator seeded at construction, so the same seed and the same
  /// sequence of calls give the same estimates. Allocates nothing.
  TrunkPose estimate(const TrunkState& truth, const ElevationMap& map);

  /// Feet whose height the map gave in the last call (0 to 6); with fewer
  /// than 3 the previous h_ref was kept.
  int feet_read_from_map() const { return feet_from_map_; }
  /// The last call's trunk-height error by cause (`map_footholds` only;
  /// zeros otherwise).
  const HeightReferenceError& last_height_error() const { return height_error_; }
  const PoseErrorOptions& options() const { return options_; }

  /// Attitude biases known from a calibration (experiments/
  /// attitude_calibration.hpp), taken off every IMU reading [rad].
  void set_attitude_correction(double pitch_bias_rad, double roll_bias_rad) {
    pitch_correction_rad_ = pitch_bias_rad;
    roll_correction_rad_ = roll_bias_rad;
  }

 private:
  double foot_elevation(const ElevationMap& map, double x_m, double y_m, double fallback,
                        const float* fused) const;
  /// The `legs` reference: the trunk's height (reference point, h_ref + d_z)
  /// from the stance feet; updates the footholds.
  double trunk_height_from_legs(const TrunkState& truth, const TrunkPose& estimate, const ElevationMap& map,
                                const float* fused);

  /// Where the leg kinematics put stance foot `f` relative to the trunk
  /// reference point, in the map frame: measured from the true trunk with
  /// encoder noise (three draws), turned by the estimated attitude.
  /// `rotations` are the true and the estimated trunk rotation.
  Eigen::Vector3d foot_from_trunk_in_map(const TrunkState& truth, const std::pair<Eigen::Matrix3d, Eigen::Matrix3d>& rotations,
                                         std::size_t f);

  /// The trunk's height above the known footholds of the stance feet, each
  /// plus its kinematic depth, and its variance; false when no stance foot
  /// has a known foothold (outputs untouched).
  bool trunk_on_footholds(const TrunkState& truth, const std::array<double, 6>& depth_m, double& z_m,
                          double& variance_m2) const;

  /// The `map_footholds` reference: the trunk's height (h_ref + d_z) from
  /// the fused layer at the stance feet's soles (core/stance_height.hpp),
  /// or NaN when no stance foot stands on known cells.
  double trunk_height_from_footholds(const TrunkState& truth, const TrunkPose& estimate, const ElevationMap& map);

  /// A stance foot's sole as the kinematics place it, averaged over the
  /// scans of its stance (the foot does not move while it stands).
  struct SoleAverage {
    int scans = 0;
    Eigen::Vector2d sum_m = Eigen::Vector2d::Zero();
  };
  std::array<SoleAverage, 6> soles_{};

  /// A stance foot's foothold height as the estimator knows it.
  struct Foothold {
    bool known = false;
    double z_m = 0.0;
    double variance_m2 = 0.0;
  };
  std::array<Foothold, 6> footholds_{};
  double trunk_z_m_ = 0.0, trunk_variance_m2_ = 0.0;
  /// Where and when the trunk stood at the first scan on the current
  /// tripod, and the last scan's time: the climb rate across a switch.
  double stance_start_z_m_ = 0.0, stance_start_time_s_ = 0.0, last_time_s_ = 0.0;

  PoseErrorOptions options_;
  GaitOptions gait_;
  std::mt19937_64 rng_;
  std::normal_distribution<double> gaussian_{0.0, 1.0};
  /// A foot's sole: the known cells within this radius give its height.
  static constexpr double kFootRadius_m = 0.02;
  static constexpr int kMaxFootReach = 8;  ///< cells; bounds the scratch array
  /// The last h_ref (the true ground at the first scan: the map's zero is
  /// the ground the robot starts on).
  double reference_m_ = 0.0;
  bool started_ = false;
  int feet_from_map_ = 0;
  HeightReferenceError height_error_;
  double pitch_correction_rad_ = 0.0, roll_correction_rad_ = 0.0;
};

}  // namespace stridemap
