// stridemap_urg_bridge: a URG-04LX (or `stridemap emulate-urg`'s
// pseudo-terminal) as ROS 1 topics: LaserScan on /scan, and, from a pose
// file that grows (the emulator's --poses-out), TF map -> base_link plus
// the configured mount as base_link -> laser (docs/ros.md, "The whole
// stack without hardware").
#include <cstdio>
#include <string>

#include <ros/ros.h>
#include <sensor_msgs/LaserScan.h>
#include <tf2_ros/static_transform_broadcaster.h>
#include <tf2_ros/transform_broadcaster.h>

#include "stridemap_ros/ros1_messages.hpp"
#include "stridemap_ros/node_parameters.hpp"
#include "stridemap_ros/urg_input.hpp"

namespace {

struct BridgeSettings {
  std::string device, poses_file, config, map_frame, base_frame, laser_frame;
};

BridgeSettings read_bridge_settings(stridemap::ros_adapter::ParameterReader& read) {
  const std::string home = stridemap::ros_adapter::ros_home();
  BridgeSettings s;
  s.device = read.path("device", "/dev/ttyACM0", home, "the URG-04LX's serial device (or the emulator's link)");
  s.poses_file = read.path("poses_file", "", home, "a pose file as it grows (docs/live.md's format); empty: no poses");
  s.config = read.path("config", "", home, "the mapper YAML whose mount gives base_frame -> laser_frame; empty: defaults");
  s.map_frame = read.text("map_frame", "map", "the poses' parent frame");
  s.base_frame = read.text("base_frame", "base_link", "the robot's trunk frame");
  s.laser_frame = read.text("laser_frame", "laser", "the scans' frame");
  return s;
}

}  // namespace

int main(int argc, char** argv) {
  using namespace stridemap::ros_adapter;
  if (asks_for_help(argc, argv)) {
    const std::string help =
        node_help("stridemap_urg_bridge", "a URG-04LX as LaserScan on /scan, a pose file as TF (docs/ros.md)", read_bridge_settings);
    std::fputs(help.c_str(), stdout);
    return 0;
  }
  ros::init(argc, argv, "stridemap_urg_bridge");
  ros::NodeHandle nh;
  ros::NodeHandle pnh("~");
  std::string device, poses_file, config, map_frame, base_frame, laser_frame;
  try {
    const ServerParameters server(pnh);
    ParameterReader read(server);
    const BridgeSettings s = read_bridge_settings(read);
    read.refuse_unknown();
    ROS_INFO("stridemap_urg_bridge: %s", read.summary().c_str());
    std::fflush(stdout);
    device = s.device;
    poses_file = s.poses_file;
    config = s.config;
    map_frame = s.map_frame;
    base_frame = s.base_frame;
    laser_frame = s.laser_frame;
  } catch (const std::exception& e) {
    ROS_FATAL("stridemap_urg_bridge: %s", e.what());
    return 2;
  }
  try {
    UrgInput input(device, poses_file, config);
    ros::Publisher scan_pub = nh.advertise<sensor_msgs::LaserScan>("scan", 20);
    tf2_ros::TransformBroadcaster tf;
    tf2_ros::StaticTransformBroadcaster static_tf;
    geometry_msgs::TransformStamped mount;
    mount.header.stamp = ros::Time::now();
    mount.header.frame_id = base_frame;
    mount.child_frame_id = laser_frame;
    mount.transform = to_transform(input.sensor_on_trunk());
    static_tf.sendTransform(mount);
    UrgInputScan scan;
    std::string message;
    while (ros::ok()) {
      // Poses first: a scan's TF should be there before the scan is.
      for (const UrgInputPose& pose : input.poll_poses()) {
        geometry_msgs::TransformStamped t;
        t.header.stamp.fromSec(pose.stamp_s);
        t.header.frame_id = map_frame;
        t.child_frame_id = base_frame;
        t.transform = to_transform(pose.trunk_in_map);
        tf.sendTransform(t);
      }
      switch (input.next(scan, message, 0.01)) {
        case UrgInput::Event::scan: {
          sensor_msgs::LaserScan msg;
          msg.header.stamp.fromSec(scan.stamp_s);
          msg.header.frame_id = laser_frame;
          msg.angle_min = static_cast<float>(scan.angle_min_rad);
          msg.angle_increment = static_cast<float>(scan.angle_increment_rad);
          msg.angle_max = static_cast<float>(scan.angle_min_rad + scan.angle_increment_rad * (scan.ranges_m.size() - 1));
          msg.scan_time = static_cast<float>(scan.scan_period_s);
          msg.range_min = static_cast<float>(scan.range_min_m);
          msg.range_max = static_cast<float>(scan.range_max_m);
          msg.ranges = scan.ranges_m;
          scan_pub.publish(msg);
          break;
        }
        case UrgInput::Event::connected: ROS_INFO("stridemap_urg_bridge: %s", message.c_str()); break;
        case UrgInput::Event::fault: ROS_WARN("stridemap_urg_bridge: %s", message.c_str()); break;
        case UrgInput::Event::none: break;
      }
      ros::spinOnce();
    }
  } catch (const std::exception& e) {
    ROS_FATAL("stridemap_urg_bridge: %s", e.what());
    return 2;
  }
  return 0;
}
