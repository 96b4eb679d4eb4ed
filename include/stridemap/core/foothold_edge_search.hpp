#pragma once
// The foothold layers' edge search (core/foothold.hpp): each cell's squared
// distance in cells to the nearest edge (a cell whose step height exceeds
// max_step_m) within the search radius, kept in FootholdChanges::seen_edge2
// and redone only where an edge appeared or went. A cell whose distance
// changed gets its score marked.
#include <cstddef>
#include <cstdint>
#include <vector>

#include "stridemap/core/foothold_changes.hpp"
#include "stridemap/core/foothold_stencil.hpp"

namespace stridemap {

/// The search's rows and scratch, sized for one window (allocated once).
struct FootholdEdgeSearch {
  FootholdEdgeSearch() = default;
  explicit FootholdEdgeSearch(int cells_per_side);

  /// Columns the search takes at once; rows are padded by as many.
  static constexpr int kBlock = 8;

  /// Per window-local row: the cells whose edge distance is searched for.
  std::vector<RowSpan> edge_rows;
  /// Per row: the columns whose along-row edge distances are needed.
  std::vector<RowSpan> distance_rows;
  std::size_t stride = 0;  ///< of distance2's rows: n and a block's padding
  std::vector<std::int32_t> distance2;  ///< n rows: squared along-row distance to an edge, or far (or more)
  std::vector<std::int32_t> best2;      ///< two rows of squared edge distances (padded)
  std::vector<std::int32_t> offset2;    ///< squared row offsets of the two rows' search
  std::vector<std::int32_t> row_a, row_b;  ///< one row's distances in cells, by window-local column
  std::vector<RowSpan> merged, merged_rows;  ///< search_or_raise_edges()'s scratch
};

/// Searches the edge distance of the cells in search.edge_rows, stored in
/// changes.seen_edge2; marks the score of a cell whose distance changed
/// (`all`: of every cell searched). Returns the cells searched.
std::size_t search_edge_distances(FootholdEdgeSearch& search, FootholdChanges& changes, const FootholdStencil& stencil,
                                  const float* step_height_m, float max_step_m, bool all);

/// Moves the cells that became edges (changes.raised) into
/// search.edge_rows when searching their region costs less than raising
/// them one by one.
void search_or_raise_edges(FootholdEdgeSearch& search, FootholdChanges& changes, const FootholdStencil& stencil);

/// Lowers the edge distances within the search radius of each cell that
/// became an edge and is still in changes.raised; empties it.
void raise_edges(FootholdChanges& changes, const FootholdStencil& stencil);

}  // namespace stridemap
