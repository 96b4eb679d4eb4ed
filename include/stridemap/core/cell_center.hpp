#pragma once
// Where a cell lies in the map frame. Every map form (the window, an
// export, a ROS message, a grid file's origin) places cells through this
// one expression, so that their coordinates agree to the bit.
#include <Eigen/Core>

#include "stridemap/core/grid_map.hpp"

namespace stridemap {

/// Centre of a cell in the map frame [m]: cell (x, y) spans
/// [x, x + 1) * cell_size_m by [y, y + 1) * cell_size_m.
inline Eigen::Vector2d cell_center(CellIndex cell, double cell_size_m) {
  return {(static_cast<double>(cell.x) + 0.5) * cell_size_m, (static_cast<double>(cell.y) + 0.5) * cell_size_m};
}

}  // namespace stridemap
