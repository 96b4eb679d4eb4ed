#include "stridemap/core/map_integrity.hpp"

#include <cmath>
#include <limits>

#include <gtest/gtest.h>

namespace stridemap {
namespace {

TEST(MapIntegrity, AFreshMapIsValidAndEveryBrokenRuleIsFound) {
  ElevationMap map(GridOptions{10, 0.01});
  MapIntegrity r = check_map_integrity(map, 100.0);
  EXPECT_TRUE(r.ok());
  EXPECT_EQ(r.unknown, 100u);
  const CellIndex c = map.cell_at_local(3, 4);
  const std::size_t s = map.slot(c);
  map.state_data()[s] = static_cast<std::uint8_t>(CellState::measured);
  map.elevation_data()[s] = 0.1f;
  map.certainty_data()[s] = 3.0f;
  EXPECT_TRUE(check_map_integrity(map, 100.0).ok());
  EXPECT_EQ(check_map_integrity(map, 100.0).measured, 1u);

  const float nan = std::numeric_limits<float>::quiet_NaN();
  struct Case {
    std::uint8_t state;
    float elevation, certainty;
    const char* problem;
  };
  for (const Case& bad : {Case{1, nan, 3.0f, "measured but elevation nan"}, Case{1, 0.1f, 0.0f, "measured but"},
                          Case{1, 0.1f, 101.0f, "measured but"}, Case{0, 0.1f, 0.0f, "unknown but"},
                          Case{0, nan, 1.0f, "unknown but"}, Case{2, 0.1f, 1.0f, "filled but"},
                          Case{2, std::numeric_limits<float>::infinity(), 0.0f, "filled but"},
                          Case{7, 0.0f, 0.0f, "state 7 does not exist"}}) {
    map.state_data()[s] = bad.state;
    map.elevation_data()[s] = bad.elevation;
    map.certainty_data()[s] = bad.certainty;
    r = check_map_integrity(map, 100.0);
    EXPECT_EQ(r.invalid, 1u) << bad.problem;
    EXPECT_EQ(r.first_problem.rfind("cell (" + std::to_string(c.x) + ", " + std::to_string(c.y) + "): ", 0), 0u);
    EXPECT_NE(r.first_problem.find(bad.problem), std::string::npos) << r.first_problem;
  }
}

TEST(MapIntegrity, HashSeesEveryLayerAndNotTheBufferOffset) {
  ElevationMap a(GridOptions{10, 0.01}), b(GridOptions{10, 0.01});
  EXPECT_EQ(map_layers_hash(a), map_layers_hash(b));
  a.certainty_data()[7] = 1.0f;
  EXPECT_NE(map_layers_hash(a), map_layers_hash(b));
  a.certainty_data()[7] = 0.0f;
  a.state_data()[7] = 1;
  EXPECT_NE(map_layers_hash(a), map_layers_hash(b));
  // The same window reached by different moves: the circular buffer starts
  // elsewhere, the map is the same.
  ElevationMap c(GridOptions{10, 0.01}), d(GridOptions{10, 0.01});
  c.move_to(0.05, 0.0);
  d.move_to(0.30, 0.0);
  d.move_to(0.05, 0.0);
  EXPECT_EQ(map_layers_hash(c), map_layers_hash(d));
  EXPECT_NE(map_layers_hash(c), map_layers_hash(a));  // another window
}

}  // namespace
}  // namespace stridemap
