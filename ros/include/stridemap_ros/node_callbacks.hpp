#pragma once
// What stridemap_node's callbacks do with each message, beyond roscpp's
// delivery: functions of their own so that a test runs exactly the node's
// per-scan work (ros/tests/allocation counts its allocations: none per
// scan once warmed up).
#include <string>

#include <geometry_msgs/Pose.h>
#include <ros/time.h>
#include <sensor_msgs/LaserScan.h>
#include <sensor_msgs/PointCloud2.h>

#include "stridemap_ros/message_mapper.hpp"

namespace stridemap::ros_adapter {

/// The scan's fields into `out`, whose frame name keeps its storage from
/// message to message; the ranges point into `msg`, which must outlive the use.
void read_laser_scan(const sensor_msgs::LaserScan& msg, LaserScanData& out);

/// Maps the scans waiting whose pose has come (MessageMapper::process at
/// `now_s`); true when a scan was dropped (mapper.last_drop() says why).
bool map_waiting(MessageMapper& mapper, double now_s);

/// The node's LaserScan callback: the message read into `scan` (reused),
/// queued as arriving at now_s(), then map_waiting at now_s().
bool take_laser_scan(const sensor_msgs::LaserScan& msg, LaserScanData& scan, MessageMapper& mapper, double (*now_s)());

/// The node's PointCloud2 callback: the cloud read into `cloud` (reused;
/// an unreadable one is counted and dropped with its reason), queued as
/// arriving at now_s(), then map_waiting at now_s().
bool take_point_cloud(const sensor_msgs::PointCloud2& msg, PointCloudData& cloud, MessageMapper& mapper,
                      double (*now_s)());

/// A PoseStamped's or Odometry's pose, offered to the pose topic's track:
/// kept when in the map frame and later than the last, counted either way.
/// Then map_waiting at now_s(), as the node does; true when that dropped a scan.
bool take_pose(MessageMapper& mapper, TopicPoseSource& poses, const std::string& frame_id, const ros::Time& stamp,
               const geometry_msgs::Pose& pose, double (*now_s)());

}  // namespace stridemap::ros_adapter
