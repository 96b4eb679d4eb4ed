#include "stridemap/core/top_point.hpp"

#include <cmath>
#include <vector>

#include <gtest/gtest.h>

#include "stridemap/core/terrain_mapper.hpp"

namespace stridemap {
namespace {

TEST(TopPoints, KeepThePositionOfTheReadingThatSetTheCell) {
  MapperOptions options;
  options.follow_robot = false;
  options.grid = {20, 0.01};
  TerrainMapper mapper(options, SensorMount{});
  const TopPoints top(mapper.map());  // declares the layers
  ElevationMap& map = mapper.map();
  const std::vector<MapPoint> points{{0.0031, 0.0042, 0.050, 1.0}, {0.0077, 0.0018, 0.055, 1.0}, {0.0061, 0.0093, 0.040, 1.0}};
  mapper.integrate_points(points, TrunkPose{});
  std::size_t set = 0;
  for (const MapPoint& p : points) set += top.note(map, p.x_m, p.y_m, p.elevation_m);
  EXPECT_EQ(set, 1u);  // only the highest is the cell's elevation
  const std::size_t slot = map.slot({0, 0});
  EXPECT_EQ(map.data(top.x_layer())[slot], 0.0077f);
  EXPECT_EQ(map.data(top.y_layer())[slot], 0.0018f);
  // Untouched cells hold NaN; a point outside the window sets nothing.
  EXPECT_TRUE(std::isnan(map.data(top.x_layer())[map.slot({5, 5})]));
  EXPECT_FALSE(top.note(map, 5.0, 5.0, 0.1));
  // The window moving away and back forgets the position with the height.
  map.move_to(10.0, 10.0);
  map.move_corner_to({0, 0});
  EXPECT_TRUE(std::isnan(map.data(top.x_layer())[map.slot({0, 0})]));
}

TEST(TopPoints, LayersAreDeclaredOnceAndNotExportedByDefault) {
  ElevationMap map(GridOptions{10, 0.01});
  const std::size_t before = map.layer_count();
  const TopPoints first(map);
  const TopPoints second(map);
  EXPECT_EQ(map.layer_count(), before + 2);
  EXPECT_EQ(first.x_layer().index, second.x_layer().index);
  EXPECT_FALSE(top_point_x_layer().exported);
  EXPECT_EQ(top_point_y_layer().unit, "m");
}

}  // namespace
}  // namespace stridemap
