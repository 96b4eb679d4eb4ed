// `stridemap map --bag` in a tool built without ROS: the option is there
// (so scripts get a clear message, not "unknown option") and says why it
// cannot run.
#include "map_bag.hpp"

#include "stridemap/core/error.hpp"

namespace stridemap::cli {

void add_map_bag_options(CLI::App& map, MapBagArgs& args) {
  map.add_option("--bag", args.bag_path, "A ROS 1 bag (this build has no ROS: see docs/ros.md)");
  map.add_option("--scan-topic", args.scan_topic, "--bag only");
  map.add_option("--cloud-topic", args.cloud_topic, "--bag only");
  map.add_option("--pose-topic", args.pose_topic, "--bag only");
  map.add_flag("--tf", args.tf, "--bag only");
  map.add_option("--map-frame", args.map_frame, "--bag only");
  map.add_option("--sensor-frame", args.sensor_frame, "--bag only");
  map.add_option("--pose-wait-s", args.pose_wait_s, "--bag only");
}

void run_map_bag(const MapBagArgs& args, const std::string&, const std::string&) {
  throw InputError("--bag " + args.bag_path +
                   ": this stridemap was built without ROS (configure with the ROS packages installed and "
                   "-DSTRIDEMAP_WITH_ROS=ON; docs/ros.md)");
}

}  // namespace stridemap::cli
