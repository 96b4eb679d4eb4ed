// `stridemap map --bag`'s options, the same in a build with ROS and one
// without (where running them says the tool was built without ROS). Each
// is the node's parameter of the same name (docs/ros.md), so the bag gives
// the map the node would.
#include "cli_parsing.hpp"
#include "map_bag.hpp"

namespace stridemap::cli {

void add_map_bag_options(CLI::App& map, MapBagArgs& args) {
  map.add_option("--bag", args.bag_path, "A ROS 1 bag to map instead of --log/--poses (docs/ros.md)");
  map.add_option("--scan-topic", args.scan_topic, "--bag: sensor_msgs/LaserScan topic");
  map.add_option("--cloud-topic", args.cloud_topic, "--bag: sensor_msgs/PointCloud2 topic (the stripe camera)");
  map.add_option("--pose-topic", args.pose_topic, "--bag: the trunk's geometry_msgs/PoseStamped or nav_msgs/Odometry");
  map.add_flag("--tf", args.tf, "--bag: the sensor's pose from the bag's /tf and /tf_static");
  map.add_option("--map-frame", args.map_frame, "--bag: fixed frame of TF or of the pose topic")->capture_default_str();
  map.add_option("--sensor-frame", args.sensor_frame, "--bag: frame the scans must carry (default: the first scan's)");
  map.add_option("--pose-wait-s", args.pose_wait_s,
                 "--bag: a scan whose pose has not come this long (bag time) after it is dropped, as the node does")
      ->capture_default_str()
      ->check(number_from_to(0.0, 3600.0, "s"));
  map.add_option("--range-error-m", args.range_error_m,
                 "--bag: a beam's maximum range error Delta r = max(this, --range-error-fraction x range)")
      ->capture_default_str()
      ->check(number_from_to(1e-6, 10.0, "m"));
  map.add_option("--range-error-fraction", args.range_error_fraction, "--bag: see --range-error-m")
      ->capture_default_str()
      ->check(number_from_to(0.0, 1.0));
  map.add_option("--min-intensity", args.min_intensity,
                 "--bag: LaserScan beams with a lower intensity are not used (0: intensities ignored)")
      ->capture_default_str();
}

}  // namespace stridemap::cli
