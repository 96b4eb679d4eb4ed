// The pruned walk of the visibility clean-up (core/visibility_clearing.hpp)
// against the full walk it replaced, kept here as the reference: on random
// terrain (unknown, measured and filled cells, tall blocks, a window whose
// slots wrap) and random beams (falling, rising, level, vertical, along an
// axis, from inside and outside the window, with range errors beyond the
// range), every layer, count and cleared cell must be the same bit for bit.
#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cstdio>
#include <cmath>
#include <cstring>
#include <limits>
#include <random>
#include <vector>

#include "core/visibility_full_walk.hpp"
#include "stridemap/core/visibility_clearing.hpp"

namespace stridemap {
namespace {

using test::FullWalk;
using test::expect_same_maps;

// Rough terrain with blocks, unknown and filled cells, in a window moved
// so that its slots wrap.
ElevationMap random_map(std::mt19937_64& rng, int n, double cell_m) {
  ElevationMap map(GridOptions{n, cell_m});
  std::uniform_int_distribution<int> corner(-3 * n, 3 * n);
  map.move_corner_to({corner(rng), corner(rng)});
  std::uniform_real_distribution<double> u(0.0, 1.0);
  const double block_height = 0.02 + 0.3 * u(rng);
  const CellIndex lo = map.min_cell();
  const int blocks = std::uniform_int_distribution<int>(0, 4)(rng);
  std::vector<std::array<int, 4>> block_boxes;
  for (int b = 0; b < blocks; ++b) {
    const int x = std::uniform_int_distribution<int>(0, n - 1)(rng), y = std::uniform_int_distribution<int>(0, n - 1)(rng);
    block_boxes.push_back({x, y, x + std::uniform_int_distribution<int>(0, n / 4)(rng),
                           y + std::uniform_int_distribution<int>(0, n / 4)(rng)});
  }
  for (int i = 0; i < n; ++i) {
    for (int j = 0; j < n; ++j) {
      const std::size_t s = map.slot({lo.x + i, lo.y + j});
      const double roll = u(rng);
      if (roll < 0.15) continue;  // unknown
      double h = 0.003 * (u(rng) - 0.5) + 0.02 * std::sin(0.3 * i) * std::cos(0.2 * j);
      for (const auto& box : block_boxes) {
        if (i >= box[0] && i <= box[2] && j >= box[1] && j <= box[3]) h += block_height;
      }
      map.elevation_data()[s] = static_cast<float>(h);
      if (roll < 0.25) {
        map.state_data()[s] = static_cast<std::uint8_t>(CellState::filled);
      } else {
        map.state_data()[s] = static_cast<std::uint8_t>(CellState::measured);
        map.certainty_data()[s] = static_cast<float>(1 + std::uniform_int_distribution<int>(0, 12)(rng));
      }
    }
  }
  return map;
}

// A beam from a sensor above (or beside) the window: mostly falling to the
// terrain, some rising, level, vertical or along an axis.
VisibilityBeam random_beam(std::mt19937_64& rng, const ElevationMap& map, const Eigen::Vector3d& sensor) {
  std::uniform_real_distribution<double> u(0.0, 1.0);
  const double cell = map.cell_size_m();
  const double n = map.cells_per_side();
  const Eigen::Vector2d lo(map.min_cell().x * cell, map.min_cell().y * cell);
  VisibilityBeam b;
  b.origin_m = sensor;
  const double kind = u(rng);
  Eigen::Vector2d target = lo + Eigen::Vector2d(u(rng) * 1.4 - 0.2, u(rng) * 1.4 - 0.2) * n * cell;
  if (kind < 0.05) target = sensor.head<2>();                                              // vertical
  else if (kind < 0.1) target.x() = sensor.x();                                            // along y
  else if (kind < 0.15) target.y() = sensor.y();                                           // along x
  else if (kind < 0.2) target = (target / cell).array().round().matrix() * cell;          // on a corner
  double z = 0.4 * (u(rng) - 0.3);
  if (kind > 0.9) z = sensor.z() + 0.2 * u(rng);  // rising
  else if (kind > 0.85) z = sensor.z();           // level
  b.hit_m = {target.x(), target.y(), z};
  const double range = (b.hit_m - b.origin_m).norm();
  b.range_error_m = u(rng) < 0.05 ? range * (1.0 + u(rng)) : 0.02 * u(rng) * range;
  b.height_error_m = 0.01 * u(rng);
  return b;
}

TEST(VisibilityPruning, SameResultAsTheFullWalkOnRandomTerrainAndBeams) {
  std::size_t contradicted = 0, cleared = 0, walked = 0, walked_full = 0;
  for (std::uint64_t seed = 1; seed <= 60; ++seed) {
    SCOPED_TRACE("seed " + std::to_string(seed));
    std::mt19937_64 rng(seed);
    std::uniform_real_distribution<double> u(0.0, 1.0);
    const int n = seed % 3 == 0 ? 17 : 40;
    const double cell = seed % 2 == 0 ? 0.01 : 0.05;
    ElevationMap map = random_map(rng, n, cell);
    ElevationMap reference_map = map;
    VisibilityOptions options;
    options.beam_spacing_cells = seed % 4 == 0 ? 0.0 : 0.5;
    options.relief_factor = seed % 5 == 0 ? 0.0 : 1.0;
    VisibilityClearing pruned(map, options);
    FullWalk full(map, options);
    const double extent = n * cell;
    for (int scan = 0; scan < 4; ++scan) {
      const Eigen::Vector3d sensor(map.min_cell().x * cell + extent * (1.6 * u(rng) - 0.3),
                                   map.min_cell().y * cell + extent * (1.6 * u(rng) - 0.3), 0.05 + 0.4 * u(rng));
      pruned.begin_scan(map);
      full.begin_scan();
      for (int k = 0; k < 300; ++k) {
        const VisibilityBeam beam = random_beam(rng, map, sensor);
        pruned.trace(map, beam);
        full.trace(reference_map, beam);
      }
      expect_same_maps(map, reference_map);
      EXPECT_EQ(pruned.stats().beams_traced, full.stats().beams_traced);
      EXPECT_EQ(pruned.stats().cells_contradicted, full.stats().cells_contradicted);
      EXPECT_EQ(pruned.stats().cells_cleared, full.stats().cells_cleared);
      EXPECT_LE(pruned.stats().cells_crossed, full.stats().cells_crossed);
      ASSERT_EQ(pruned.cleared().size(), full.cleared().size());
      for (std::size_t c = 0; c < full.cleared().size(); ++c) {
        EXPECT_EQ(pruned.cleared()[c].cell, full.cleared()[c].cell);
        EXPECT_EQ(pruned.cleared()[c].elevation_m, full.cleared()[c].elevation_m);
      }
      EXPECT_EQ(pruned.changed().min, full.changed().min);
      EXPECT_EQ(pruned.changed().max, full.changed().max);
      contradicted += full.stats().cells_contradicted;
      cleared += full.stats().cells_cleared;
      walked += pruned.stats().cells_crossed;
      walked_full += full.stats().cells_crossed;
    }
  }
  // The comparison means something only if beams did clear cells, and the
  // pruning is there only if it walked less.
  EXPECT_GT(contradicted, 1000u);
  EXPECT_GT(cleared, 300u);
  EXPECT_LT(walked, walked_full / 2);
  std::printf("contradicted %zu, cleared %zu, cells walked %zu of %zu\n", contradicted, cleared, walked, walked_full);
}

// A block near the sensor, below the beam, and a floor where the beam ends:
// the window's bound (the block) puts the walk's start near the end, and
// the rows and columns left from there hold only floor, so the bound taken
// again there ends the walk before its first cell. Same result as the full
// walk, which walks the whole beam.
TEST(VisibilityPruning, TheBoundNarrowedAlongTheBeamEndsAWalkOverTheFloor) {
  ElevationMap map(GridOptions{40, 0.01});
  map.move_corner_to({0, 0});
  for (int i = 0; i < 40; ++i) {
    for (int j = 0; j < 40; ++j) {
      const std::size_t s = map.slot({i, j});
      const bool block = i >= 8 && i <= 10 && j >= 8 && j <= 10;
      map.elevation_data()[s] = block ? 0.1f : 0.0f;
      map.state_data()[s] = static_cast<std::uint8_t>(CellState::measured);
      map.certainty_data()[s] = 5.0f;
    }
  }
  ElevationMap reference_map = map;
  VisibilityOptions options;
  VisibilityClearing pruned(map, options);
  FullWalk full(map, options);
  VisibilityBeam beam;
  beam.origin_m = {0.055, 0.055, 0.3};
  beam.hit_m = {0.355, 0.355, 0.0};
  beam.range_error_m = 0.01;
  beam.height_error_m = 0.005;
  pruned.begin_scan(map);
  full.begin_scan();
  pruned.trace(map, beam);
  full.trace(reference_map, beam);
  expect_same_maps(map, reference_map);
  EXPECT_EQ(full.stats().cells_contradicted, 0u);
  EXPECT_GT(full.stats().cells_crossed, 40u);
  EXPECT_EQ(pruned.stats().beams_traced, 1u);
  EXPECT_EQ(pruned.stats().cells_crossed, 0u);
}

}  // namespace
}  // namespace stridemap
