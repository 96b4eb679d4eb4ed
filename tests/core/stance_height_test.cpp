#include "stridemap/core/stance_height.hpp"

#include <cmath>
#include <vector>

#include <gtest/gtest.h>

#include "stridemap/core/error.hpp"
#include "stridemap/core/height_fusion.hpp"

namespace stridemap {
namespace {

// A 40 x 40 window of 10 mm cells around the origin with its fused layers;
// ground(x, y) gives each cell's fused height and variance.
template <typename Ground>
ElevationMap fused_map(Ground ground, double variance_m2 = 0.0015 * 0.0015) {
  ElevationMap map(GridOptions{40, 0.01});
  map.move_to(0.0, 0.0);
  const HeightFusion fusion(map);
  for (int i = 0; i < map.cells_per_side(); ++i) {
    for (int j = 0; j < map.cells_per_side(); ++j) {
      const CellIndex c = map.cell_at_local(i, j);
      const double x = (c.x + 0.5) * 0.01, y = (c.y + 0.5) * 0.01;
      const double h = ground(x, y);
      const std::size_t slot = map.slot(c);
      map.data(fusion.elevation_layer())[slot] = static_cast<float>(h);
      map.data(fusion.variance_layer())[slot] = std::isnan(h) ? NAN : static_cast<float>(variance_m2);
    }
  }
  return map;
}

TEST(StanceHeight, TheTrunkStandsAboveTheGroundUnderItsFeetByTheirDepths) {
  const ElevationMap map = fused_map([](double, double) { return 0.03; });
  const StanceHeightReader reader(map);
  const std::vector<StanceFoot> feet{{0.1, 0.05, 0.12}, {-0.1, 0.05, 0.12}, {0.0, -0.05, 0.12}};
  const StanceHeight h = reader.read(map, feet);
  EXPECT_EQ(h.feet_read, 3);
  EXPECT_EQ(h.feet_used, 3);
  EXPECT_NEAR(h.trunk_z_m, 0.15, 1e-6);
  // Three feet of equal weight: a third of one foot's variance.
  const double one = 0.0015 * 0.0015 + 0.002 * 0.002;
  EXPECT_NEAR(h.variance_m2, one / 3.0, 1e-12);
  for (int k = 0; k < 3; ++k) EXPECT_NEAR(h.feet[static_cast<std::size_t>(k)].ground_m, 0.03, 1e-6);
}

TEST(StanceHeight, AFootOnARockEdgeWeighsLessAndAFootFarOffIsGatedOut) {
  // A step of 5 cm at x = 0.15 m: the foot at 0.15 stands on its edge (its
  // sole's cells spread), the one at -0.1 on a stray 3 cm lump.
  const ElevationMap map = fused_map([](double x, double y) {
    if (x > 0.15) return 0.05;
    if (std::abs(x + 0.1) < 0.025 && std::abs(y - 0.05) < 0.025) return 0.03;
    return 0.0;
  });
  const StanceHeightReader reader(map);
  const std::vector<StanceFoot> feet{{0.0, 0.05, 0.1}, {-0.1, 0.05, 0.1}, {0.0, -0.05, 0.1}, {0.151, -0.05, 0.1}};
  const StanceHeight h = reader.read(map, feet);
  EXPECT_EQ(h.feet_read, 4);
  EXPECT_FALSE(h.feet[1].used);  // 30 mm off the others: beyond 2.5 sigma
  EXPECT_TRUE(h.feet[0].used);
  EXPECT_GT(h.feet[3].variance_m2, 10 * h.feet[0].variance_m2);  // the edge's spread
  EXPECT_NEAR(h.trunk_z_m, 0.1, 0.005);

  StanceHeightOptions keep_all;
  keep_all.gate_sigmas = std::numeric_limits<double>::infinity();
  const StanceHeight all = StanceHeightReader(map, keep_all).read(map, feet);
  EXPECT_EQ(all.feet_used, 4);
  EXPECT_GT(all.trunk_z_m, h.trunk_z_m + 0.001);  // the lump lifts the robot, its spread weighing it down
}

TEST(StanceHeight, ASoleMostlyOverUnknownCellsHasNoSay) {
  // Known only for x < 0.1: a sole centred at x = 0.11 sees under half its
  // cells; one outside the window sees none.
  const ElevationMap map = fused_map([](double x, double) { return x < 0.1 ? 0.02 : NAN; });
  const StanceHeightReader reader(map);
  const std::vector<StanceFoot> feet{{0.0, 0.0, 0.1}, {0.11, 0.0, 0.1}, {5.0, 5.0, 0.1}};
  const StanceHeight h = reader.read(map, feet);
  EXPECT_EQ(h.feet_read, 1);
  EXPECT_TRUE(h.feet[0].used);
  EXPECT_FALSE(h.feet[1].read);
  EXPECT_FALSE(h.feet[2].read);
  EXPECT_NEAR(h.trunk_z_m, 0.12, 1e-6);
  EXPECT_TRUE(reader.ground_under(map, 0.11, 0.0).has_value());  // read, but under the share
  EXPECT_FALSE(reader.ground_under(map, 5.0, 5.0).has_value());

  const StanceHeight none = reader.read(map, std::vector<StanceFoot>{{0.3, 0.0, 0.1}});
  EXPECT_EQ(none.feet_used, 0);
  EXPECT_TRUE(std::isnan(none.trunk_z_m));
}

TEST(StanceHeight, BadFeetAndAMapWithoutTheLayersAreErrorsNamingThem) {
  const ElevationMap map = fused_map([](double, double) { return 0.0; });
  const StanceHeightReader reader(map);
  try {
    reader.read(map, std::vector<StanceFoot>{{0.0, 0.0, 0.1}, {0.0, NAN, 0.1}});
    FAIL() << "a NaN foot was read";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("foot 1: y_m: expected a finite number, got nan"), std::string::npos) << e.what();
  }
  EXPECT_THROW(reader.read(map, std::vector<StanceFoot>{{0.0, 0.0, INFINITY}}), InputError);
  EXPECT_THROW(reader.read(map, std::vector<StanceFoot>(StanceHeight::kMaxFeet + 1)), InputError);

  ElevationMap bare(GridOptions{10, 0.01});
  try {
    const StanceHeightReader without(bare);
    FAIL() << "a map without the fused layers was taken";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("needs the layer fused_elevation"), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find("the map has elevation"), std::string::npos) << e.what();
  }
  for (auto bad : {+[](StanceHeightOptions& o) { o.sole_radius_m = 0.0; },
                   +[](StanceHeightOptions& o) { o.min_known_share = 1.5; },
                   +[](StanceHeightOptions& o) { o.gate_sigmas = NAN; },
                   +[](StanceHeightOptions& o) { o.depth_sigma_m = -1.0; }}) {
    StanceHeightOptions options;
    bad(options);
    EXPECT_THROW(StanceHeightReader(map, options), InputError);
  }
}

}  // namespace
}  // namespace stridemap
