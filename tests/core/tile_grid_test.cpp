// Tile arithmetic (core/tile_grid.hpp): which tile holds a cell, a tile's
// cells, and tiles as keys.
#include <gtest/gtest.h>

#include <cstdint>
#include <set>

#include "stridemap/core/tile_grid.hpp"

namespace stridemap {
namespace {

TEST(TileGrid, FloorDivRoundsTowardsMinusInfinity) {
  EXPECT_EQ(floor_div(7, 8), 0);
  EXPECT_EQ(floor_div(8, 8), 1);
  EXPECT_EQ(floor_div(0, 8), 0);
  EXPECT_EQ(floor_div(-1, 8), -1);
  EXPECT_EQ(floor_div(-8, 8), -1);
  EXPECT_EQ(floor_div(-9, 8), -2);
}

TEST(TileGrid, TileOfHoldsTheCellOnBothSidesOfZero) {
  EXPECT_EQ(tile_of({0, 7}, 8), (TileIndex{0, 0}));
  EXPECT_EQ(tile_of({-1, 8}, 8), (TileIndex{-1, 1}));
  EXPECT_EQ(tile_of({-8, -9}, 8), (TileIndex{-1, -2}));
  EXPECT_EQ(tile_of({5, -5}, 1), (TileIndex{5, -5}));
}

TEST(TileGrid, EveryCellLiesInsideItsTile) {
  for (const std::int64_t t : {1, 3, 8}) {
    for (std::int64_t x = -20; x <= 20; ++x) {
      const CellIndex cell{x, -x};
      const TileIndex tile = tile_of(cell, t);
      const CellIndex lo = tile_min_cell(tile, t), end = tile_end_cell(tile, t);
      EXPECT_LE(lo.x, cell.x);
      EXPECT_LT(cell.x, end.x);
      EXPECT_LE(lo.y, cell.y);
      EXPECT_LT(cell.y, end.y);
      EXPECT_EQ(end.x - lo.x, t);
      EXPECT_EQ(end.y - lo.y, t);
    }
  }
}

TEST(TileGrid, TileCornersAndEnds) {
  EXPECT_EQ(tile_min_cell({-1, 2}, 100), (CellIndex{-100, 200}));
  EXPECT_EQ(tile_end_cell({-1, 2}, 100), (CellIndex{0, 300}));
}

TEST(TileGrid, TileMeetsACellRangeOnlyWhenTheyShareACell) {
  const TileIndex tile{1, 0};  // cells [10, 20) x [0, 10)
  EXPECT_TRUE(tile_meets(tile, 10, {0, 0}, {11, 1}));
  EXPECT_FALSE(tile_meets(tile, 10, {0, 0}, {10, 10}));   // ends where the tile starts
  EXPECT_FALSE(tile_meets(tile, 10, {20, 0}, {30, 10}));  // starts where the tile ends
  EXPECT_TRUE(tile_meets(tile, 10, {19, 9}, {40, 40}));
  EXPECT_FALSE(tile_meets(tile, 10, {12, 10}, {15, 20}));  // beside it in y
  EXPECT_TRUE(tile_meets(tile, 10, {-100, -100}, {100, 100}));
}

TEST(TileGrid, TilesOrderAsKeys) {
  const std::set<TileIndex> tiles{{1, 0}, {-1, 5}, {0, 0}, {-1, -5}, {1, 0}};
  ASSERT_EQ(tiles.size(), 4u);
  EXPECT_EQ(*tiles.begin(), (TileIndex{-1, -5}));
  EXPECT_EQ(*tiles.rbegin(), (TileIndex{1, 0}));
}

}  // namespace
}  // namespace stridemap
