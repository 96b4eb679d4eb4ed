// The OccupancyGrid and grid_map_msgs/GridMap conversions on a small map
// whose every cell is known, and the generated GridMap headers' MD5 sums
// against grid_map_msgs' (ROS 1): a subscriber built against upstream's
// headers connects to the node only if they are equal.
#include <cmath>
#include <limits>
#include <string>

#include <grid_map_msgs/GridMap.h>
#include <grid_map_msgs/GridMapInfo.h>
#include <gtest/gtest.h>
#include <nav_msgs/OccupancyGrid.h>

#include "stridemap_ros/ros1_messages.hpp"

namespace stridemap::ros_adapter {
namespace grid_messages_test {
namespace {

constexpr float kNaN = std::numeric_limits<float>::quiet_NaN();

// 3 x 3 cells of 0.1 m from cell (-1, 2): value(i, j) = 10 i + j, one NaN.
MapLayers small_map() {
  MapLayers map;
  map.min_cell_x = -1;
  map.min_cell_y = 2;
  map.cell_size_m = 0.1;
  map.cells_per_side = 3;
  map.names = {"elevation", "foothold_score"};
  std::vector<float> elevation(9), score = {0.0f, 0.25f, 1.0f, 0.5f, kNaN, 1.5f, -0.5f, 0.994f, 0.996f};
  for (int i = 0; i < 3; ++i) {
    for (int j = 0; j < 3; ++j) elevation[static_cast<std::size_t>(i * 3 + j)] = static_cast<float>(10 * i + j);
  }
  map.values = {elevation, score};
  return map;
}

TEST(GridMessages, GeneratedGridMapDefinitionsHaveUpstreamMd5Sums) {
  EXPECT_STREQ(ros::message_traits::MD5Sum<grid_map_msgs::GridMapInfo>::value(), "43ee5430e1c253682111cb6bedac0ef9");
  EXPECT_STREQ(ros::message_traits::MD5Sum<grid_map_msgs::GridMap>::value(), "95681e052b1f73bf87b7eb984382b401");
  EXPECT_STREQ(ros::message_traits::DataType<grid_map_msgs::GridMap>::value(), "grid_map_msgs/GridMap");
}

TEST(GridMessages, OccupancyIsOneHundredTimesOneMinusTheScoreAndUnknownIsMinusOne) {
  EXPECT_EQ(occupancy_of_score(1.0f), 0);
  EXPECT_EQ(occupancy_of_score(0.0f), 100);
  EXPECT_EQ(occupancy_of_score(0.25f), 75);
  EXPECT_EQ(occupancy_of_score(0.996f), 0);   // rounded
  EXPECT_EQ(occupancy_of_score(0.994f), 1);
  EXPECT_EQ(occupancy_of_score(1.5f), 0);     // clamped
  EXPECT_EQ(occupancy_of_score(-0.5f), 100);
  EXPECT_EQ(occupancy_of_score(kNaN), -1);

  const MapLayers map = small_map();
  const nav_msgs::OccupancyGrid grid = occupancy_grid(map, 1, "odom", ros::Time(5.0));
  EXPECT_EQ(grid.header.frame_id, "odom");
  EXPECT_EQ(grid.header.stamp, ros::Time(5.0));
  EXPECT_EQ(grid.info.width, 3u);
  EXPECT_EQ(grid.info.height, 3u);
  EXPECT_FLOAT_EQ(grid.info.resolution, 0.1f);
  EXPECT_DOUBLE_EQ(grid.info.origin.position.x, -0.1);
  EXPECT_DOUBLE_EQ(grid.info.origin.position.y, 0.2);
  EXPECT_EQ(grid.info.origin.orientation.w, 1.0);
  ASSERT_EQ(grid.data.size(), 9u);
  // Row r is y index j, column c is x index i: data[j * 3 + i] from score[i * 3 + j].
  for (int i = 0; i < 3; ++i) {
    for (int j = 0; j < 3; ++j) {
      EXPECT_EQ(grid.data[static_cast<std::size_t>(j * 3 + i)], occupancy_of_score(map.values[1][static_cast<std::size_t>(i * 3 + j)]))
          << i << ", " << j;
    }
  }
  EXPECT_EQ(grid.data[1 * 3 + 1], -1);
}

TEST(GridMessages, GridMapFollowsGridMapsStorageOrder) {
  const MapLayers map = small_map();
  const grid_map_msgs::GridMap msg = grid_map_message(map, "map", ros::Time(7.0));
  EXPECT_EQ(msg.info.header.frame_id, "map");
  EXPECT_EQ(msg.info.header.stamp, ros::Time(7.0));
  EXPECT_DOUBLE_EQ(msg.info.resolution, 0.1);
  EXPECT_DOUBLE_EQ(msg.info.length_x, 0.3);
  EXPECT_DOUBLE_EQ(msg.info.length_y, 0.3);
  // The centre of cells x -1..1 and y 2..4.
  EXPECT_NEAR(msg.info.pose.position.x, 0.05, 1e-12);
  EXPECT_NEAR(msg.info.pose.position.y, 0.35, 1e-12);
  EXPECT_EQ(msg.info.pose.orientation.w, 1.0);
  ASSERT_EQ(msg.layers, map.names);
  ASSERT_EQ(msg.basic_layers, std::vector<std::string>{"elevation"});
  EXPECT_EQ(msg.outer_start_index, 0);
  EXPECT_EQ(msg.inner_start_index, 0);
  ASSERT_EQ(msg.data.size(), 2u);
  const std_msgs::Float32MultiArray& z = msg.data[0];
  ASSERT_EQ(z.layout.dim.size(), 2u);
  EXPECT_EQ(z.layout.dim[0].label, "column_index");
  EXPECT_EQ(z.layout.dim[0].size, 3u);
  EXPECT_EQ(z.layout.dim[0].stride, 9u);
  EXPECT_EQ(z.layout.dim[1].label, "row_index");
  EXPECT_EQ(z.layout.dim[1].size, 3u);
  EXPECT_EQ(z.layout.dim[1].stride, 3u);
  ASSERT_EQ(z.data.size(), 9u);
  // grid_map's cell (row, col) lies at centre + (length/2 - (row + 0.5) res, length/2 - (col + 0.5) res):
  // (0, 0) is the (max x, max y) cell, i = 2, j = 2; column-major: data[col * rows + row].
  for (int row = 0; row < 3; ++row) {
    for (int col = 0; col < 3; ++col) {
      const double x = msg.info.pose.position.x + 0.5 * msg.info.length_x - (row + 0.5) * 0.1;
      const double y = msg.info.pose.position.y + 0.5 * msg.info.length_y - (col + 0.5) * 0.1;
      const int i = static_cast<int>(std::floor(x / 0.1 + 1e-9)) - static_cast<int>(map.min_cell_x);
      const int j = static_cast<int>(std::floor(y / 0.1 + 1e-9)) - static_cast<int>(map.min_cell_y);
      EXPECT_EQ(z.data[static_cast<std::size_t>(col * 3 + row)], static_cast<float>(10 * i + j)) << row << ", " << col;
    }
  }
  EXPECT_EQ(z.data[0], 22.0f);
  EXPECT_TRUE(std::isnan(msg.data[1].data[1 * 3 + 1]));  // the unknown score at (1, 1)
}

}  // namespace
}  // namespace grid_messages_test
}  // namespace stridemap::ros_adapter
