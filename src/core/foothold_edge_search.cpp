#include "stridemap/core/foothold_edge_search.hpp"

#include <algorithm>
#include <limits>

#include "foothold_cells.hpp"

namespace stridemap {

FootholdEdgeSearch::FootholdEdgeSearch(int cells_per_side) {
  const auto n = static_cast<std::size_t>(cells_per_side);
  const RowSpan none{cells_per_side, -1};
  edge_rows.assign(n, none);
  distance_rows.assign(n, none);
  distance2.assign(n * n, 0);
  best2.assign(n, 0);
  merged.assign(n, none);
  merged_rows.assign(n, none);
}

// With AVX2 the row minima below take eight cells an instruction.
STRIDEMAP_FOOTHOLD_CLONES std::size_t search_edge_distances(FootholdEdgeSearch& search, FootholdChanges& changes,
                                                            const FootholdStencil& stencil, const float* step,
                                                            float max_step, bool all) {
  const int n_cells = changes.n;
  const int r = static_cast<int>(stencil.edge_cells), none = r + 1;
  const std::int32_t none2 = r * r + 1;
  // Far beyond any r * r + r * r, and no overflow when dx * dx is added.
  constexpr std::int32_t kFar = 1 << 29;
  const auto n = static_cast<std::size_t>(n_cells);
  std::size_t cells = 0;
  // The along-row distances a row must supply: its columns wherever a row
  // within r of it has cells to redo.
  std::fill(search.distance_rows.begin(), search.distance_rows.end(), RowSpan{n_cells, -1});
  for (int x = 0; x < n_cells; ++x) {
    const RowSpan e = search.edge_rows[static_cast<std::size_t>(x)];
    if (e.lo > e.hi) continue;
    for (int k = std::max(0, x - r); k <= std::min(n_cells - 1, x + r); ++k) {
      RowSpan& d = search.distance_rows[static_cast<std::size_t>(k)];
      d.lo = std::min(d.lo, e.lo);
      d.hi = std::max(d.hi, e.hi);
    }
  }
  // Per row: the squared distance along the row to the nearest edge within
  // r (kFar beyond), two sweeps over the needed columns and r either side.
  for (int x = 0; x < n_cells; ++x) {
    const RowSpan need = search.distance_rows[static_cast<std::size_t>(x)];
    if (need.lo > need.hi) continue;
    std::int32_t* out = search.distance2.data() + static_cast<std::size_t>(x) * n;
    const int lo = std::max(need.lo - r, 0), hi = std::min(need.hi + r, n_cells - 1);
    const float* row = step + changes.row_slot[static_cast<std::size_t>(x)];
    const std::size_t* cols = changes.col_slot.data();
    int last = std::numeric_limits<int>::min() / 2;
    for (int y = lo; y <= hi; ++y) {
      if (row[cols[y]] > max_step) last = y;
      out[y] = std::min(none, y - last);
    }
    int next = std::numeric_limits<int>::max() / 2;
    for (int y = hi; y >= lo; --y) {
      if (row[cols[y]] > max_step) next = y;
      const int d = std::min(out[y], std::min(none, next - y));
      out[y] = d <= r ? d * d : kFar;
    }
  }
  for (int x = 0; x < n_cells; ++x) {
    const RowSpan e = search.edge_rows[static_cast<std::size_t>(x)];
    if (e.lo > e.hi) continue;
    // min over the rows within r of dx^2 + (along-row distance)^2: exact
    // within the search disc (the nearest edge in Euclidean distance is the
    // nearest along its own row). Contiguous, so it vectorises.
    cells += static_cast<std::size_t>(e.hi - e.lo + 1);
    std::int32_t* best = search.best2.data();
    std::fill(best + e.lo, best + e.hi + 1, kFar);
    for (int k = std::max(0, x - r); k <= std::min(n_cells - 1, x + r); ++k) {
      const std::int32_t dx2 = (k - x) * (k - x);
      const std::int32_t* row = search.distance2.data() + static_cast<std::size_t>(k) * n;
      for (int y = e.lo; y <= e.hi; ++y) best[y] = std::min(best[y], dx2 + row[y]);
    }
    const std::size_t row = changes.row_slot[static_cast<std::size_t>(x)];
    for (int y = e.lo; y <= e.hi; ++y) {
      const std::int32_t b = std::min(best[y], none2);
      std::int32_t& seen = changes.seen_edge2[row + changes.col_slot[static_cast<std::size_t>(y)]];
      if (b != seen || all) {
        seen = b;
        changes.mark_score(x, y);
      }
    }
  }
  return cells;
}

// Cells that became edges are cheap one by one (raise_edges(), a pass over
// the search disc each), but a cluster of them costs less searched for as
// one region. Whichever costs less by the rough counts below (about ten
// instructions a disc cell raised, eighty a cell searched with AVX2;
// callgrind, the benchmark's walks) is taken: the values are the same.
void search_or_raise_edges(FootholdEdgeSearch& search, FootholdChanges& changes, const FootholdStencil& stencil) {
  if (changes.raised.empty()) return;
  const int n = changes.n;
  const auto area = [](const std::vector<RowSpan>& rows) {
    std::size_t cells = 0;
    for (const RowSpan& r : rows) cells += r.lo <= r.hi ? static_cast<std::size_t>(r.hi - r.lo + 1) : 0;
    return cells;
  };
  search.merged = changes.flips;
  for (const std::int32_t cell : changes.raised) {
    RowSpan& m = search.merged[static_cast<std::size_t>(cell / n)];
    m.lo = std::min(m.lo, cell % n);
    m.hi = std::max(m.hi, cell % n);
  }
  grow_rows(search.merged, search.merged_rows, stencil.edge_widths);
  const std::size_t extra = area(search.merged_rows) - area(search.edge_rows);
  if (extra * 8 < changes.raised.size() * stencil.edge_disc_cells) {
    search.edge_rows.swap(search.merged_rows);
    changes.raised.clear();
  }
}

// A cell that became an edge can only shorten the edge distances within
// the search radius: each becomes the smaller of what it was and the
// distance to the new edge, which is what the search would find (the
// edges that went are searched for before, in search_edge_distances()). A
// cell not yet known (kEdgeUnknown) is searched for when it is.
void raise_edges(FootholdChanges& changes, const FootholdStencil& stencil) {
  const int r = static_cast<int>(stencil.edge_cells);
  const int n = changes.n;
  for (const std::int32_t cell : changes.raised) {
    const int ei = cell / n, ej = cell % n;
    for (int dx = std::max(-r, -ei); dx <= std::min(r, n - 1 - ei); ++dx) {
      const int w = stencil.edge_widths[static_cast<std::size_t>(dx + r)];
      const std::size_t row = changes.row_slot[static_cast<std::size_t>(ei + dx)];
      for (int dy = std::max(-w, -ej); dy <= std::min(w, n - 1 - ej); ++dy) {
        const std::int32_t d2 = dx * dx + dy * dy;
        std::int32_t& seen = changes.seen_edge2[row + changes.col_slot[static_cast<std::size_t>(ej + dy)]];
        if (d2 < seen) {
          seen = d2;
          changes.mark_score(ei + dx, ej + dy);
        }
      }
    }
  }
  changes.raised.clear();
}

}  // namespace stridemap
