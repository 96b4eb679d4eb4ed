#pragma once
// A box's four edges fitted to sub-cell precision from the positions of
// the readings that set its edge cells (core/top_point.hpp). The cells say
// roughly where the sides are (the minimum-area rectangle of the box's
// region); each edge cell's reading is given to the nearest side; one
// orientation shared by the four sides and one offset per side are fitted
// by least squares (the smallest eigenvector of the pooled scatter, Eigen).
// A reading that set an edge cell lies on the box's top inside the edge,
// or on its face at the edge, so the edge is the outer envelope of the
// side's readings, not their mean: each side's line is moved out to an
// upper quantile of its readings' offsets, or, on a side square to the
// grid, to the end of their even spread over the covered parts of their
// cells (BoxEdgeOptions::stripe_chords).
//
// Trimmed: readings further from their side's line than a multiple of the
// robust spread (median absolute deviation) are left out and the fit
// repeated (a mixed pixel, a reading pushed off the edge by range noise).
// Untrimmed: the same fit with every reading.
#include <array>
#include <cstddef>
#include <limits>
#include <vector>

#include <Eigen/Core>

namespace stridemap {

struct BoxEdgeOptions {
  /// A reading whose second-nearest side is within this many cells of it
  /// sits in a corner and is not used: it could belong to either side.
  double corner_cells = 1.0;
  /// Trimming leaves out readings further from their line than this many
  /// robust standard deviations (1.4826 x the median absolute deviation).
  double trim_sigmas = 2.5;
  /// ... but never closer than this [m] (noise-free readings have no spread).
  double min_trim_m = 0.002;
  int trim_rounds = 3;
  /// The side's edge is at this quantile of its readings' offsets from the
  /// fitted line, outwards (0.5 = the line itself, 1 = the outermost).
  double edge_quantile = 0.9;
  /// The heading the sensor looked along while it scanned (map frame)
  /// [rad]; NaN when unknown, and then every side takes edge_quantile.
  double view_heading_rad = std::numeric_limits<double>::quiet_NaN();
  /// A side whose outward normal points back against the view heading
  /// (cosine below -facing_cos) is a face the beams met: range noise moves
  /// its readings along the beams, towards the sensor and upwards, so eq.
  /// (10) keeps the ones in front of the face and its edge cells' readings
  /// spread outwards past the edge. Its edge is at this quantile instead.
  /// The default keeps the envelope: 0.5 (the readings' middle) made seed
  /// 1's random scenes better and seed 2's not (docs/experiments.md,
  /// "Facing sides"), so it is there to be chosen, not the default.
  double facing_edge_quantile = 0.9;
  double facing_cos = 0.5;
  /// A side that runs along the view (its outward normal's cosine to the
  /// view within +-facing_cos) and drifts less than a cell across the grid over its
  /// length takes its edge from where its readings lie on their stripes, not
  /// from a quantile, when the readings' cells are given. Each scan crosses
  /// a cell along one line square to the view, the stripe, whose beams
  /// sample it far finer than a cell, and the cell keeps one of the readings
  /// on the part of that chord the top covers, any of them alike (eq. (10)'s
  /// highest: range noise picks it). On such a side every border cell's
  /// covered part is the same share of a cell, up to a whole cell, and a
  /// quantile of readings spread evenly over it stays inside the edge by a
  /// share of it; the end of a uniform spread is estimated from its
  /// outermost reading instead (box_edges.cpp, stripe_edge).
  /// Only a side whose face the beams cannot meet: the sensor's path (a
  /// point on it, `view_path_point_m`, in the readings' frame) lies on the
  /// box's side of the side's line. Range noise moves the readings on a face
  /// the beams meet towards the sensor and upwards, past the edge, where
  /// eq. (10) keeps them; the outermost reading is then no bound.
  bool stripe_chords = true;
  /// NaN when unknown, and then no side takes stripe chords.
  Eigen::Vector2d view_path_point_m = Eigen::Vector2d::Constant(std::numeric_limits<double>::quiet_NaN());
};

/// The rectangle the cells give, in a frame turned by `yaw_rad` (u along
/// the first axis, v along the second), around which readings are sorted.
struct BoxFrame {
  double yaw_rad = 0.0;
  double u_min_m = 0.0, u_max_m = 0.0, v_min_m = 0.0, v_max_m = 0.0;
};

struct BoxEdgeFit {
  bool ok = false;  ///< false when a side has fewer than two readings
  /// The fitted first axis's direction in the map frame [rad].
  double yaw_rad = 0.0;
  double length_m = 0.0;  ///< between the u sides
  double width_m = 0.0;   ///< between the v sides
  /// Readings used per side (u min, u max, v min, v max), after trimming.
  std::array<std::size_t, 4> points{};
  /// Each side's edge as a signed offset along its axis from the readings'
  /// origin (u min, u max, v min, v max) [m].
  std::array<double, 4> edges_m{};
  /// Which sides were taken as faces the sensor saw (facing_edge_quantile).
  std::array<bool, 4> facing{};
  /// Which sides took their edge from their readings' stripe chords
  /// (BoxEdgeOptions::stripe_chords).
  std::array<bool, 4> stripe{};
};

/// Fits the four edges to `readings` (map frame, any origin) with the
/// sides placed by `frame` and `cell_size_m` setting the corner margin.
/// `reading_cells`, when it holds one entry per reading, gives the centre of
/// the cell each reading set (same frame), for BoxEdgeOptions::stripe_chords.
/// `level_readings`, when it holds one entry per reading, gives each
/// reading moved along its beam to the top's level (same frame): the sides
/// running along the view take their edges from those, the line, the
/// trimming and the other sides from `readings`. `beam_level_readings`,
/// likewise, gives each reading moved down its beam to the top's level
/// along the view as well: the sides whose outward normal points along the
/// view (cosine above facing_cos), faces the beams cannot meet, take their
/// edges from those.
BoxEdgeFit fit_box_edges(const std::vector<Eigen::Vector2d>& readings, const BoxFrame& frame, double cell_size_m,
                         bool trim, const BoxEdgeOptions& options = {},
                         const std::vector<Eigen::Vector2d>& reading_cells = {},
                         const std::vector<Eigen::Vector2d>& level_readings = {},
                         const std::vector<Eigen::Vector2d>& beam_level_readings = {});

}  // namespace stridemap
