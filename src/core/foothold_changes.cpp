#include "stridemap/core/foothold_changes.hpp"

#include <algorithm>
#include <cmath>

#include "foothold_cells.hpp"

namespace stridemap {

FootholdChanges::FootholdChanges(int cells_per_side, std::int32_t none2, double full_certainty_in)
    : n(cells_per_side), full_certainty(full_certainty_in) {
  const auto cells = static_cast<std::size_t>(n);
  pending.resize(n);
  seen_elevation.assign(cells * cells, foothold::kNaN);
  seen_certainty.assign(cells * cells, 0.0f);
  seen_edge2.assign(cells * cells, none2);
  row_slot.assign(cells, 0);
  col_slot.assign(cells, 0);
  mark_words = (cells + 63) / 64;
  geometry_mark.assign(cells * mark_words, 0);
  score_mark.assign(cells * mark_words, 0);
  for (std::vector<RowSpan>* rows : {&geometry_rows, &score_rows, &flips, &unseen_edge_rows}) {
    rows->assign(cells, RowSpan{n, -1});
  }
  raised.reserve(cells * cells);  // a cell is raised at most once a refresh
}

void FootholdChanges::set_slots(const ElevationMap& map) {
  const auto cells = static_cast<std::size_t>(n);
  const std::size_t corner = map.slot(map.min_cell());
  const std::size_t row0 = corner / cells, col0 = corner % cells;
  for (std::size_t i = 0; i < cells; ++i) {
    const std::size_t r = row0 + i;
    row_slot[i] = (r >= cells ? r - cells : r) * cells;
    const std::size_t c = col0 + i;
    col_slot[i] = c >= cells ? c - cells : c;
  }
}

// The run grown by the footprint's disc, row by row.
void FootholdChanges::mark_geometry(const FootholdStencil& stencil, std::int64_t i, std::int64_t j0, std::int64_t j1) {
  const std::int64_t f = stencil.foot_cells, side = n;
  const int* widths = stencil.foot_widths.data() + f;  // by row offset, -f..f
  std::uint64_t* marks = geometry_mark.data();
  RowSpan* hulls = geometry_rows.data();
  const std::size_t words = mark_words;
  const std::int64_t first = std::max(-f, -i), last = std::min(f, side - 1 - i);
  for (std::int64_t d = first; d <= last; ++d) {
    const std::int64_t w = widths[d < 0 ? -d : d];
    if (w < 0) continue;
    const auto lo = static_cast<int>(std::max<std::int64_t>(j0 - w, 0));
    const auto hi = static_cast<int>(std::min<std::int64_t>(j1 + w, side - 1));
    if (lo > hi) continue;
    const auto x = static_cast<std::size_t>(i + d);
    set_bits(marks + x * words, static_cast<std::size_t>(lo), static_cast<std::size_t>(hi));
    RowSpan& r = hulls[x];
    r.lo = std::min(r.lo, lo);
    r.hi = std::max(r.hi, hi);
  }
}

// A neighbour's footprint lost the known ones among them, and the edge
// distances within the search radius of one that was an edge may grow.
void FootholdChanges::see_left(const FootholdStencil& stencil, const ElevationMap& map, const CellBox& b,
                               CellIndex corner) {
  const std::int64_t foot_cells = stencil.foot_cells, edge_cells = stencil.edge_cells;
  const auto clamp = [&](std::int64_t v) { return static_cast<int>(std::clamp<std::int64_t>(v, 0, n - 1)); };
  for (std::int64_t x = b.min.x; x <= b.max.x; ++x) {
    const std::int64_t i = x - corner.x;
    if (i < -foot_cells - edge_cells || i > n - 1 + foot_cells + edge_cells) continue;  // reaches no window cell
    bool in_run = false;
    std::int64_t run = 0;
    // Slots along the row step by one and wrap: map.slot()'s two modulos
    // once a row, not once a cell.
    const std::size_t first = map.slot({x, b.min.y});
    const std::size_t row = first - first % static_cast<std::size_t>(n);
    std::size_t col = first - row;
    for (std::int64_t y = b.min.y; y <= b.max.y + 1; ++y) {
      bool was_known = false;
      if (y <= b.max.y) {
        const std::size_t s = row + col;
        col = col + 1 == static_cast<std::size_t>(n) ? 0 : col + 1;
        was_known = !std::isnan(seen_elevation[s]);
        if (seen_edge2[s] == 0) {  // it was an edge
          RowSpan& f = flips[static_cast<std::size_t>(clamp(i))];
          f.lo = std::min(f.lo, clamp(y - corner.y));
          f.hi = std::max(f.hi, clamp(y - corner.y));
        }
      }
      if (was_known && !in_run) {
        run = y;
        in_run = true;
      } else if (!was_known && in_run) {
        mark_geometry(stencil, i, run - corner.y, y - 1 - corner.y);
        in_run = false;
      }
    }
  }
}

// Compared with what the last refresh saw: a changed elevation or
// known-ness redoes the plane fits around the cell; a changed certainty
// factor, its score only.
void FootholdChanges::see_changes(const FootholdStencil& stencil, const ElevationMap& map, const CellBox& now) {
  if (pending.empty()) return;
  const float* elevation = map.elevation_data();
  const std::uint8_t* state = map.state_data();
  const float* certainty = map.certainty_data();
  const CellIndex corner = now.min;
  const CellBox rows = pending.bounds().intersected(stable);
  std::int64_t lo = 0, hi = 0;
  for (std::int64_t x = rows.min.x; !rows.empty() && x <= rows.max.x; ++x) {
    if (!pending.span(x, lo, hi)) continue;
    lo = std::max(lo, stable.min.y);
    hi = std::min(hi, stable.max.y);
    const auto i = static_cast<int>(x - corner.x);
    const std::size_t row = row_slot[static_cast<std::size_t>(i)];
    // Runs of consecutive changed cells are marked as one box.
    std::int64_t run = 0;
    bool in_run = false;
    for (std::int64_t y = lo; y <= hi + 1; ++y) {
      bool changed = false;
      if (y <= hi) {
        const auto j = static_cast<int>(y - corner.y);
        const std::size_t s = row + col_slot[static_cast<std::size_t>(j)];
        const float elevation_now = foothold::known_elevation(elevation, state, s);
        const float before = seen_elevation[s];
        if (!foothold::same_bits(elevation_now, before)) {
          changed = true;
          seen_elevation[s] = elevation_now;
          // The edge distance is NaN exactly where the cell is unknown; a
          // cell that entered the window unknown has none to show yet.
          if (std::isnan(elevation_now) != std::isnan(before)) mark_score(i, j);
          if (seen_edge2[s] == kEdgeUnknown && !std::isnan(elevation_now)) mark_edge(i, j);
        }
        // The same certainty, the same factor: most noted cells skip both
        // divisions.
        if (!foothold::same_bits(certainty[s], seen_certainty[s])) {
          // Both at or past full certainty: the same factor, 1, without dividing.
          const bool both_full = certainty[s] >= full_certainty && seen_certainty[s] >= full_certainty;
          if (!both_full && !foothold::same_bits(foothold::certainty_factor(certainty[s], full_certainty),
                                   foothold::certainty_factor(seen_certainty[s], full_certainty))) {
            mark_score(i, j);
          }
          seen_certainty[s] = certainty[s];
        }
      }
      if (changed && !in_run) {
        run = y;
        in_run = true;
      } else if (!changed && in_run) {
        mark_geometry(stencil, i, run - corner.y, y - 1 - corner.y);
        in_run = false;
      }
    }
  }
}

// With `mark`, a known cell redoes the plane fits around it and its score
// (cells that entered the window were unknown to the last refresh).
void FootholdChanges::see_all(const FootholdStencil& stencil, const ElevationMap& map, const LocalBox& b, bool mark) {
  const float* elevation = map.elevation_data();
  const std::uint8_t* state = map.state_data();
  const float* certainty = map.certainty_data();
  for (std::int64_t i = b.i0; i <= b.i1; ++i) {
    const std::size_t row = row_slot[static_cast<std::size_t>(i)];
    // Runs of consecutive known cells are marked as one box.
    std::int64_t run = 0;
    bool in_run = false;
    for (std::int64_t j = b.j0; j <= b.j1; ++j) {
      const std::size_t s = row + col_slot[static_cast<std::size_t>(j)];
      seen_elevation[s] = foothold::known_elevation(elevation, state, s);
      seen_certainty[s] = certainty[s];
      if (!mark) continue;
      // Its edge distance is searched for when it is known (then or later).
      seen_edge2[s] = kEdgeUnknown;
      const bool known = !std::isnan(seen_elevation[s]);
      if (known) {
        mark_score(static_cast<int>(i), static_cast<int>(j));
        mark_edge(static_cast<int>(i), static_cast<int>(j));
        if (!in_run) run = j;
      } else if (in_run) {
        mark_geometry(stencil, i, run, j - 1);
      }
      in_run = known;
    }
    if (in_run) mark_geometry(stencil, i, run, b.j1);
  }
}

}  // namespace stridemap
