#pragma once
// The foothold experiment (docs/foothold.md): the robot walks a rocky scene
// mapping with the URG, the foothold layers (core/foothold.hpp) are computed
// on the map it built, and every mapped cell of the swept area is scored
// against the foothold layers of the truth (the same code on the scene's
// true cell heights): is "safe" (score >= safe_score) right?
//
// Results are from the simulator, not from a real robot.
#include <cstddef>
#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "stridemap/core/foothold.hpp"
#include "stridemap/core/progress.hpp"
#include "stridemap/experiments/walk.hpp"
#include "stridemap/sim/scene.hpp"
#include "stridemap/sim/walk_path.hpp"

namespace stridemap {

/// Counts of one walk's cells; "safe" means score >= safe_score.
struct FootholdConfusion {
  std::size_t scored_cells = 0;     ///< mapped (measured or filled) cells in the swept area
  std::size_t true_safe = 0;        ///< map safe, truth safe
  std::size_t false_safe = 0;       ///< map safe, truth unsafe: the dangerous mistake
  std::size_t false_unsafe = 0;     ///< map not safe (or unknown), truth safe
  std::size_t true_unsafe = 0;
  std::size_t unknown_score = 0;    ///< mapped cells whose score is NaN (too few known neighbours)
  double precision() const;         ///< true_safe / (true_safe + false_safe); NaN when none called safe
  double recall() const;            ///< true_safe / (true_safe + false_unsafe); NaN when truth has none safe
  FootholdConfusion& operator+=(const FootholdConfusion& other);
};

struct FootholdRun {
  std::string scene;                ///< "rocky_mockup.yaml", "random rocky 3"
  std::uint64_t seed = 0;           ///< the walk's seed (sensor noise, pose errors)
  FootholdConfusion all;            ///< measured and filled cells
  FootholdConfusion measured;       ///< measured cells only
  /// Mean |map - truth| over the scored cells where both are known.
  double mean_slope_error_deg = 0.0;
  double mean_step_error_m = 0.0;
  double mean_score_error = 0.0;
  std::size_t truth_safe_cells = 0;  ///< of the scored cells
};

struct FootholdExperimentOptions {
  /// Each walk's settings (its seed is set per run); the paper's local map.
  WalkOptions walk{};
  FootholdOptions foothold{};
  /// Walks over the given scene (the rocky mock-up), seeds seed .. seed + n - 1.
  std::size_t mockup_seeds = 5;
  /// Walks over random rocky scenes (sim/random_scene.hpp), scene k with
  /// scene seed seed * 1000 + k, walked with that seed.
  std::size_t random_scenes = 10;
  std::uint64_t seed = 1;
  ProgressCallback progress{};
  /// Checked before the walk: InputError naming the field.
  void validate() const;
};


struct FootholdExperimentResult {
  std::vector<FootholdRun> runs;  ///< the mock-up's walks first
  /// The first walk's map of the whole walk and its truth, foothold layers
  /// included, and the swept area (window order): for the pictures.
  std::optional<ElevationMap> first_map, first_truth;
  CellMask first_swept;
};

/// Truth foothold layers for `map`'s window: a map of the same geometry
/// whose every cell holds the true height `truth_m` (window order, e.g.
/// MapSnapshot::truth_m: the highest scene point in the cell) at full
/// certainty, with its foothold layers computed.
ElevationMap truth_foothold_map(const ElevationMap& map, const Eigen::MatrixXf& truth_m, const FootholdOptions& options);

/// Scores one map (with its foothold layers computed) against the truth
/// map's, over the cells where `area` is non-zero (window order).
FootholdRun score_footholds(const ElevationMap& map, const ElevationMap& truth, const CellMask& area,
                            const FootholdOptions& options);

/// One walk with `sensor` over the scene, scored. Deterministic for the seeds.
/// With `keep`, the map, truth and swept area are moved into it.
FootholdRun run_foothold_walk(const Scene& scene, const WalkPath& path, WalkSensor& sensor,
                              const FootholdExperimentOptions& options, FootholdExperimentResult* keep = nullptr);

/// Every walk of the experiment with the simulated URG (default sensor
/// options); `mockup_name` labels the given scene's runs.
FootholdExperimentResult run_foothold_experiment(const Scene& mockup, const WalkPath& mockup_path,
                                                 const std::string& mockup_name,
                                                 const FootholdExperimentOptions& options);

/// summary.json: the options, every run, and per group (mock-up, random,
/// all) the median, 10th and 90th percentiles of precision and recall.
std::string foothold_summary_json(const FootholdExperimentResult& result, const FootholdExperimentOptions& options);
/// The printed table: one line per run, then the distributions.
std::string foothold_table(const FootholdExperimentResult& result);
/// summary.json, table.txt and the first walk's pictures (map/: elevation,
/// certainty and foothold PNGs and CSVs of the map; truth_foothold_score.png)
/// into `directory`; InputError naming a file that cannot be written.
void write_foothold_outputs(const FootholdExperimentResult& result, const FootholdExperimentOptions& options,
                            const std::string& directory);

}  // namespace stridemap
