// stridemap_urg_bridge: a URG-04LX (or `stridemap emulate-urg`'s
// pseudo-terminal) as ROS 1 topics: LaserScan on /scan, and, from a pose
// file that grows (the emulator's --poses-out), TF map -> base_link plus
// the configured mount as base_link -> laser (docs/ros.md, "The whole
// stack without hardware").
#include <string>

#include <ros/ros.h>
#include <sensor_msgs/LaserScan.h>
#include <tf2_ros/static_transform_broadcaster.h>
#include <tf2_ros/transform_broadcaster.h>

#include "stridemap_ros/ros1_messages.hpp"
#include "stridemap_ros/urg_input.hpp"

int main(int argc, char** argv) {
  using namespace stridemap::ros_adapter;
  ros::init(argc, argv, "stridemap_urg_bridge");
  ros::NodeHandle nh;
  ros::NodeHandle pnh("~");
  std::string device, poses_file, config, map_frame, base_frame, laser_frame;
  pnh.param<std::string>("device", device, "/dev/ttyACM0");
  pnh.param<std::string>("poses_file", poses_file, "");
  pnh.param<std::string>("config", config, "");
  pnh.param<std::string>("map_frame", map_frame, "map");
  pnh.param<std::string>("base_frame", base_frame, "base_link");
  pnh.param<std::string>("laser_frame", laser_frame, "laser");
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
