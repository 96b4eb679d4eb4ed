#pragma once
// The cells a scan changed, row by row: for each row of cells (global x
// index) the smallest and largest changed column (global y). Finer than one
// CellBox: a scan line lying diagonally across the window has a box of half
// the window but only a few cells per row. Like a box it is a bound, never
// smaller than what changed, which is all incremental updates need
// (core/foothold.hpp).
//
// Rows are kept in a ring of one window's rows (row x in x mod rows), each
// with its global row index: a row written after the window moved on by a
// whole window replaces the one that shared its place, which by then has
// left the window. Storage is sized once (constructor or resize()); adding
// and clearing allocate nothing.
#include <algorithm>
#include <cstdint>
#include <limits>
#include <vector>

#include "stridemap/core/cell_box.hpp"
#include "stridemap/core/grid_map.hpp"

namespace stridemap {

class ChangedRows {
 public:
  ChangedRows() = default;
  /// Room for `rows` rows: a map's cells_per_side().
  explicit ChangedRows(int rows) { resize(rows); }

  /// Allocates; forgets every row.
  void resize(int rows) {
    rows_.assign(static_cast<std::size_t>(std::max(rows, 1)), Row{});
    bounds_.clear();
  }
  int rows() const { return static_cast<int>(rows_.size()); }

  void add(CellIndex c) { add_span(c.x, c.y, c.y); }
  /// Columns lo..hi of row x (inclusive; lo > hi adds nothing).
  void add_span(std::int64_t x, std::int64_t lo, std::int64_t hi) {
    if (lo > hi) return;
    Row& r = row_for(x);
    r.lo = std::min(r.lo, lo);
    r.hi = std::max(r.hi, hi);
    bounds_.add(CellIndex{x, lo});
    bounds_.add(CellIndex{x, hi});
  }
  /// add_span(first_x + k, y0 + lo[k], y0 + hi[k]) for k = 0..count-1, with
  /// one modulo for all the rows rather than one per row (the mapper's
  /// per-scan spans, kept window-local in int32). Returns the box of the
  /// spans added (empty when none was), which the caller's own box needs.
  CellBox add_spans(std::int64_t first_x, std::size_t count, const std::int32_t* lo, const std::int32_t* hi,
                    std::int64_t y0) {
    const std::size_t n = rows_.size();
    std::size_t p = place(first_x);
    Row* rows = rows_.data();
    std::size_t first_k = count, last_k = 0;
    std::int32_t lo_y = std::numeric_limits<std::int32_t>::max(), hi_y = std::numeric_limits<std::int32_t>::min();
    for (std::size_t k = 0; k < count; ++k) {
      const std::int32_t l = lo[k], h = hi[k];
      if (l <= h) {
        const std::int64_t x = first_x + static_cast<std::int64_t>(k);
        Row& r = rows[p];
        if (r.x != x) r = Row{x, std::numeric_limits<std::int64_t>::max(), std::numeric_limits<std::int64_t>::min()};
        r.lo = std::min(r.lo, y0 + l);
        r.hi = std::max(r.hi, y0 + h);
        first_k = std::min(first_k, k);
        last_k = k;
        lo_y = std::min(lo_y, l);
        hi_y = std::max(hi_y, h);
      }
      if (++p == n) p = 0;
    }
    CellBox added;
    if (first_k == count) return added;
    // A box grows by its corners: these two bound every span's.
    added.add(CellIndex{first_x + static_cast<std::int64_t>(first_k), y0 + lo_y});
    added.add(CellIndex{first_x + static_cast<std::int64_t>(last_k), y0 + hi_y});
    bounds_.add(added);
    return added;
  }
  /// Every cell of `box` (its last rows() rows when it has more).
  void add(const CellBox& box) {
    if (box.empty()) return;
    const std::int64_t first = std::max(box.min.x, box.max.x - static_cast<std::int64_t>(rows_.size()) + 1);
    for (std::int64_t x = first; x <= box.max.x; ++x) add_span(x, box.min.y, box.max.y);
  }
  /// Every span of `other`, as add_span() of each, with one modulo per
  /// ring rather than two per row (the foothold layers note every scan's).
  void add(const ChangedRows& other) {
    if (other.empty() || rows_.empty()) return;
    const CellBox& b = other.bounds_;
    if (b.max.x - b.min.x < static_cast<std::int64_t>(other.rows_.size())) {
      // No row of other was replaced: its bounds are its spans' box, no
      // need to find that box row by row.
      if (merge_rows<false>(other, b.min.x, b.max.x)) bounds_.add(b);
      return;
    }
    const std::int64_t first = b.max.x - static_cast<std::int64_t>(other.rows_.size()) + 1;
    merge_rows<true>(other, first, b.max.x);
  }

  bool empty() const { return bounds_.empty(); }
  /// Bounding box of what was added (may include rows since replaced).
  const CellBox& bounds() const { return bounds_; }
  /// The changed columns of row x; false when none are recorded.
  bool span(std::int64_t x, std::int64_t& lo, std::int64_t& hi) const {
    if (rows_.empty()) return false;
    const Row& r = rows_[place(x)];
    if (r.x != x || r.lo > r.hi) return false;
    lo = r.lo;
    hi = r.hi;
    return true;
  }
  void clear() {
    if (bounds_.empty()) return;
    const auto n = static_cast<std::int64_t>(rows_.size());
    if (bounds_.max.x - bounds_.min.x + 1 >= n) {
      std::fill(rows_.begin(), rows_.end(), Row{});
    } else {
      // At most two stretches of the ring, one modulo for both.
      const auto first = static_cast<std::ptrdiff_t>(place(bounds_.min.x));
      const std::int64_t count = bounds_.max.x - bounds_.min.x + 1;
      const std::int64_t before_end = std::min<std::int64_t>(count, n - first);
      std::fill(rows_.begin() + first, rows_.begin() + first + before_end, Row{});
      std::fill(rows_.begin(), rows_.begin() + (count - before_end), Row{});
    }
    bounds_.clear();
  }

 private:
  struct Row {
    std::int64_t x = std::numeric_limits<std::int64_t>::min();
    std::int64_t lo = std::numeric_limits<std::int64_t>::max();
    std::int64_t hi = std::numeric_limits<std::int64_t>::min();
  };
  std::size_t place(std::int64_t x) const {
    const auto n = static_cast<std::int64_t>(rows_.size());
    const std::int64_t m = x % n;
    return static_cast<std::size_t>(m < 0 ? m + n : m);
  }
  // other's spans of rows first..last into this record's; false when none
  // was there. kBoxRows: the bounds grow by the box of the rows merged.
  template <bool kBoxRows>
  bool merge_rows(const ChangedRows& other, std::int64_t first, std::int64_t last) {
    const std::size_t n_other = other.rows_.size(), n = rows_.size();
    std::size_t from = other.place(first), to = place(first);
    const Row* theirs = other.rows_.data();
    Row* ours = rows_.data();
    bool merged = false;
    // The box of the rows merged, grown once at the end by its two corners.
    std::int64_t first_x = 0, last_x = 0;
    std::int64_t lo_y = std::numeric_limits<std::int64_t>::max(), hi_y = std::numeric_limits<std::int64_t>::min();
    // Stretches of rows along which neither ring wraps.
    for (std::int64_t x = first; x <= last;) {
      const auto stretch = static_cast<std::size_t>(
          std::min<std::int64_t>(last - x + 1, static_cast<std::int64_t>(std::min(n_other - from, n - to))));
      for (std::size_t k = 0; k < stretch; ++k) {
        const Row& o = theirs[from + k];
        const std::int64_t row_x = x + static_cast<std::int64_t>(k);
        if (o.x == row_x && o.lo <= o.hi) {
          Row& r = ours[to + k];
          if (r.x != row_x) {
            r = Row{row_x, std::numeric_limits<std::int64_t>::max(), std::numeric_limits<std::int64_t>::min()};
          }
          r.lo = std::min(r.lo, o.lo);
          r.hi = std::max(r.hi, o.hi);
          merged = true;
          if constexpr (kBoxRows) {
            if (lo_y > hi_y) first_x = row_x;
            last_x = row_x;
            lo_y = std::min(lo_y, o.lo);
            hi_y = std::max(hi_y, o.hi);
          }
        }
      }
      x += static_cast<std::int64_t>(stretch);
      from += stretch;
      to += stretch;
      if (from == n_other) from = 0;
      if (to == n) to = 0;
    }
    if (kBoxRows && merged) {
      bounds_.add(CellIndex{first_x, lo_y});
      bounds_.add(CellIndex{last_x, hi_y});
    }
    return merged;
  }
  Row& row_for(std::int64_t x) {
    Row& r = rows_[place(x)];
    if (r.x != x) r = Row{x, std::numeric_limits<std::int64_t>::max(), std::numeric_limits<std::int64_t>::min()};
    return r;
  }

  std::vector<Row> rows_;
  CellBox bounds_;
};

}  // namespace stridemap
