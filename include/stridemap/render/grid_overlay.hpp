#pragma once
// Drawing on top of a rendered map (grid_render.hpp): a path in map
// coordinates, e.g. the robot's track over the elevation map.
#include <array>
#include <cstdint>
#include <vector>

#include <Eigen/Core>

#include "stridemap/render/grid_render.hpp"

namespace stridemap::io {

/// Draws the polyline through `points_m` (map frame) onto the grid of
/// `rendered`, whose cell (0, 0) is centred at (origin_x_m, origin_y_m)
/// with cells of cell_size_m. Parts outside the grid are clipped; points
/// that are not finite break the line. A green dot marks the start and an
/// arrow past the last point the heading at the end.
void draw_path(RenderedGrid& rendered, const std::vector<Eigen::Vector2d>& points_m, double origin_x_m,
               double origin_y_m, double cell_size_m, std::array<std::uint8_t, 3> rgb = {220, 30, 30},
               int thickness_px = 2);

}  // namespace stridemap::io
