#include "stridemap_ros/node_callbacks.hpp"

#include "stridemap_ros/ros1_messages.hpp"

namespace stridemap::ros_adapter {

void read_laser_scan(const sensor_msgs::LaserScan& msg, LaserScanData& out) {
  out.stamp_s = msg.header.stamp.toSec();
  out.frame_id = msg.header.frame_id;  // assigned, not constructed: a long name allocates once
  out.angle_min_rad = msg.angle_min;
  out.angle_increment_rad = msg.angle_increment;
  out.range_min_m = msg.range_min;
  out.range_max_m = msg.range_max;
  out.ranges_m = msg.ranges.data();
  out.range_count = msg.ranges.size();
  out.intensities = msg.intensities.data();
  out.intensity_count = msg.intensities.size();
}

bool map_waiting(MessageMapper& mapper, double now_s) {
  const std::size_t dropped = mapper.stats().dropped();
  mapper.process(now_s, false);
  return mapper.stats().dropped() != dropped;
}

bool take_laser_scan(const sensor_msgs::LaserScan& msg, LaserScanData& scan, MessageMapper& mapper, double (*now_s)()) {
  read_laser_scan(msg, scan);
  mapper.add(scan, now_s());
  return map_waiting(mapper, now_s());
}

bool take_point_cloud(const sensor_msgs::PointCloud2& msg, PointCloudData& cloud, MessageMapper& mapper,
                      double (*now_s)()) {
  std::string why;  // filled only for a cloud that cannot be read
  if (point_cloud_data(msg, cloud, why)) {
    mapper.add(cloud, now_s());
  } else {
    mapper.add_unreadable(msg.header.frame_id, why);
  }
  return map_waiting(mapper, now_s());
}

bool take_pose(MessageMapper& mapper, TopicPoseSource& poses, const std::string& frame_id, const ros::Time& stamp,
               const geometry_msgs::Pose& pose, double (*now_s)()) {
  mapper.count_pose(frame_id == mapper.options().map_frame && poses.add(stamp.toSec(), to_isometry(pose)));
  return map_waiting(mapper, now_s());
}

}  // namespace stridemap::ros_adapter
