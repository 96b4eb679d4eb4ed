// stridemap_node's per-scan work (ros/src/node_callbacks.cpp: what its
// LaserScan, PointCloud2 and pose callbacks and its timer run once roscpp
// has delivered the message) allocates nothing once warmed up: scans whose
// pose TF holds already, scans that wait for TF and are mapped on a later
// timer tick, scans mapped against a pose topic, and stripe clouds. Inserting TF (the listener's thread in
// the node) and filling the test's messages are not counted. No roscore:
// TF is a tf2::BufferCore filled here. Global operator new is replaced in
// this test binary to count allocations while a flag is set.
#include <gtest/gtest.h>

#include "allocation_counting.hpp"

#include <cmath>
#include <cstring>
#include <limits>
#include <string>

#include <geometry_msgs/TransformStamped.h>
#include <sensor_msgs/LaserScan.h>
#include <sensor_msgs/PointCloud2.h>
#include <tf2/buffer_core.h>

#include "stridemap_ros/node_callbacks.hpp"
#include "stridemap_ros/ros1_messages.hpp"

STRIDEMAP_REPLACE_OPERATOR_NEW()

namespace stridemap::ros_adapter {
namespace {

using test::allocation_counter;

// Longer than a short string holds, as many a URDF's laser frame is: the
// scan's copy of it must keep its storage.
const std::string kLongLaserFrame = "hokuyo_urg04lx_laser_link";
// tf2's lookupTransform hands back both frame names in a TransformStamped,
// which allocates for a name as long as the one above: tf2's own, not
// counted here, so the TF runs use a short name.
const std::string kLaserFrame = "laser";
constexpr double kScanPeriodS = 0.1;  // the URG-04LX's 10 scans per second
constexpr double kPosePeriodS = 0.01;

double g_now_s = 0.0;
double test_now() { return g_now_s; }

// Counting runs while the node's code does, paused around the test's own work.
void count(bool on) { allocation_counter().counting = on; }

// An URG-04LX scan of the ground ahead, 682 beams, a few without an echo
// (REP-117's +inf) and one NaN; the values change from scan to scan.
void fill_scan(sensor_msgs::LaserScan& msg, int k, const std::string& frame = kLaserFrame) {
  msg.header.stamp.fromSec(100.0 + kScanPeriodS * k);
  msg.header.frame_id = frame;
  msg.angle_min = -2.0862f;
  msg.angle_increment = 0.0061f;
  msg.range_min = 0.02f;
  msg.range_max = 5.6f;
  msg.ranges.resize(682);
  for (std::size_t i = 0; i < msg.ranges.size(); ++i) {
    msg.ranges[i] = 0.5f + 0.001f * static_cast<float>((static_cast<int>(i) * 13 + k * 7) % 50);
  }
  msg.ranges[5] = msg.ranges[6] = std::numeric_limits<float>::infinity();
  msg.ranges[7] = std::numeric_limits<float>::quiet_NaN();
}

// The robot walking along x at 0.2 m/s, the laser 0.3 m up, pitched down.
geometry_msgs::Pose trunk_at(double t_s) {
  geometry_msgs::Pose p;
  p.position.x = 0.2 * (t_s - 100.0);
  p.position.z = 0.05;
  p.orientation.w = 1.0;
  return p;
}

geometry_msgs::TransformStamped stamped_transform(const std::string& parent, const std::string& child, double t_s,
                                          const geometry_msgs::Pose& pose) {
  geometry_msgs::TransformStamped t;
  t.header.stamp.fromSec(t_s);
  t.header.frame_id = parent;
  t.child_frame_id = child;
  t.transform.translation.x = pose.position.x;
  t.transform.translation.y = pose.position.y;
  t.transform.translation.z = pose.position.z;
  t.transform.rotation = pose.orientation;
  return t;
}

void add_static_laser(tf2::BufferCore& tf) {
  geometry_msgs::Pose laser;
  laser.position.x = 0.1;
  laser.position.z = 0.3;
  laser.orientation.y = std::sin(0.3);  // 0.6 rad about y: pitched down
  laser.orientation.w = std::cos(0.3);
  tf.setTransform(stamped_transform("base_link", kLaserFrame, 0.0, laser), "test", true);
}

// Map -> base_link at 100 Hz up to `until_s`, from where the last call left off.
void add_trunk_poses(tf2::BufferCore& tf, double& next_s, double until_s) {
  for (; next_s <= until_s + 1e-9; next_s += kPosePeriodS) {
    tf.setTransform(stamped_transform("map", "base_link", next_s, trunk_at(next_s)), "test");
  }
}

struct TfRun {
  std::size_t scans = 0, allocations = 0, mapped = 0, dropped = 0;
  std::size_t waited = 0;  ///< scans not mapped on arrival
};

// TF `lead_s` ahead of the scans (negative: behind, so that every scan waits
// for its pose and the timer's ticks map it).
TfRun run_with_tf(double lead_s, int warm_up, int counted) {
  tf2::BufferCore tf(ros::Duration(10.0));
  add_static_laser(tf);
  TfPoseSource poses(tf, "map");
  MessageMapperOptions options;
  options.pose_wait_s = 1.0;
  MessageMapper mapper(options, poses);
  LaserScanData scan;
  sensor_msgs::LaserScan msg;
  double next_pose_s = 99.0;
  std::size_t waited = 0;
  allocation_counter().allocations = 0;
  for (int k = 0; k < warm_up + counted; ++k) {
    const bool counts = k >= warm_up;
    fill_scan(msg, k);
    const double stamp_s = msg.header.stamp.toSec();
    add_trunk_poses(tf, next_pose_s, stamp_s + lead_s);
    g_now_s = stamp_s + 0.005;
    count(counts);
    take_laser_scan(msg, scan, mapper, test_now);
    count(false);
    if (mapper.waiting() > 0) ++waited;
    // The 20 Hz timer's ticks until the next scan; TF comes in between.
    for (int tick = 1; tick <= 2; ++tick) {
      add_trunk_poses(tf, next_pose_s, stamp_s + lead_s + 0.05 * tick);
      g_now_s = stamp_s + 0.05 * tick;
      count(counts);
      map_waiting(mapper, g_now_s);
      count(false);
    }
  }
  return {static_cast<std::size_t>(counted), allocation_counter().allocations.load(), mapper.stats().mapped,
          mapper.stats().dropped(), waited};
}

TEST(RosScanCallbackAllocation, ScansWhosePoseTfHoldsAllocateNothing) {
  STRIDEMAP_SKIP_UNLESS_COUNTING_ALLOCATIONS();
  constexpr int kWarmUp = 20, kScans = 300;
  const TfRun run = run_with_tf(0.05, kWarmUp, kScans);
  EXPECT_EQ(run.allocations, 0u) << "over " << run.scans << " scans";
  EXPECT_EQ(run.waited, 0u);
  EXPECT_EQ(run.mapped, static_cast<std::size_t>(kWarmUp + kScans));
  EXPECT_EQ(run.dropped, 0u);
}

TEST(RosScanCallbackAllocation, ScansWaitingForTfAllocateNothing) {
  STRIDEMAP_SKIP_UNLESS_COUNTING_ALLOCATIONS();
  constexpr int kWarmUp = 20, kScans = 300;
  const TfRun run = run_with_tf(-0.03, kWarmUp, kScans);
  EXPECT_EQ(run.allocations, 0u) << "over " << run.scans << " scans";
  EXPECT_EQ(run.waited, static_cast<std::size_t>(kWarmUp + kScans));
  EXPECT_EQ(run.mapped, static_cast<std::size_t>(kWarmUp + kScans));
  EXPECT_EQ(run.dropped, 0u);
}

TEST(RosScanCallbackAllocation, ScansAgainstAPoseTopicAllocateNothing) {
  STRIDEMAP_SKIP_UNLESS_COUNTING_ALLOCATIONS();
  constexpr int kWarmUp = 20, kScans = 300;
  TopicPoseSource poses(1.0);
  MessageMapper mapper(MessageMapperOptions{}, poses);
  LaserScanData scan;
  sensor_msgs::LaserScan msg;
  const std::string map_frame = "map";
  double next_pose_s = 99.0;
  allocation_counter().allocations = 0;
  for (int k = 0; k < kWarmUp + kScans; ++k) {
    fill_scan(msg, k, kLongLaserFrame);
    const double stamp_s = msg.header.stamp.toSec();
    count(k >= kWarmUp);
    // Odometry at 100 Hz, 30 ms behind: each scan waits for the pose after it.
    for (; next_pose_s <= stamp_s - 0.03; next_pose_s += kPosePeriodS) {
      g_now_s = next_pose_s + 0.03;
      take_pose(mapper, poses, map_frame, ros::Time(next_pose_s), trunk_at(next_pose_s), test_now);
    }
    g_now_s = stamp_s + 0.005;
    take_laser_scan(msg, scan, mapper, test_now);
    count(false);
  }
  EXPECT_EQ(allocation_counter().allocations.load(), 0u) << "over " << kScans << " scans";
  EXPECT_GE(mapper.stats().mapped, static_cast<std::size_t>(kWarmUp + kScans - 1));
  EXPECT_EQ(mapper.stats().dropped(), 0u);
}

// A structured-light stripe as a camera node publishes it: 640 points of
// float32 x, y, z in the sensor frame, across the view 0.5 m ahead, one
// with a NaN coordinate (a column without the stripe); they change per frame.
void fill_stripe_cloud(sensor_msgs::PointCloud2& msg, int k) {
  constexpr std::uint32_t kPoints = 640;
  msg.header.stamp.fromSec(100.0 + kScanPeriodS * k);
  msg.header.frame_id = kLaserFrame;
  msg.height = 1;
  msg.width = kPoints;
  msg.is_bigendian = false;
  msg.point_step = 3 * sizeof(float);
  msg.row_step = msg.point_step * kPoints;
  msg.fields.resize(3);
  const char* names[3] = {"x", "y", "z"};
  for (std::uint32_t i = 0; i < 3; ++i) {
    msg.fields[i].name = names[i];
    msg.fields[i].offset = i * sizeof(float);
    msg.fields[i].datatype = sensor_msgs::PointField::FLOAT32;
    msg.fields[i].count = 1;
  }
  msg.data.resize(msg.row_step);
  for (std::uint32_t i = 0; i < kPoints; ++i) {
    const float xyz[3] = {0.5f + 0.001f * static_cast<float>((i * 7 + static_cast<std::uint32_t>(k) * 3) % 20),
                          -0.2f + 0.4f * static_cast<float>(i) / kPoints, 0.0f};
    std::memcpy(msg.data.data() + i * msg.point_step, xyz, sizeof xyz);
  }
  const float nan = std::numeric_limits<float>::quiet_NaN();
  std::memcpy(msg.data.data() + 5 * msg.point_step, &nan, sizeof nan);
}

TEST(RosScanCallbackAllocation, StripeCloudsWhosePoseTfHoldsAllocateNothing) {
  STRIDEMAP_SKIP_UNLESS_COUNTING_ALLOCATIONS();
  constexpr int kWarmUp = 20, kFrames = 300;
  tf2::BufferCore tf(ros::Duration(10.0));
  add_static_laser(tf);
  TfPoseSource poses(tf, "map");
  MessageMapper mapper(MessageMapperOptions{}, poses);
  PointCloudData cloud;
  sensor_msgs::PointCloud2 msg;
  double next_pose_s = 99.0;
  allocation_counter().allocations = 0;
  for (int k = 0; k < kWarmUp + kFrames; ++k) {
    fill_stripe_cloud(msg, k);
    const double stamp_s = msg.header.stamp.toSec();
    add_trunk_poses(tf, next_pose_s, stamp_s + 0.05);
    g_now_s = stamp_s + 0.005;
    count(k >= kWarmUp);
    take_point_cloud(msg, cloud, mapper, test_now);
    count(false);
  }
  EXPECT_EQ(allocation_counter().allocations.load(), 0u) << "over " << kFrames << " clouds";
  EXPECT_EQ(mapper.stats().mapped, static_cast<std::size_t>(kWarmUp + kFrames));
  EXPECT_EQ(mapper.stats().dropped(), 0u);
  EXPECT_EQ(mapper.stats().beams_not_finite, static_cast<std::size_t>(kWarmUp + kFrames));
}

TEST(RosScanCallbackAllocation, AnUnreadableCloudIsDroppedWithItsReason) {
  TopicPoseSource poses(1.0);
  MessageMapper mapper(MessageMapperOptions{}, poses);
  PointCloudData cloud;
  sensor_msgs::PointCloud2 msg;
  fill_stripe_cloud(msg, 0);
  msg.data.pop_back();  // one byte short of width x point_step
  g_now_s = 100.0;
  take_point_cloud(msg, cloud, mapper, test_now);
  EXPECT_EQ(mapper.stats().unreadable, 1u);
  EXPECT_NE(mapper.last_drop().find("do not match the 7679 bytes of data"), std::string::npos) << mapper.last_drop();
}

}  // namespace
}  // namespace stridemap::ros_adapter
