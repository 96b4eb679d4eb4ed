#pragma once
// The ROS tests' fixture: one roscore per test program run, on a free port
// (its ROS_MASTER_URI set in this process only); this process publishes a
// bag's messages to the node under test and listens to its diagnostics.
#include <map>
#include <memory>
#include <string>
#include <vector>

#include <Eigen/Geometry>
#include <geometry_msgs/TransformStamped.h>
#include <gtest/gtest.h>
#include <ros/ros.h>
#include <rosbag/bag.h>

#include "ros_harness.hpp"

namespace stridemap::ros_test {

constexpr double kStart = 1000.0;  // the bags' clock: stamps from here

geometry_msgs::TransformStamped stamped(const Eigen::Isometry3d& pose, const std::string& parent,
                                        const std::string& child, double stamp_s);

/// The trunk's TF (map -> base_link) for a scan at `t`: two samples of its
/// pose around the stamp (+-`half_width_s`), never at it, so tf2
/// interpolates between the same two samples whenever the lookup happens
/// (in the node as in the bag), and a scan's pose is never an exact sample
/// in one and an interpolation in the other. `half_width_s` must be under
/// half the scan period, or one scan's samples land among the next one's.
void write_trunk_tf(rosbag::Bag& bag, const Eigen::Isometry3d& trunk_in_map, double t, double half_width_s = 0.04);

/// Plays a bag's messages in their recorded order, each on its topic (any
/// type), once the node subscribes to every topic in the bag. The pacing
/// keeps the node's queues from overflowing on a loaded machine; the tests
/// then wait on the node's own counts, not on time. Keep the publishers
/// returned until the node has counted every message: a publisher dropped
/// at once takes the messages still queued in its connections with it,
/// which a slow node on a loaded machine had not read yet.
[[nodiscard]] std::map<std::string, ros::Publisher> play(ros::NodeHandle& nh, const std::string& bag_path,
                                                         const std::string& node);

class RosNodeTest : public ::testing::Test {
 protected:
  static void SetUpTestSuite();
  static void TearDownTestSuite();
  void SetUp() override;

  /// Starts the node under `name` with the given private parameters.
  std::unique_ptr<Child> start_node(const std::string& name, const std::map<std::string, std::string>& params);
  /// Keeps the latest diagnostics of `name` as key -> value.
  void listen_to_diagnostics(const std::string& name);
  /// -1 when the key has not been seen.
  double diag(const std::string& key) const;
  /// Runs `command` (a shell command line) with its output in `log`; its exit status.
  int run_tool(const std::string& command, const std::string& log) const;

  static void pump() { ros::spinOnce(); }

  static std::string* folder_;
  static Child* roscore_;
  static bool master_up_;
  std::unique_ptr<ros::NodeHandle> nh_;
  ros::Subscriber diag_sub_;
  std::map<std::string, double> diagnostics_;
  int level_ = -1;
  std::string message_;
  std::string log_;
};

}  // namespace stridemap::ros_test
