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
  /// 1 where no object (box, cylinder) comes within the margin of the cell:
  /// free floor, where any height in the map is a phantom. Empty when the
  /// snapshot has no truth.
  CellMask clear_of_objects;
};

/// Default margin of clear_of_objects [m]: a reading of an object's edge
/// lands up to a cell beside it (its cell is the reading's, not the edge's),
/// so the cells next to an object are neither floor nor object.
inline constexpr double kObjectMarginM = 0.01;

MapSnapshot snapshot_with_truth(const ElevationMap& map, const Scene& scene,
                                double object_margin_m = kObjectMarginM);

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
  /// Known cells clear of objects (MapSnapshot::clear_of_objects) in the
  /// scored area, those off by more than the artifact threshold there, and
  /// the largest error there; all 0 when the snapshot has no such mask.
  std::size_t clear_cells = 0;
  std::size_t clear_artifact_cells = 0;
  double clear_max_error_m = 0.0;
};

/// Scores the cells where `area` is non-zero (e.g. the swept area).
MapScore score_map(const MapSnapshot& snapshot, const CellMask& area, const MapScoreOptions& options = {});

}  // namespace stridemap
