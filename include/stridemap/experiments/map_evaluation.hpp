#pragma once
// Scores a map against the simulator's ground truth: per-cell truth (the
// highest terrain point inside the cell), error statistics, coverage and
// artifact counts, as the experiments' summaries report them.
//
// A cell at an object's edge holds whichever reading fell in it: the top,
// the face or the floor; and a reading a few millimetres off sideways puts
// the top's height in the cell beside the edge. Such a cell's error against
// its highest point (up to the object's height) says how finely and how
// exactly in x-y the sensor sampled the edge, not that a height is wrong,
// and a few of them set the map's RMS. So the score also reports apart the
// level cells (the surface varies little within the object margin of the
// cell) and the error beyond each cell's span: how far its height lies
// outside the lowest and highest surface within that margin, a height no
// reading near the cell could have given: what a phantom or a bias leaves.
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
  CellMask clear_of_objects;
  /// The lowest and highest surface within the same margin of each cell:
  /// the heights a reading near it can hold. The highest is exact; the
  /// lowest is sampled at kSpanSamplesPerSide^2 points spread evenly over
  /// the grown cell, so floor narrower than their spacing may be missed.
  Eigen::MatrixXf span_low_m, span_high_m;
};

/// Default margin of clear_of_objects [m]: a reading of an object's edge
/// lands up to a cell beside it (its cell is the reading's, not the edge's),
/// so the cells next to an object are neither floor nor object.
inline constexpr double kObjectMarginM = 0.01;

/// Points per side of the grown cell at which span_low_m is sampled: 3 mm
/// apart for 5 mm cells and the default margin.
inline constexpr int kSpanSamplesPerSide = 9;

/// The lowest and highest scene surface over a rectangle [m]: the highest
/// exact (Scene::max_height_in_rect), the lowest sampled at
/// `samples_per_side`^2 points spread evenly over it, so floor narrower
/// than their spacing may be missed. NaN high for a non-finite rectangle.
struct SurfaceSpan {
  double low_m = 0.0;
  double high_m = 0.0;
};
SurfaceSpan surface_span(const Scene& scene, double min_x_m, double min_y_m, double max_x_m, double max_y_m,
                         int samples_per_side = kSpanSamplesPerSide);

MapSnapshot snapshot_with_truth(const ElevationMap& map, const Scene& scene,
                                double object_margin_m = kObjectMarginM);

struct MapScoreOptions {
  /// A known cell whose elevation is off by more than this counts as an
  /// artifact [m]. 20 mm is twice the URG's accuracy bound below 1 m and
  /// two cell sizes, so range noise alone does not reach it while a spike,
  /// a phantom edge or a wrong fill does.
  double artifact_threshold_m = 0.02;
  /// A cell whose span (MapSnapshot::span_low_m..span_high_m) is at most
  /// this is level [m]: its truth is one height whatever reading fell near
  /// it. 5 mm lets sloped floor count as level but no object's edge.
  double level_relief_m = 0.005;
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
  /// Known level cells (MapScoreOptions::level_relief_m) and the RMS error
  /// over them; the rest are edge cells.
  std::size_t level_cells = 0;
  double level_relief_m = 0.0;
  double rms_error_level_m = 0.0;
  /// How far each known cell's elevation lies outside its span (0
  /// inside): RMS, largest, and the cells beyond it by more than the
  /// artifact threshold. 0 when the snapshot has no span.
  double rms_beyond_span_m = 0.0;
  double max_beyond_span_m = 0.0;
  std::size_t beyond_span_artifact_cells = 0;
};

/// Scores the cells where `area` is non-zero (e.g. the swept area).
MapScore score_map(const MapSnapshot& snapshot, const CellMask& area, const MapScoreOptions& options = {});

}  // namespace stridemap
