#pragma once
// `stridemap map --bag`: a map from a ROS 1 bag (docs/ros.md). The options
// are ros/cli/map_bag_options.cpp in every build; the run is
// ros/cli/map_bag.cpp when ROS is found (STRIDEMAP_WITH_ROS), otherwise
// ros/cli/map_bag_without_ros.cpp, which says the tool was built without ROS.
#include <string>

#include <CLI/CLI.hpp>

namespace stridemap::cli {

struct MapBagArgs {
  std::string bag_path;
  std::string scan_topic;
  std::string cloud_topic;
  std::string pose_topic;
  bool tf = false;
  std::string map_frame = "map";
  std::string sensor_frame;
  double pose_wait_s = 0.5;
  // The node's parameters of the same names (MessageMapperOptions' defaults);
  // max_pose_gap_s is the map command's own --max-pose-gap-s.
  double max_pose_gap_s = 1.0;
  double range_error_m = 0.01;
  double range_error_fraction = 0.01;
  double min_intensity = 0.0;
  bool overwrite = false;  ///< the map command's --overwrite
};

/// Adds --bag and its options to the map command.
void add_map_bag_options(CLI::App& map, MapBagArgs& args);
/// Maps the bag into `out_dir` with the mapper configuration at `config_path` ("" = defaults).
void run_map_bag(const MapBagArgs& args, const std::string& config_path, const std::string& out_dir);

}  // namespace stridemap::cli
