#pragma once
// A hook on the robot-centred window's moves (TerrainMapper::follow): told
// which cells are about to leave the window while they still hold their
// values, and which cells entered once they hold their reset values. What
// keeps a map larger than the window (mapfile/tile_store.hpp) sits here, so that
// it never depends on how the grid stores its cells.
#include "stridemap/core/grid_map.hpp"

namespace stridemap {

class WindowMoveListener {
 public:
  virtual ~WindowMoveListener() = default;
  /// The window's corner is about to go from map.min_cell() to `new_min`;
  /// the cells of the old window outside the new one still hold their
  /// values. Throwing leaves the window where it is.
  virtual void window_leaving(const ElevationMap& map, CellIndex new_min) = 0;
  /// The window's corner went from `old_min` to map.min_cell(); the cells
  /// of the new window outside the old one hold their reset values.
  virtual void window_entered(ElevationMap& map, CellIndex old_min) = 0;
};

}  // namespace stridemap
