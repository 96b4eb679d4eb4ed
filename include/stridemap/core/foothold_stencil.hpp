#pragma once
// The two discs of the foothold layers (core/foothold.hpp) in whole cells
// of one map: the foot's footprint (plane fits, step height) and the edge
// search disc (edge distance). Both are fixed when the layers are attached,
// so that a refresh reads tables instead of testing radii per cell; the
// change tracking, the plane fits and the edge search share them.
#include <cstddef>
#include <cstdint>
#include <vector>

#include <Eigen/Core>

#include "stridemap/core/grid_map.hpp"

namespace stridemap {

/// Columns lo..hi of a window-local row; lo > hi: none.
struct RowSpan {
  int lo, hi;
};

struct FootholdStencil {
  FootholdStencil() = default;
  /// Radii as in FootholdOptions; the edge search disc is capped at the
  /// window's side.
  FootholdStencil(double foot_radius_m, double edge_search_radius_m, double min_known_fraction, double cell_size_m,
                  int cells_per_side);

  double cell_size_m = 0.0;
  std::int64_t foot_cells = 0;  ///< footprint radius in whole cells
  std::int64_t edge_cells = 0;  ///< edge search radius in whole cells
  std::size_t min_known = 3;    ///< known cells a footprint needs for any value
  std::vector<CellIndex> footprint;        ///< offsets of the footprint's cells
  std::vector<double> foot_x_m, foot_y_m;  ///< the same offsets [m]
  std::vector<double> foot_dx, foot_dy;    ///< and in cells, as doubles
  /// The plane fit's normal matrix inverted for a whole footprint, the
  /// common case, so that only a partial footprint inverts its own.
  Eigen::Matrix3d full_inverse = Eigen::Matrix3d::Zero();
  /// Half-widths of the footprint disc and of the edge search disc per row
  /// offset -r..r (index dx + r; -1: no cell): how far a change reaches
  /// along a row.
  std::vector<int> foot_widths, edge_widths;
  std::size_t edge_disc_cells = 0;  ///< cells of the edge search disc
};

/// to[x] covers from[x + dx] widened by widths[dx + r] for |dx| <= r (a
/// bound of the disc around every cell of `from`, as rows' hulls), within
/// the window's from.size() rows and columns.
void grow_rows(const std::vector<RowSpan>& from, std::vector<RowSpan>& to, const std::vector<int>& widths);

}  // namespace stridemap
