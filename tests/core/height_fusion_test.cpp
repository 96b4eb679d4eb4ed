#include "stridemap/core/height_fusion.hpp"

#include <cmath>
#include <random>

#include <gtest/gtest.h>

#include "stridemap/core/error.hpp"
#include "stridemap/core/map_update.hpp"

namespace stridemap {
namespace {

TEST(HeightFusion, NoisyReadingsOfAFlatCellAverageToTheSurfaceWhereTheHighestLiesAbove) {
  HeightFusionOptions options;
  std::mt19937_64 rng(7);
  std::normal_distribution<double> noise(0.0, 0.004);
  float fused = NAN, variance = NAN, highest = -1.0f;
  for (int k = 0; k < 40; ++k) {
    const double h = 0.05 + noise(rng);
    fuse_height(fused, variance, h, 0.004 * 0.004, options);
    highest = std::max(highest, static_cast<float>(h));
  }
  EXPECT_NEAR(fused, 0.05, 0.0015);
  EXPECT_GT(highest - 0.05, 0.005);  // eq. (10)'s bias, for contrast
  EXPECT_GE(variance, options.min_variance_m2 * (1 - 1e-6));
}

TEST(HeightFusion, AStrayReadingIsGatedOutAndAPersistentChangeGetsIn) {
  HeightFusionOptions options;
  float fused = NAN, variance = NAN;
  for (int k = 0; k < 10; ++k) ASSERT_TRUE(fuse_height(fused, variance, 0.0, 0.003 * 0.003, options));
  const float before = variance;
  EXPECT_FALSE(fuse_height(fused, variance, 0.03, 0.003 * 0.003, options));  // a mixed pixel
  EXPECT_FLOAT_EQ(fused, 0.0f);
  EXPECT_NEAR(variance, before + options.outlier_variance_m2, 1e-9);
  // A rock moved in: the cell opens to it after a few readings in a row.
  int readings = 1;
  while (!fuse_height(fused, variance, 0.03, 0.003 * 0.003, options)) ++readings;
  EXPECT_LT(readings, 15);
  EXPECT_GT(fused, 0.01f);
}

TEST(HeightFusion, WeightsReadingsByTheirVariance) {
  HeightFusionOptions options;
  options.mahalanobis_gate = 100.0;
  float fused = NAN, variance = NAN;
  fuse_height(fused, variance, 0.0, 0.001 * 0.001 * 4, options);  // sigma 2 mm
  fuse_height(fused, variance, 0.003, 0.002 * 0.002 * 4, options);  // sigma 4 mm: a quarter of the weight
  EXPECT_NEAR(fused, 0.003 * 0.2, 1e-7);
}

TEST(HeightFusion, DeclaresItsLayersWhichMoveAndResetWithTheMap) {
  ElevationMap map(GridOptions{20, 0.01});
  map.move_to(0.0, 0.0);
  const HeightFusion fusion(map);
  const HeightFusion again(map);  // a second one finds the layers there
  EXPECT_EQ(fusion.elevation_layer().index, again.elevation_layer().index);
  EXPECT_FALSE(map.layer_spec(fusion.elevation_layer().index).exported);
  EXPECT_TRUE(fusion.add(map, 0.015, 0.025, 0.04, 0.006));
  EXPECT_FALSE(fusion.add(map, 5.0, 0.0, 0.04, 0.006));  // outside the window
  EXPECT_FALSE(fusion.add(map, 0.0, 0.0, NAN, 0.006));
  const std::size_t slot = map.slot(map.cell_of(0.015, 0.025));
  EXPECT_FLOAT_EQ(map.data(fusion.elevation_layer())[slot], 0.04f);
  EXPECT_NEAR(map.data(fusion.variance_layer())[slot], 0.002 * 0.002, 1e-9);
  map.move_to(1.0, 1.0);
  map.move_to(0.0, 0.0);
  EXPECT_TRUE(std::isnan(map.data(fusion.elevation_layer())[map.slot(map.cell_of(0.015, 0.025))]));
}

TEST(HeightFusion, RefusesUnusableOptionsNamingTheField) {
  ElevationMap map(GridOptions{10, 0.01});
  HeightFusionOptions options;
  options.min_variance_m2 = -1.0;
  try {
    HeightFusion fusion(map, options);
    FAIL() << "accepted a negative variance floor";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("min_variance_m2"), std::string::npos) << e.what();
  }
  options = {};
  options.mahalanobis_gate = NAN;
  EXPECT_THROW(HeightFusion(map, options), InputError);
}

}  // namespace
}  // namespace stridemap
