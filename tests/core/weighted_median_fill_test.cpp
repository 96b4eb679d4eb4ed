#include "stridemap/core/weighted_median_fill.hpp"

#include <cmath>

#include <gtest/gtest.h>

#include "stridemap/core/error.hpp"

namespace stridemap {
namespace weighted_median_fill_test {
namespace {

void measure(ElevationMap& map, int i, int j, float h, float c = 3.0f) {
  const std::size_t s = map.slot(map.cell_at_local(i, j));
  map.elevation_data()[s] = h;
  map.certainty_data()[s] = c;
  map.state_data()[s] = static_cast<std::uint8_t>(CellState::measured);
}

CellState state_at(const ElevationMap& map, int i, int j) { return map.state(map.cell_at_local(i, j)); }
float elevation_at(const ElevationMap& map, int i, int j) { return map.elevation(map.cell_at_local(i, j)); }

TEST(WeightedMedianFill, FillsASmallHoleInsideAPlane) {
  ElevationMap map({20, 0.01});
  for (int i = 0; i < 20; ++i)
    for (int j = 0; j < 20; ++j) measure(map, i, j, 0.05f);
  const std::size_t hole = map.slot(map.cell_at_local(10, 10));
  map.reset_slot(hole);
  WeightedMedianFill fill;
  EXPECT_EQ(fill.apply(map), 1u);
  EXPECT_EQ(state_at(map, 10, 10), CellState::filled);
  EXPECT_FLOAT_EQ(elevation_at(map, 10, 10), 0.05f);
  EXPECT_EQ(map.certainty(map.cell_at_local(10, 10)), 0.0f);
}

TEST(WeightedMedianFill, MedianIgnoresASingleSpike) {
  ElevationMap map({10, 0.01});
  for (int i = 0; i < 10; ++i)
    for (int j = 0; j < 10; ++j) measure(map, i, j, 0.0f);
  measure(map, 4, 5, 1.0f);  // an outlier next to the hole, as certain as the rest
  map.reset_slot(map.slot(map.cell_at_local(5, 5)));
  WeightedMedianFill().apply(map);
  EXPECT_FLOAT_EQ(elevation_at(map, 5, 5), 0.0f);
}

TEST(WeightedMedianFill, CertaintyWeightsDecide) {
  // Left half high with high certainty, right half low with low certainty:
  // the weighted median follows the certain side.
  ElevationMap map({9, 0.01});
  for (int i = 0; i < 9; ++i)
    for (int j = 0; j < 9; ++j) measure(map, i, j, j < 4 ? 0.2f : 0.0f, j < 4 ? 30.0f : 3.0f);
  map.reset_slot(map.slot(map.cell_at_local(4, 4)));
  WeightedMedianFill().apply(map);
  EXPECT_FLOAT_EQ(elevation_at(map, 4, 4), 0.2f);
}

TEST(WeightedMedianFill, LargeOcclusionStaysUnknown) {
  ElevationMap map({30, 0.01});
  for (int i = 0; i < 30; ++i)
    for (int j = 0; j < 30; ++j)
      if (!(i >= 10 && i < 20 && j >= 10 && j < 20)) measure(map, i, j, 0.0f);
  WeightedMedianFill fill;
  fill.apply(map);
  EXPECT_EQ(state_at(map, 15, 15), CellState::unknown);
  EXPECT_TRUE(std::isnan(elevation_at(map, 15, 15)));
  EXPECT_EQ(state_at(map, 12, 15), CellState::unknown);
}

TEST(WeightedMedianFill, DoesNotExtrapolateBeyondAnEdge) {
  // Known cells only on one side (the edge of the observed stripe): the
  // quadrant rule refuses to extend the surface outward.
  ElevationMap map({20, 0.01});
  for (int i = 0; i < 10; ++i)
    for (int j = 0; j < 20; ++j) measure(map, i, j, 0.1f);
  WeightedMedianFill().apply(map);
  for (int j = 0; j < 20; ++j) EXPECT_EQ(state_at(map, 10, j), CellState::unknown) << j;
}

TEST(WeightedMedianFill, LeavesCellsOnAStepUnknown) {
  // Half the neighbours on a box top, half on the floor: no honest value.
  ElevationMap map({9, 0.01});
  for (int i = 0; i < 9; ++i)
    for (int j = 0; j < 9; ++j) measure(map, i, j, j < 4 ? 0.1f : 0.0f);
  map.reset_slot(map.slot(map.cell_at_local(4, 4)));
  WeightedMedianFill fill;
  EXPECT_EQ(fill.apply(map), 0u);
  EXPECT_EQ(state_at(map, 4, 4), CellState::unknown);
  FillOptions no_step_test;
  no_step_test.max_quartile_spread_m = 0.0;
  EXPECT_EQ(WeightedMedianFill(no_step_test).apply(map), 1u);
}

TEST(WeightedMedianFill, RecomputesFilledCellsFromNewData) {
  ElevationMap map({10, 0.01});
  for (int i = 0; i < 10; ++i)
    for (int j = 0; j < 10; ++j) measure(map, i, j, 0.0f);
  map.reset_slot(map.slot(map.cell_at_local(5, 5)));
  WeightedMedianFill fill;
  fill.apply(map);
  for (int i = 0; i < 10; ++i)
    for (int j = 0; j < 10; ++j)
      if (!(i == 5 && j == 5)) measure(map, i, j, 0.3f);
  fill.apply(map);
  EXPECT_FLOAT_EQ(elevation_at(map, 5, 5), 0.3f);
  // And a filled cell whose support disappears becomes unknown again.
  for (int i = 0; i < 10; ++i)
    for (int j = 0; j < 10; ++j)
      if (!(i == 5 && j == 5)) map.reset_slot(map.slot(map.cell_at_local(i, j)));
  EXPECT_EQ(fill.apply(map), 0u);
  EXPECT_EQ(state_at(map, 5, 5), CellState::unknown);
}

TEST(WeightedMedianFill, RejectsBadOptions) {
  EXPECT_THROW(WeightedMedianFill({0, 8, 3, 2.0, 0.03}), InputError);
  EXPECT_THROW(WeightedMedianFill({2, 0, 3, 2.0, 0.03}), InputError);
  EXPECT_THROW(WeightedMedianFill({2, 8, 5, 2.0, 0.03}), InputError);
  EXPECT_THROW(WeightedMedianFill({2, 8, 3, -1.0, 0.03}), InputError);
  EXPECT_THROW(WeightedMedianFill({2, 8, 3, 2.0, std::nan("")}), InputError);
}

}  // namespace
}  // namespace weighted_median_fill_test
}  // namespace stridemap
