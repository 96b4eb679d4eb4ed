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

#include "stridemap/core/visibility_clearing.hpp"

namespace stridemap {
namespace {

// The clean-up as it was before the pruning: every beam walks all its cells
// from the sensor, the crossings summed step by step.
class FullWalk {
 public:
  FullWalk(const ElevationMap& map, const VisibilityOptions& options)
      : options_(options),
        stamp_(static_cast<std::size_t>(map.cells_per_side()) * static_cast<std::size_t>(map.cells_per_side()), 0) {}

  void begin_scan() {
    ++scan_;
    have_last_hit_ = false;
    cleared_.clear();
    changed_.clear();
    stats_ = {};
  }

  void trace(ElevationMap& map, const VisibilityBeam& beam) {
    const Eigen::Vector3d d = beam.hit_m - beam.origin_m;
    const double range = d.norm();
    if (!(range > 0.0) || !std::isfinite(range) || !std::isfinite(beam.range_error_m) ||
        !std::isfinite(beam.height_error_m) || !beam.origin_m.allFinite()) {
      return;
    }
    const double cell = map.cell_size_m();
    const Eigen::Vector2d hit = beam.hit_m.head<2>();
    if (have_last_hit_ && options_.beam_spacing_cells > 0.0 &&
        (hit - last_hit_).squaredNorm() < std::pow(options_.beam_spacing_cells * cell, 2)) {
      return;
    }
    have_last_hit_ = true;
    last_hit_ = hit;
    ++stats_.beams_traced;
    const double t_stop = 1.0 - beam.range_error_m / range;
    if (!(t_stop > 0.0)) return;
    const double margin = options_.uncertainty_factor * beam.height_error_m + options_.relief_factor * cell;
    const double inverse_cell = 1.0 / cell;
    const double ox = beam.origin_m.x() * inverse_cell, oy = beam.origin_m.y() * inverse_cell;
    const double dx = d.x() * inverse_cell, dy = d.y() * inverse_cell;
    auto ix = static_cast<std::int64_t>(std::floor(ox)), iy = static_cast<std::int64_t>(std::floor(oy));
    const std::int64_t step_x = dx > 0 ? 1 : -1, step_y = dy > 0 ? 1 : -1;
    constexpr double kInf = std::numeric_limits<double>::infinity();
    double next_x = dx != 0.0 ? (static_cast<double>(ix + (dx > 0 ? 1 : 0)) - ox) / dx : kInf;
    double next_y = dy != 0.0 ? (static_cast<double>(iy + (dy > 0 ? 1 : 0)) - oy) / dy : kInf;
    const double delta_x = dx != 0.0 ? 1.0 / std::abs(dx) : kInf, delta_y = dy != 0.0 ? 1.0 / std::abs(dy) : kInf;
    const double z0 = beam.origin_m.z(), dz = d.z();
    double t_in = 0.0;
    while (true) {
      const double t_out = std::min(next_x, next_y);
      if (t_out > t_stop) break;
      const CellIndex c{ix, iy};
      if (map.contains(c)) {
        ++stats_.cells_crossed;
        const double z_beam_max = z0 + dz * (dz > 0 ? t_out : t_in);
        const std::size_t s = map.slot(c);
        if (map.elevation_data()[s] > z_beam_max + margin) contradict(map, c, s);
      }
      t_in = t_out;
      if (next_x < next_y) {
        ix += step_x;
        next_x += delta_x;
      } else {
        iy += step_y;
        next_y += delta_y;
      }
    }
  }

  const VisibilityStats& stats() const { return stats_; }
  const std::vector<ClearedCell>& cleared() const { return cleared_; }
  const CellBox& changed() const { return changed_; }

 private:
  void contradict(ElevationMap& map, CellIndex cell, std::size_t slot) {
    if (stamp_[slot] == scan_) return;
    stamp_[slot] = scan_;
    ++stats_.cells_contradicted;
    changed_.add(cell);
    if (static_cast<CellState>(map.state_data()[slot]) == CellState::measured) {
      float& certainty = map.certainty_data()[slot];
      certainty -= static_cast<float>(options_.certainty_decrement);
      if (certainty > 0.0f) return;
    }
    const float was = map.elevation_data()[slot];
    map.reset_slot(slot);
    ++stats_.cells_cleared;
    cleared_.push_back({cell, was});
  }

  VisibilityOptions options_;
  std::vector<std::uint32_t> stamp_;
  std::uint32_t scan_ = 0;
  bool have_last_hit_ = false;
  Eigen::Vector2d last_hit_{0.0, 0.0};
  std::vector<ClearedCell> cleared_;
  CellBox changed_;
  VisibilityStats stats_;
};

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

void expect_same_maps(const ElevationMap& a, const ElevationMap& b) {
  const std::size_t cells = static_cast<std::size_t>(a.cells_per_side()) * static_cast<std::size_t>(a.cells_per_side());
  EXPECT_EQ(std::memcmp(a.elevation_data(), b.elevation_data(), cells * sizeof(float)), 0);
  EXPECT_EQ(std::memcmp(a.certainty_data(), b.certainty_data(), cells * sizeof(float)), 0);
  EXPECT_EQ(std::memcmp(a.state_data(), b.state_data(), cells), 0);
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
