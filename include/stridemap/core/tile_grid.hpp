#pragma once
// Square tiles of tile_cells x tile_cells cells laid on the map's cell
// grid: tile (x, y) holds the cells [x * tile_cells, (x + 1) * tile_cells)
// x [y * tile_cells, (y + 1) * tile_cells). Tiles are fixed to global cell
// indices, not to the window, so a cell lands in the same tile however the
// window moved before it was seen (the tile store, mapfile/tile_store.hpp).
// All arguments tile_cells are > 0.
#include <compare>
#include <cstdint>

#include "stridemap/core/grid_map.hpp"

namespace stridemap {

/// A tile's integer coordinates; ordered, so that it can key a set or map.
struct TileIndex {
  std::int64_t x = 0;
  std::int64_t y = 0;
  friend auto operator<=>(const TileIndex&, const TileIndex&) = default;
};

/// a / b rounded towards minus infinity (b > 0): the tile of cell -1 is
/// tile -1, where integer division would give 0.
inline std::int64_t floor_div(std::int64_t a, std::int64_t b) {
  const std::int64_t q = a / b;
  return (a % b != 0 && (a < 0) != (b < 0)) ? q - 1 : q;
}

/// The tile holding a cell.
inline TileIndex tile_of(CellIndex cell, std::int64_t tile_cells) {
  return {floor_div(cell.x, tile_cells), floor_div(cell.y, tile_cells)};
}

/// The tile's corner cell (smallest x and y).
inline CellIndex tile_min_cell(TileIndex tile, std::int64_t tile_cells) {
  return {tile.x * tile_cells, tile.y * tile_cells};
}

/// One past the tile's last cell on both axes.
inline CellIndex tile_end_cell(TileIndex tile, std::int64_t tile_cells) {
  return {(tile.x + 1) * tile_cells, (tile.y + 1) * tile_cells};
}

/// Whether the tile shares a cell with the cells [min, end).
inline bool tile_meets(TileIndex tile, std::int64_t tile_cells, CellIndex min, CellIndex end) {
  const CellIndex lo = tile_min_cell(tile, tile_cells), hi = tile_end_cell(tile, tile_cells);
  return lo.x < end.x && hi.x > min.x && lo.y < end.y && hi.y > min.y;
}

}  // namespace stridemap
