#pragma once
// A map from a ROS 1 bag (rosbag API, no roscore): the bag's messages in
// the order they were recorded, through the same MessageMapper the node
// runs, with the bag's receive times as the node's arrival times. The same
// bag gives the node's map bit for bit (ros/tests/ros_node_test.cpp).
#include <cstddef>
#include <functional>
#include <memory>
#include <string>
#include <vector>

#include "stridemap_ros/message_mapper.hpp"

namespace stridemap::ros_adapter {

struct BagMappingOptions {
  std::string bag_path;
  std::string scan_topic;    ///< sensor_msgs/LaserScan (this or cloud_topic)
  std::string cloud_topic;   ///< sensor_msgs/PointCloud2
  /// geometry_msgs/PoseStamped or nav_msgs/Odometry of the trunk; empty:
  /// the sensor's pose from the bag's /tf and /tf_static.
  std::string pose_topic;
  MessageMapperOptions mapper{};
};

class BagMapping {
 public:
  /// Opens the bag and checks the topics are in it; throws InputError
  /// naming the bag and listing its topics otherwise.
  explicit BagMapping(const BagMappingOptions& options);
  ~BagMapping();

  /// Plays every message; `progress(done, total)` after each.
  void run(const std::function<void(std::size_t, std::size_t)>& progress = {});

  const MessageMapper& mapper() const { return *mapper_; }
  std::size_t messages() const { return messages_; }

 private:
  struct Bag;  // the bag and TF's buffer
  BagMappingOptions options_;
  std::unique_ptr<Bag> bag_;
  std::unique_ptr<PoseSource> poses_;
  TopicPoseSource* topic_poses_ = nullptr;
  std::unique_ptr<MessageMapper> mapper_;
  std::size_t messages_ = 0;
};

}  // namespace stridemap::ros_adapter
