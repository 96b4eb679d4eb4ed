#include "stridemap/core/cas_filter.hpp"

#include <cmath>

#include <gtest/gtest.h>

#include "stridemap/core/error.hpp"

namespace stridemap {
namespace {

void measure(ElevationMap& map, int i, int j, float h, float c) {
  const std::size_t s = map.slot(map.cell_at_local(i, j));
  map.elevation_data()[s] = h;
  map.certainty_data()[s] = c;
  map.state_data()[s] = static_cast<std::uint8_t>(CellState::measured);
}

ElevationMap flat(float certainty) {
  ElevationMap map({15, 0.01});
  for (int i = 0; i < 15; ++i)
    for (int j = 0; j < 15; ++j) measure(map, i, j, 0.0f, certainty);
  return map;
}

float elevation_at(const ElevationMap& map, int i, int j) { return map.elevation(map.cell_at_local(i, j)); }
CellState state_at(const ElevationMap& map, int i, int j) { return map.state(map.cell_at_local(i, j)); }

TEST(CasFilter, RemovesAWeakIsolatedSpikeAndFillsIt) {
  ElevationMap map = flat(30.0f);
  measure(map, 7, 7, 0.15f, 3.0f);
  const CasResult result = CasFilter().apply(map);
  EXPECT_EQ(result.removed, 1u);
  EXPECT_EQ(state_at(map, 7, 7), CellState::filled);
  EXPECT_FLOAT_EQ(elevation_at(map, 7, 7), 0.0f);
}

TEST(CasFilter, KeepsAWellSupportedPeak) {
  ElevationMap map = flat(30.0f);
  measure(map, 7, 7, 0.15f, 30.0f);
  EXPECT_EQ(CasFilter().apply(map).removed, 0u);
  EXPECT_FLOAT_EQ(elevation_at(map, 7, 7), 0.15f);
}

TEST(CasFilter, KeepsASmallObstacleWhoseCellsAgree) {
  ElevationMap map = flat(30.0f);
  for (int i = 6; i <= 7; ++i)
    for (int j = 6; j <= 7; ++j) measure(map, i, j, 0.10f, 3.0f);
  EXPECT_EQ(CasFilter().apply(map).removed, 0u);
  EXPECT_FLOAT_EQ(elevation_at(map, 6, 6), 0.10f);
}

TEST(CasFilter, KeepsLowCellsAndHolesAlone) {
  ElevationMap map = flat(30.0f);
  measure(map, 7, 7, -0.15f, 3.0f);  // a dip is not an artifact of the max rule
  EXPECT_EQ(CasFilter().apply(map).removed, 0u);
}

TEST(CasFilter, SparseEvidenceIsWeakEvenWithEqualCertainties) {
  ElevationMap map({15, 0.01});
  measure(map, 7, 7, 0.15f, 3.0f);
  measure(map, 7, 8, 0.0f, 3.0f);
  measure(map, 8, 7, 0.0f, 3.0f);
  EXPECT_EQ(CasFilter().apply(map).removed, 1u);
}

TEST(CasFilter, RejectsBadOptions) {
  CasOptions o;
  o.window_radius_cells = 0;
  EXPECT_THROW(CasFilter{o}, InputError);
  o = {};
  o.elevation_tolerance_m = -1.0;
  EXPECT_THROW(CasFilter{o}, InputError);
  o = {};
  o.certainty_ratio = std::nan("");
  EXPECT_THROW(CasFilter{o}, InputError);
}

}  // namespace
}  // namespace stridemap
