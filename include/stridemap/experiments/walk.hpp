#pragma once
// A walking robot mapping as it goes (paper sections 5.1, 5.2, 6.2): the
// trunk follows a path with its gait (sim/trunk_motion.hpp), the sensor
// scans from the true pose, the mapper integrates with the estimate
// (sim/pose_estimate.hpp), and the local map moves with the robot on its
// circular buffer. For scoring, the local map is copied every few scans
// into a mosaic that covers the whole scene, so that what the robot knew of
// each cell before it left the window is kept; the area the sensor swept is
// traced on a flat floor at the robot's ground level.
//
// Results are from the simulator, not from a real robot.
#include <cstddef>
#include <cstdint>
#include <optional>
#include <vector>

#include "stridemap/config/mapper_config.hpp"
#include "stridemap/core/cas_filter.hpp"
#include "stridemap/core/height_fusion.hpp"
#include "stridemap/core/stance_height.hpp"
#include "stridemap/core/terrain_mapper.hpp"
#include "stridemap/core/weighted_median_fill.hpp"
#include "stridemap/experiments/cart_rail.hpp"
#include "stridemap/experiments/map_evaluation.hpp"
#include "stridemap/experiments/walk_sensor.hpp"
#include "stridemap/sim/pose_estimate.hpp"
#include "stridemap/sim/trunk_motion.hpp"

namespace stridemap {

struct WalkOptions {
  /// Seeds the pose-error noise (the sensor has its own seed).
  std::uint64_t seed = 1;
  GaitOptions gait{};
  PoseErrorOptions pose_errors{};
  /// The fused layer the estimator reads h_ref from when
  /// pose_errors.reference is map_fused (declared in the local map and fed
  /// every scan's points; unused otherwise).
  HeightFusionOptions height_fusion{};
  /// IMU biases known from a calibration before the walk
  /// (experiments/attitude_calibration.hpp), taken off every reading [rad].
  double imu_pitch_correction_rad = 0.0;
  double imu_roll_correction_rad = 0.0;
  /// Default: the paper's local map, 100 x 100 cells of 10 mm, following
  /// the robot. With follow_robot off the map instead covers the whole
  /// scene (a test bed view, as in the mount analysis) and is its own mosaic.
  MapperOptions mapper{};
  MapFilter map_filter = MapFilter::fill;
  FillOptions fill{};
  CasOptions cas{};
  /// Keep a mosaic of the whole scene (and the swept area) for scoring. Off
  /// for long runs that only exercise the map.
  bool build_mosaic = true;
  /// Copy the local map into the mosaic every this many scans (>= 1). The
  /// cells that leave the window are 0.5 m behind the robot, long out of
  /// the sensor's view, so a few scans' delay loses nothing.
  int mosaic_every_scans = 5;
  /// The swept area, the ground the walk is scored on: where the sensor's
  /// rays meet a flat floor at the robot's ground level within this range,
  /// inside the local map at that moment [m]. 0.9 m ends the URG's
  /// favourable interval (section 4.2), as in the cart-rail experiment.
  double swept_max_range_m = 0.9;
  /// Height of that floor: the robot's ground (the support plane under its
  /// feet, true), or the scene terrain's base elevation (for step fields,
  /// whose floor is flat while the robot climbs the blocks).
  enum class SweptFloor : std::uint8_t { robot_ground, scene_base };
  SweptFloor swept_floor = SweptFloor::robot_ground;
  /// Compute the ground truth of every cell and score the maps (off: the
  /// snapshots carry NaN truth and the scores stay empty; for analyses that
  /// only need which cells were seen).
  bool score_against_truth = true;
  MapScoreOptions score{};
  /// A cleared cell's height at most this far above the truth counts as
  /// having been right (wrongly lowered); more, as an artifact [m]. Twice
  /// the URG's 10 mm range error bound seen along a steep beam.
  double visibility_correct_m = 0.02;
};

/// RMS of estimate - truth over the walk's scans, per channel.
struct PoseErrorStats {
  double x_m = 0.0, y_m = 0.0, yaw_rad = 0.0, pitch_rad = 0.0, roll_rad = 0.0;
  /// Sensor height (h_ref + d_z): the error that moves every point up or down.
  double sensor_height_m = 0.0;
  double mean_sensor_height_m = 0.0;  ///< signed mean of that error
};

struct WalkResult {
  std::size_t scans = 0;
  double duration_s = 0.0, distance_m = 0.0, turned_rad = 0.0;
  MapperTotals mapper_totals;
  PoseErrorStats pose_errors;
  /// Scans during which the mapper used the turning term (a yaw change).
  std::size_t scans_with_yaw_change = 0;
  /// The final local map after the map filter, and its score on the swept
  /// cells inside it.
  MapSnapshot local;
  CellMask local_swept;
  MapScore local_score;
  /// The mosaic after the map filter, the swept area and the score (empty
  /// without build_mosaic).
  MapSnapshot mosaic;
  CellMask mosaic_swept;
  MapScore mosaic_score;
  /// The final map whole (the mosaic, or the local map without one), after
  /// the map filter, and the settings it was made with: what the run's
  /// map.smap holds (mapfile/map_file.hpp).
  ElevationMap map;
  MapperConfig map_config;
  /// Swept cells still unknown after the fill-in: the shadows behind
  /// obstacles (the scan line crossed them, no ray reached them).
  std::size_t unknown_swept_cells = 0;
  std::size_t filled_cells = 0;
  std::size_t cas_removed_cells = 0;
  /// The visibility clean-up (off unless the sensor has it on): cells it
  /// cleared, and of those the ones whose height was within
  /// WalkOptions::visibility_correct_m of the truth (wrongly lowered: the
  /// scene of a walk does not move) and the ones above it (artifacts).
  bool visibility_enabled = false;
  double visibility_correct_m = 0.0;  ///< WalkOptions::visibility_correct_m
  std::size_t visibility_cleared = 0;
  std::size_t visibility_wrongly_cleared = 0;
  std::size_t visibility_artifacts_cleared = 0;
  std::size_t visibility_cells_contradicted = 0;
  /// Scans the clean-up ran on, and those of them that took the row and
  /// column maxima from the whole map (the rest kept them from the scan
  /// before: docs/visibility.md, "What it costs").
  std::size_t visibility_scans = 0;
  std::size_t visibility_whole_map_scans = 0;
  /// The true trunk positions, one per scan (for drawing the path).
  std::vector<Eigen::Vector2d> trajectory;
  /// Per scan, the trunk-height error by cause (h_ref from `map_footholds`;
  /// empty otherwise).
  std::vector<HeightReferenceError> height_errors;
  /// The fused layer against the truth under the true stance soles
  /// (core/stance_height.hpp's reading, soles at least half known), summed
  /// over the scans with such a sole: what an h_ref read there inherits from
  /// the map alone. Kept by the walks that keep the fused layers, and by
  /// those with the true h_ref (the map's own error under the feet). 0
  /// scans otherwise.
  double fused_under_soles_error_sum_m = 0.0;
  std::size_t fused_under_soles_scans = 0;
};

/// Cells of a map holding a value the layers must never hold: a measured
/// cell with a non-finite elevation or a certainty outside (0, max], an
/// unknown cell with a number or a certainty, a filled cell with a NaN or a
/// certainty, a state out of range.
std::size_t count_invalid_cells(const ElevationMap& map, double certainty_max);

/// One walk, scan by scan (the long-run test drives it this way).
class WalkRun {
 public:
  /// Copies the scene; the sensor must outlive the run. Validates everything (gait, path
  /// inside the scene, pose errors, mapper options, the mount seeing the
  /// ground) before any scan: InputError.
  WalkRun(const Scene& scene, const WalkPath& path, WalkSensor& sensor, const WalkOptions& options);

  bool done() const { return next_scan_ >= total_scans_; }
  std::size_t total_scans() const { return total_scans_; }
  std::size_t scans_done() const { return next_scan_; }
  /// Simulates and integrates the next scan. Allocates nothing once the
  /// buffers have grown (without the mosaic). Precondition: !done().
  void step();
  /// Flushes the sensor, applies the map filter, scores; call once, at the
  /// end (or earlier, to score a partial walk).
  WalkResult finish();

  const TerrainMapper& mapper() const { return mapper_; }
  const TrunkState& last_truth() const { return truth_; }
  const TrunkPose& last_estimate() const { return estimate_; }
  const ScanStats& last_stats() const { return last_stats_; }

 private:
  void copy_into_mosaic();
  void trace_swept(const TrunkPose& truth);

  WalkSensor& sensor_;
  WalkOptions options_;
  TrunkMotion motion_;
  PoseEstimator estimator_;
  TerrainMapper mapper_;
  std::optional<HeightFusion> fusion_;
  std::optional<StanceHeightReader> soles_reader_;  ///< over fusion_'s layers
  std::optional<ElevationMap> mosaic_;
  CellMask swept_;  ///< over the mosaic's window
  std::size_t total_scans_ = 0, next_scan_ = 0;
  TrunkState truth_;
  TrunkPose estimate_;
  ScanStats last_stats_;
  std::vector<Eigen::Vector2d> trace_, previous_trace_;
  bool have_previous_trace_ = false;
  double sum_sq_[6] = {0, 0, 0, 0, 0, 0};
  double sum_height_error_ = 0.0;
  std::size_t yaw_change_scans_ = 0;
  void count_visibility();
  std::uint64_t visibility_scans_ = 0;  // the clean-up's scans already counted
  std::size_t visibility_cleared_ = 0, visibility_wrong_ = 0, visibility_artifacts_ = 0, visibility_contradicted_ = 0;
  std::size_t visibility_scans_counted_ = 0, visibility_whole_map_ = 0;
  std::vector<Eigen::Vector2d> trajectory_;
  std::vector<HeightReferenceError> height_errors_;
  void read_fused_under_soles();
  double fused_under_soles_error_sum_m_ = 0.0;
  std::size_t fused_under_soles_scans_ = 0;
};

/// The whole walk.
WalkResult run_walk(const Scene& scene, const WalkPath& path, WalkSensor& sensor, const WalkOptions& options);

}  // namespace stridemap
