#pragma once
// Change tracking of the foothold layers (core/foothold.hpp): what the last
// refresh saw, per cell, and what the cells noted since then, the window's
// moves and the cells that left it make the next refresh redo. A refresh
// redoes a cell's plane fit only where its footprint changed, and its score
// only where the plane fit, the certainty factor or the edge distance did.
#include <cstddef>
#include <cstdint>
#include <vector>

#include "stridemap/core/cell_box.hpp"
#include "stridemap/core/changed_rows.hpp"
#include "stridemap/core/foothold_stencil.hpp"
#include "stridemap/core/grid_map.hpp"

namespace stridemap {

/// Window-local cells: rows i0..i1, columns j0..j1 (may reach outside the
/// window).
struct LocalBox {
  std::int64_t i0, i1, j0, j1;
};

struct FootholdChanges {
  /// seen_edge2 of a cell that entered the window and is not yet known.
  static constexpr std::int32_t kEdgeUnknown = -1;

  FootholdChanges() = default;
  /// `none2`: the squared edge distance that stands for no edge in reach.
  FootholdChanges(int cells_per_side, std::int32_t none2, double full_certainty);

  /// Records changed cells and the window's move; nothing before the
  /// first refresh, which computes everything.
  template <class Changed>
  void note(const ElevationMap& map, const Changed& changed) {
    if (!computed) return;
    stable = stable.intersected(CellBox::window_of(map));
    pending.add(changed);
  }

  /// row_slot and col_slot for the map's window as it is now.
  void set_slots(const ElevationMap& map);
  /// Marks every window cell whose footprint holds a cell of window-local
  /// row i, columns j0..j1 (which may lie outside the window).
  void mark_geometry(const FootholdStencil& stencil, std::int64_t i, std::int64_t j0, std::int64_t j1);
  /// mark_geometry() of every run of `bits` (bit b: column 64 * word + b)
  /// of window-local row i (0 <= i < n), for a footprint narrower than a
  /// word (stencil.foot_cells < 64): the disc's rows are the bits widened
  /// by shifts, a word and its two neighbours at a time, rather than a pass
  /// over the disc's rows per run.
  void mark_geometry_word(const FootholdStencil& stencil, std::int64_t i, std::size_t word, std::uint64_t bits);
  /// Marks the score of window-local cell (i, j), whose row's hull must
  /// already cover j (widen_scores()): the passes that mark cell by cell
  /// widen a row's hull once for all the cells they may mark in it.
  void mark_score(int i, int j) {
    const auto column = static_cast<std::size_t>(j);
    score_mark[static_cast<std::size_t>(i) * mark_words + column / 64] |= std::uint64_t{1} << (column % 64);
  }
  /// mark_score() of the cells (i, j + k) for each bit k of `bits`.
  void mark_scores(int i, int j, std::uint64_t bits) {
    const auto column = static_cast<std::size_t>(j);
    std::uint64_t* row = score_mark.data() + static_cast<std::size_t>(i) * mark_words + column / 64;
    row[0] |= bits << (column % 64);
    // The bits past the word, if any, are cells' columns: the next word exists.
    if (column % 64 != 0 && (bits >> (64 - column % 64)) != 0) row[1] |= bits >> (64 - column % 64);
  }
  /// Widens the hull of row i's score marks to columns lo..hi.
  void widen_scores(int i, int lo, int hi) {
    RowSpan& r = score_rows[static_cast<std::size_t>(i)];
    r.lo = r.lo < lo ? r.lo : lo;
    r.hi = r.hi > hi ? r.hi : hi;
  }
  void mark_edge(int i, int j) {  // inline: called per changed cell
    RowSpan& r = unseen_edge_rows[static_cast<std::size_t>(i)];
    r.lo = r.lo < j ? r.lo : j;
    r.hi = r.hi > j ? r.hi : j;
  }
  /// The cells of `b` (global, of the last refresh's window) that left
  /// every window since.
  void see_left(const FootholdStencil& stencil, const ElevationMap& map, const CellBox& b, CellIndex corner);
  /// The noted cells in every window since the last refresh.
  void see_changes(const FootholdStencil& stencil, const ElevationMap& map, const CellBox& window);
  /// Every cell of `b` (within the window) seen as it is now; with `mark`,
  /// as cells new to the window.
  void see_all(const FootholdStencil& stencil, const ElevationMap& map, const LocalBox& b, bool mark);

  int n = 0;  ///< cells per side of the window
  double full_certainty = 1.0;
  // What changed since the last refresh, and the intersection of the
  // windows since then (cells outside it may have left and come back reset).
  ChangedRows pending;
  CellBox window;  ///< the window at the last refresh
  CellBox stable;
  bool computed = false;
  // What the last refresh saw, per storage slot of the window: the
  // elevation where known (NaN where unknown), the certainty, and the
  // squared edge distance in cells (capped at none2). A noted cell whose
  // elevation and known-ness are unchanged redoes no plane fit; one whose
  // certainty factor is unchanged too redoes no score.
  std::vector<float> seen_elevation, seen_certainty;
  std::vector<std::int32_t> seen_edge2;
  // Storage slot = row_slot[local row] + col_slot[local column], for the
  // window of the refresh under way.
  std::vector<std::size_t> row_slot, col_slot;
  // Per window-local cell: its geometry is to be redone, or its edge
  // distance and score (bit j % 64 of word i * mark_words + j / 64 of
  // either: a run of marked cells is set a word at a time, and the passes
  // find the next marked cell by counting zeros, not by reading every
  // cell of a row's hull); cleared as they are.
  std::vector<std::uint64_t> geometry_mark, score_mark;
  std::size_t mark_words = 0;  ///< words of a row of marks
  /// Marks the geometry of window-local row i, columns lo..hi (0 <= lo <= hi < n).
  void mark_geometry_span(std::int64_t i, int lo, int hi) {
    set_bits(geometry_mark.data() + static_cast<std::size_t>(i) * mark_words, static_cast<std::size_t>(lo),
             static_cast<std::size_t>(hi));
  }
  /// Whether the 64 columns of a word of marks whose first column is at
  /// storage slot `start` follow it in storage, the ring not wrapping
  /// within them: then column 64 * word + b is at start + b, without a
  /// column slot looked up per cell.
  bool word_in_one_run(std::size_t start) const { return start % static_cast<std::size_t>(n) + 63 < static_cast<std::size_t>(n); }
  /// Sets bits lo..hi (lo <= hi) of a row of words.
  static void set_bits(std::uint64_t* row, std::size_t lo, std::size_t hi) {
    const std::size_t first = lo / 64, last = hi / 64;
    const std::uint64_t from_lo = ~std::uint64_t{0} << (lo % 64);
    const std::uint64_t to_hi = ~std::uint64_t{0} >> (63 - hi % 64);
    if (first == last) {
      row[first] |= from_lo & to_hi;
      return;
    }
    row[first] |= from_lo;
    for (std::size_t w = first + 1; w < last; ++w) row[w] = ~std::uint64_t{0};
    row[last] |= to_hi;
  }
  // Per window-local row: the hulls of the marks, the cells that stopped
  // being edges (step no longer above max_step_m) or that left as edges,
  // and the cells whose edge distance is searched for because they became
  // known since they entered the window.
  std::vector<RowSpan> geometry_rows, score_rows, flips, unseen_edge_rows;
  std::vector<std::int32_t> raised;  ///< window-local cells (i * n + j) that became edges
};

}  // namespace stridemap
