// The README's ROS line run as written (its `make build &&` is the test's
// own build; a scratch work_dir keeps runs apart): the emulator demo from
// the build's package, seen where the docs say, on `~grid_map` and
// `~traversability`.
#include <filesystem>
#include <fstream>
#include <memory>
#include <string>

#include <grid_map_msgs/GridMap.h>
#include <gtest/gtest.h>
#include <nav_msgs/OccupancyGrid.h>
#include <ros/ros.h>

#include "ros_fixture.hpp"
#include "test_paths.hpp"

namespace stridemap::ros_test {
namespace readme_ros_test {
namespace {

std::string readme_ros_command() {
  std::ifstream in(std::string(STRIDEMAP_SOURCE_DIR) + "/README.md");
  for (std::string line; std::getline(in, line);) {
    if (line.find("roslaunch stridemap demo.launch") != std::string::npos) return line;
  }
  return "";
}

TEST_F(RosNodeTest, TheReadmesDemoLinePublishesTheGridMapAndTheOccupancyGrid) {
  std::string command = readme_ros_command();
  const std::string prefix = "make build && ";
  ASSERT_EQ(command.rfind(prefix, 0), 0u) << "README's ROS line changed: " << command;
  command.erase(0, prefix.size());
  // $PWD/build is the build tree when run from the source root, as the
  // README is; this build's folder may have another name.
  const std::string build = std::filesystem::path(STRIDEMAP_NODE_PATH).parent_path().parent_path().string();
  const auto at = command.find("$PWD/build/");
  ASSERT_NE(at, std::string::npos) << command;
  command.replace(at, std::string("$PWD/build/").size(), build + "/");
  const std::string runnable = command + " work_dir:=" + *folder_ + "/readme_demo";

  grid_map_msgs::GridMap::ConstPtr grid;
  nav_msgs::OccupancyGrid::ConstPtr occupancy;
  ros::Subscriber s1 = nh_->subscribe<grid_map_msgs::GridMap>(
      "/stridemap_node/grid_map", 1, [&](const grid_map_msgs::GridMap::ConstPtr& m) { grid = m; });
  ros::Subscriber s2 = nh_->subscribe<nav_msgs::OccupancyGrid>(
      "/stridemap_node/traversability", 1, [&](const nav_msgs::OccupancyGrid::ConstPtr& m) { occupancy = m; });
  log_ = *folder_ + "/readme_demo.log";
  Child demo({"bash", "-c", runnable}, log_);
  const auto measured = [&] {
    if (!grid || !occupancy) return false;
    int known = 0;
    for (const auto v : occupancy->data) known += v >= 0;
    return known > 100;
  };
  ASSERT_TRUE(wait_for(measured, 120.0, pump)) << runnable << "\n" << read_text(log_);
  EXPECT_EQ(grid->info.header.frame_id, "map");
  EXPECT_FALSE(grid->layers.empty());
  EXPECT_EQ(grid->layers.size(), grid->data.size());
  EXPECT_EQ(occupancy->header.frame_id, "map");
  demo.stop();
}

}  // namespace
}  // namespace readme_ros_test
}  // namespace stridemap::ros_test
