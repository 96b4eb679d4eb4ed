#pragma once
// Scores a map against the simulator's ground truth: per-cell truth (the
// highest terrain point inside the cell), error statistics, coverage and
// artifact counts, as the experiments' summaries report them.
#include <cstddef>
#include <cstdint>
#include <vector>

#include <Eigen/Core>

#include "stridemap/core/exported_map.hpp"
#include "stridemap/core/grid_map.hpp"
#include "stridemap/sim/scene.hpp"

namespace stridemap {

/// The exported map (core/exported_map.hpp) with the truth beside it, in
/// the same window order.
struct MapSnapshot : ExportedMap {
  Eigen::MatrixXf truth_m;  ///< highest scene point inside each cell
};

MapSnapshot snapshot_with_truth(const ElevationMap& map, const Scene& scene);

struct MapScoreOptions {
  /// A known cell whose elevation is off by more than this counts as an
  /// artifact [m]. 20 mm is twice the URG's accuracy bound below 1 m and
  /// two cell sizes, so range noise alone does not reach it while a spike,
  /// a phantom edge or a wrong fill does.
  double artifact_threshold_m = 0.02;
};

struct MapScore {
  std::size_t known_cells = 0;     ///< measured + filled, within the scored area
  std::size_t measured_cells = 0;
  std::size_t filled_cells = 0;
  std::size_t scored_area_cells = 0;
  double rms_error_m = 0.0;        ///< over known cells in the scored area
  double max_error_m = 0.0;
  double rms_error_measured_m = 0.0;
  double rms_error_filled_m = 0.0;
  double mean_error_m = 0.0;       ///< signed: positive = map higher than truth
  double coverage = 0.0;           ///< known / scored area
  std::size_t artifact_cells = 0;
  double artifact_threshold_m = 0.0;
};

/// Scores the cells where `area` is non-zero (e.g. the swept area).
MapScore score_map(const MapSnapshot& snapshot, const CellMask& area, const MapScoreOptions& options = {});

}  // namespace stridemap
