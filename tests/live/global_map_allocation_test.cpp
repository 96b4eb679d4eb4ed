// The global map allocates nothing while the window moves within tiles it
// holds in memory or over ground no tile holds: only taking a tile from
// disk, or writing one the window left, does. Counted with the operator new of allocation_test.cpp.
#include <gtest/gtest.h>

#include "allocation_counting.hpp"
#include "live/test_folder.hpp"
#include "stridemap/core/terrain_mapper.hpp"
#include "stridemap/mapfile/tile_store.hpp"

namespace stridemap {
namespace {

using test::allocation_counter;

TrunkPose at(double x_m, double y_m) {
  TrunkPose p;
  p.x_m = x_m;
  p.y_m = y_m;
  return p;
}

TEST(GlobalMapAllocation, MovesWithinCachedTilesAllocateNothing) {
  STRIDEMAP_SKIP_UNLESS_COUNTING_ALLOCATIONS();
  test::TestFolder folder;
  MapperOptions options;
  options.grid.cells_per_side = 100;
  options.reject_stale_scans = false;
  TerrainMapper mapper(options, SensorMount{});
  GlobalMapOptions tiles;
  tiles.folder = folder / "tiles";
  tiles.tile_cells = 100;
  tiles.cached_tiles = 16;
  io::TileStore store(tiles, mapper.map(), {});
  mapper.set_window_listener(&store);
  // Something in every cell, so that every move saves and restores cells.
  std::vector<MapPoint> points;
  for (int i = -60; i < 60; ++i) {
    for (int j = -60; j < 60; ++j) points.push_back({0.01 * i + 0.005, 0.01 * j + 0.005, 0.02, 0.05});
  }
  // Warm-up: the path below once, so that every tile it touches is in memory.
  const auto drive = [&](double phase) {
    for (int k = 0; k < 200; ++k) {
      const double t = 0.01 * k;
      mapper.integrate_points({}, at(0.3 * std::sin(t * 3 + phase), 0.25 * std::cos(t * 2)));
    }
  };
  mapper.integrate_points(points, at(0.0, 0.0));
  drive(0.0);
  drive(0.0);
  ASSERT_GT(store.stats().cells_restored, 0u);
  allocation_counter().allocations = 0;
  allocation_counter().counting = true;
  const std::size_t restored_before = store.stats().cells_restored;
  drive(0.0);
  allocation_counter().counting = false;
  // Leaving the tiles writes them (a file write allocates, as a read does)...
  const std::size_t written_before = store.stats().tiles_written;
  mapper.integrate_points({}, at(40.0, 30.0));
  EXPECT_EQ(store.stats().tiles_written, written_before + 4) << "the four tiles the window left";
  // ...and then, over ground no tile holds: nothing to save, nothing to load.
  allocation_counter().counting = true;
  for (int k = 1; k < 100; ++k) mapper.integrate_points({}, at(40.0 + 0.013 * k, 30.0));
  allocation_counter().counting = false;
  EXPECT_EQ(allocation_counter().allocations.load(), 0u);
  EXPECT_GT(store.stats().cells_restored, restored_before);
}

}  // namespace
}  // namespace stridemap
