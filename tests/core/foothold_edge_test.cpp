// The foothold layers' edge distances and scores against their definitions
// (the nearest cell whose step height exceeds max_step_m, by brute force
// over the search disc; the score's product, one cell at a time), and every
// layer against a refresh from scratch, bit for bit. The refresh searches row by row in blocks of
// columns, with shifts that reach past the disc and rows read in pairs;
// noisy readings here move steps back and forth across max_step_m all over
// a wandering window, read at uneven intervals, with search radii that
// round to each case of those shifts and windows that are no multiple of
// a block. The scores are computed four cells at a time.
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <limits>
#include <random>
#include <string>
#include <vector>

#include <Eigen/Core>
#include <gtest/gtest.h>

#include "stridemap/core/foothold.hpp"
#include "stridemap/core/terrain_mapper.hpp"

namespace stridemap {
namespace {

bool same_edge_bits(float a, float b) { return std::memcmp(&a, &b, sizeof a) == 0; }

// The edge distance of window-local cell (i, j) [m], as the layers define
// it before it is rounded to float.
double reference_edge_distance(const ElevationMap& map, const FootholdLayers& f, int i, int j) {
  const FootholdOptions& o = f.options();
  const int n = map.cells_per_side();
  const std::size_t s = map.slot(map.cell_at_local(i, j));
  const float z = map.elevation_data()[s];
  if (map.state_data()[s] == static_cast<std::uint8_t>(CellState::unknown) || !std::isfinite(z)) {
    return std::numeric_limits<double>::quiet_NaN();
  }
  const double cell = map.cell_size_m();
  const auto r = static_cast<int>(
      std::min<double>(std::floor(o.edge_search_radius_m / cell * (1.0 + 1e-9)), static_cast<double>(n)));
  const float* step = map.data(f.step_height());
  const auto max_step = static_cast<float>(o.max_step_m);
  int best = r * r + 1;
  for (int a = std::max(0, i - r); a <= std::min(n - 1, i + r); ++a) {
    for (int b = std::max(0, j - r); b <= std::min(n - 1, j + r); ++b) {
      const int d2 = (a - i) * (a - i) + (b - j) * (b - j);
      if (d2 < best && d2 <= r * r && step[map.slot(map.cell_at_local(a, b))] > max_step) best = d2;
    }
  }
  return best <= r * r ? std::sqrt(static_cast<double>(best)) * cell : o.edge_search_radius_m;
}

double reference_ramp(double value, double limit) { return std::clamp(1.0 - value / limit, 0.0, 1.0); }

// The score of the cell in slot s, edge distance distance_m, as the layers
// define it.
float reference_score(const ElevationMap& map, const FootholdLayers& f, std::size_t s, double distance_m) {
  const FootholdOptions& o = f.options();
  const float slope = map.data(f.slope())[s], step = map.data(f.step_height())[s];
  const float roughness = map.data(f.roughness())[s];
  if (std::isnan(slope) || std::isnan(step) || std::isnan(roughness) || std::isnan(distance_m)) {
    return std::numeric_limits<float>::quiet_NaN();
  }
  const double edge_factor = std::min(1.0, distance_m / o.edge_clearance_m);
  return static_cast<float>(reference_ramp(slope, o.max_slope_deg) * reference_ramp(step, o.max_step_m) *
                            reference_ramp(roughness, o.max_roughness_m) * edge_factor *
                            std::clamp(static_cast<double>(map.certainty_data()[s]) / o.full_certainty, 0.0, 1.0));
}

// A mapper of cells x cells 1 cm cells that takes scans in any order.
MapperOptions edge_test_mapper(int cells) {
  MapperOptions options;
  options.grid = GridOptions{cells, 0.01};
  options.reject_stale_scans = false;
  return options;
}

// Steps close to the 3 cm bound, so that noise moves cells across it.
FootholdOptions edge_test_foothold(double edge_radius_m) {
  FootholdOptions o;
  o.max_step_m = 0.03;
  o.edge_search_radius_m = edge_radius_m;
  return o;
}

// The first foothold layer of `map` that differs from a recomputation from
// scratch, bit for bit; empty when none does.
std::string layer_unlike_recomputed(const ElevationMap& map, const FootholdLayers& foothold) {
  ElevationMap scratch = map;
  FootholdLayers(scratch, foothold.options()).recompute_all(scratch);
  const auto cells = static_cast<std::size_t>(map.cells_per_side());
  for (LayerId<float> id : {foothold.slope(), foothold.roughness(), foothold.step_height(), foothold.edge_distance(),
                            foothold.score()}) {
    if (std::memcmp(map.data(id), scratch.data(id), cells * cells * sizeof(float)) != 0) {
      return map.layer_spec(id.index).name;
    }
  }
  return {};
}

void noisy_edge_walk(int cells, double edge_radius_m, unsigned seed) {
  SCOPED_TRACE(testing::Message() << cells << " cells, edge search radius " << edge_radius_m << " m");
  TerrainMapper mapper(edge_test_mapper(cells), SensorMount{});
  FootholdLayers foothold(mapper.map(), edge_test_foothold(edge_radius_m));
  foothold.recompute_all(mapper.map());
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> unit(-1.0, 1.0);
  std::uniform_int_distribution<int> gap(1, 9);
  // Steps close to max_step_m, so that noise moves cells across it.
  const auto ground = [](double x, double y) {
    return 0.02 * std::sin(13 * x) * std::cos(5 * y) + (std::fmod(std::abs(2 * x - y), 0.2) < 0.07 ? 0.03 : 0.0);
  };
  double x = 0.0, y = 0.0;
  std::vector<MapPoint> points;
  int next_read = gap(rng), refreshes = 0;
  std::size_t edges_seen = 0, distances = 0, scores = 0;
  for (int scan = 0; scan < 90; ++scan) {
    // Drift both ways, a jump now and then (once beyond the window).
    x += scan % 19 == 18 ? 0.2 * unit(rng) : 0.015 * unit(rng) + 0.004;
    y += scan % 13 == 12 ? 0.2 * unit(rng) : 0.015 * unit(rng) - 0.002;
    if (scan == 50) y += 0.6;
    TrunkPose pose;
    pose.x_m = x;
    pose.y_m = y;
    points.clear();
    for (int k = 0; k < 160; ++k) {  // a blob of readings ahead, 1 cm of noise
      const double px = x + 0.12 * unit(rng), py = y + 0.12 * unit(rng);
      points.push_back({px, py, ground(px, py) + 0.01 * unit(rng), 0.02});
    }
    mapper.integrate_points(points, pose);
    foothold.note(mapper.map(), mapper.changed_rows());
    mapper.clear_changed_cells();
    if (--next_read > 0) continue;
    next_read = gap(rng);
    foothold.refresh(mapper.map());
    ++refreshes;
    const ElevationMap& map = mapper.map();
    const float* edge_distance = map.data(foothold.edge_distance());
    for (int i = 0; i < cells; ++i) {
      for (int j = 0; j < cells; ++j) {
        const std::size_t s = map.slot(map.cell_at_local(i, j));
        const double distance_m = reference_edge_distance(map, foothold, i, j);
        const auto want = static_cast<float>(distance_m);
        ASSERT_TRUE(same_edge_bits(edge_distance[s], want))
            << "scan " << scan << " cell " << i << "," << j << ": " << edge_distance[s] << ", not " << want;
        const float score = reference_score(map, foothold, s, distance_m);
        ASSERT_TRUE(same_edge_bits(map.data(foothold.score())[s], score))
            << "score, scan " << scan << " cell " << i << "," << j << ": " << map.data(foothold.score())[s] << ", not "
            << score;
        scores += std::isfinite(score) && score > 0.0f && score < 1.0f ? 1 : 0;
        distances += std::isfinite(want) && want < static_cast<float>(edge_radius_m) ? 1 : 0;
        edges_seen += want == 0.0f ? 1 : 0;
      }
    }
    ASSERT_EQ(layer_unlike_recomputed(map, foothold), "") << "after scan " << scan;
  }
  EXPECT_GE(refreshes, 12);
  EXPECT_GT(edges_seen, 100u);  // edges, and cells near them, all along
  if (edge_radius_m >= 0.01) EXPECT_GT(scores, 1000u);  // scores between the bounds
  if (edge_radius_m >= 0.01) EXPECT_GT(distances, 1000u);
}

TEST(FootholdEdges, DistancesEqualABruteForceSearchAndAFreshRefreshAtEveryRadius) {
  // Radii of 1 to 17 cells (the shifts' reach 1, 3, 7, 15, 31) and the
  // whole window; sides of 4 blocks and 4 blocks plus 5 columns.
  unsigned seed = 40;
  for (const int cells : {32, 37}) {
    for (const double radius : {0.0, 0.01, 0.03, 0.04, 0.07, 0.08, 0.1, 0.15, 0.16, 0.17, 1.0}) {
      noisy_edge_walk(cells, radius, ++seed);
      if (HasFatalFailure()) return;
    }
  }
}

// The visibility clean-up clears a cell by forgetting its measurement
// (ElevationMap::forget_measurement()), which leaves the foothold layers'
// last values for their keeper to compare with: edges cleared between two
// refreshes must lengthen the distances around them, and a cell cleared
// and measured again the same before a refresh must get its layers back.
TEST(FootholdEdges, CellsClearedBetweenRefreshesLeaveNoStaleValue) {
  constexpr int kCells = 40;
  TerrainMapper mapper(edge_test_mapper(kCells), SensorMount{});
  const FootholdOptions o = edge_test_foothold(0.05);
  FootholdLayers foothold(mapper.map(), o);
  // A 6 cm step across the window, every cell read once.
  const auto reading = [&](CellIndex c) {
    const Eigen::Vector2d centre = mapper.map().cell_center(c);
    return MapPoint{centre.x(), centre.y(), c.x > mapper.map().cell_at_local(kCells / 2, 0).x ? 0.06 : 0.0, 0.02};
  };
  std::vector<MapPoint> points;
  for (int i = 0; i < kCells; ++i) {
    for (int j = 0; j < kCells; ++j) points.push_back(reading(mapper.map().cell_at_local(i, j)));
  }
  mapper.integrate_points(points, TrunkPose{});
  foothold.recompute_all(mapper.map());
  ElevationMap& map = mapper.map();
  for (LayerId<float> id : {foothold.slope(), foothold.edge_distance(), foothold.score()}) {
    EXPECT_TRUE(map.derived(id.index));
  }
  EXPECT_FALSE(map.derived(layers::elevation.index));
  const float* step = map.data(foothold.step_height());
  // Clear every cell of ten rows within a cell of the step, the edges among them.
  CellBox cleared;
  int edges_cleared = 0;
  for (int i = kCells / 2 - 2; i <= kCells / 2 + 1; ++i) {
    for (int j = 5; j < 15; ++j) {
      const CellIndex c = map.cell_at_local(i, j);
      edges_cleared += step[map.slot(c)] > o.max_step_m ? 1 : 0;
      map.forget_measurement(map.slot(c));
      cleared.add(c);
    }
  }
  ASSERT_GT(edges_cleared, 10);
  foothold.update(map, cleared);
  EXPECT_EQ(layer_unlike_recomputed(map, foothold), "") << "after clearing edges";
  // Cleared, then read again as before, between two refreshes.
  foothold.recompute_all(map);
  const CellIndex again = map.cell_at_local(kCells / 2 + 5, 30);
  map.forget_measurement(map.slot(again));
  mapper.integrate_points(std::vector<MapPoint>{reading(again)}, TrunkPose{});
  ASSERT_FALSE(std::isnan(map.elevation(again)));
  foothold.note(map, mapper.changed_rows());
  CellBox one;
  one.add(again);
  foothold.update(map, one);
  EXPECT_EQ(layer_unlike_recomputed(map, foothold), "") << "after a cell was cleared and read again";
}

// A map whose foothold layers came from a file (declared, not marked).
TEST(FootholdEdges, TheLayersOfALoadedMapAreMarkedDerived) {
  GridOptions grid{16, 0.01};
  for (const LayerSpec& spec : foothold_layer_specs()) grid.extra_layers.push_back(spec);
  ElevationMap map(grid);
  const std::size_t score = *map.find_layer("foothold_score");
  EXPECT_FALSE(map.derived(score));
  FootholdLayers foothold(map, FootholdOptions{});
  EXPECT_TRUE(map.derived(score));
  EXPECT_EQ(foothold.score().index, score);
}

}  // namespace
}  // namespace stridemap
