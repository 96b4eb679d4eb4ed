#pragma once
// A rectangle of cells by global index, both corners inclusive: what a scan
// changed, so that derived layers (core/foothold.hpp) recompute only there.
// A box may be larger than what changed (a diagonal scan line gives a large
// one); it is never smaller, which is all that incremental updates need.
#include <algorithm>
#include <cstdint>
#include <limits>

#include "stridemap/core/grid_map.hpp"

namespace stridemap {

struct CellBox {
  CellIndex min{std::numeric_limits<std::int64_t>::max(), std::numeric_limits<std::int64_t>::max()};
  CellIndex max{std::numeric_limits<std::int64_t>::min(), std::numeric_limits<std::int64_t>::min()};

  bool empty() const { return min.x > max.x || min.y > max.y; }
  void add(CellIndex c) {
    min.x = std::min(min.x, c.x);
    min.y = std::min(min.y, c.y);
    max.x = std::max(max.x, c.x);
    max.y = std::max(max.y, c.y);
  }
  void add(const CellBox& b) {
    if (b.empty()) return;
    add(b.min);
    add(b.max);
  }
  void clear() { *this = CellBox{}; }
  /// Grown by `cells` on every side (empty stays empty).
  CellBox grown(std::int64_t cells) const {
    if (empty()) return *this;
    return {{min.x - cells, min.y - cells}, {max.x + cells, max.y + cells}};
  }
  /// The part that lies inside the map's window (may be empty).
  CellBox clipped_to(const ElevationMap& map) const {
    if (empty()) return *this;
    const CellIndex lo = map.min_cell();
    const std::int64_t n = map.cells_per_side();
    CellBox out{{std::max(min.x, lo.x), std::max(min.y, lo.y)}, {std::min(max.x, lo.x + n - 1), std::min(max.y, lo.y + n - 1)}};
    return out.empty() ? CellBox{} : out;
  }
  /// The cells in both (may be empty).
  CellBox intersected(const CellBox& b) const {
    CellBox out{{std::max(min.x, b.min.x), std::max(min.y, b.min.y)}, {std::min(max.x, b.max.x), std::min(max.y, b.max.y)}};
    return out.empty() ? CellBox{} : out;
  }
  friend bool operator==(const CellBox&, const CellBox&) = default;
  /// The map's whole window.
  static CellBox window_of(const ElevationMap& map) {
    const CellIndex lo = map.min_cell();
    const std::int64_t n = map.cells_per_side();
    return {lo, {lo.x + n - 1, lo.y + n - 1}};
  }
};

}  // namespace stridemap
