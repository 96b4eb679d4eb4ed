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

/// Normal matrices of partial footprints, inverted, by which of the
/// footprint's cells are known (bit k: footprint[k]). The inverse depends on
/// that set alone, so a cached one is the one the fit would compute; the
/// few sets along a map's border recur refresh after refresh. Direct-mapped,
/// allocated once.
struct PartialInverses {
  static constexpr int kBits = 10;  ///< 1,024 entries, 90 kB
  struct Entry {
    std::uint64_t known = 0;  ///< 0: empty (a fitted footprint has >= 3 known cells)
    bool invertible = false;
    Eigen::Matrix3d inverse = Eigen::Matrix3d::Zero();
  };
  std::vector<Entry> entries = std::vector<Entry>(std::size_t{1} << kBits);
  Entry& slot(std::uint64_t known) { return entries[(known * 0x9E3779B97F4A7C15ull) >> (64 - kBits)]; }
};

/// Cells the foothold plane fits take at once, one per vector lane.
inline constexpr int kFootholdLanes = 4;

/// What a refresh saw (FootholdChanges::seen_elevation) in window-local
/// order, with a margin of unknown (NaN) around the window as wide as the
/// footprint, and room for a last lane group past the end of a row: every
/// footprint is a run of contiguous entries per row, within the window or not.
struct PaddedElevations {
  PaddedElevations() = default;
  PaddedElevations(int cells_per_side, std::int64_t foot_cells);
  const float* at(int i, int j) const { return values.data() + (i + margin) * stride + (j + margin); }
  /// Copies the entries the footprints of the marked cells (`marked`,
  /// per window-local row) read; others keep stale values no stored fit reads.
  void copy(const std::vector<RowSpan>& marked, const std::vector<float>& seen_elevation,
            const std::vector<std::size_t>& row_slot, const std::vector<std::size_t>& col_slot);

  int n = 0;
  std::ptrdiff_t margin = 0, stride = 0;
  std::vector<float> values;
  std::vector<RowSpan> needed;  ///< per window-local row: the columns copied
};

/// to[x] covers from[x + dx] widened by widths[dx + r] for |dx| <= r (a
/// bound of the disc around every cell of `from`, as rows' hulls), within
/// the window's from.size() rows and columns.
void grow_rows(const std::vector<RowSpan>& from, std::vector<RowSpan>& to, const std::vector<int>& widths);

}  // namespace stridemap
