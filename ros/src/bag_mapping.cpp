#include "stridemap_ros/bag_mapping.hpp"

#include <map>
#include <set>

#include <geometry_msgs/PoseStamped.h>
#include <nav_msgs/Odometry.h>
#include <rosbag/bag.h>
#include <rosbag/view.h>
#include <tf2_msgs/TFMessage.h>

#include "stridemap/core/error.hpp"
#include "stridemap_ros/node_callbacks.hpp"
#include "stridemap_ros/ros1_messages.hpp"

namespace stridemap::ros_adapter {

namespace {

// Longer than any bag: tf2's default cache (10 s) would forget the start
// of a bag whose scans wait behind a long gap.
constexpr double kTfCacheS = 1e6;

}  // namespace

struct BagMapping::Bag {
  rosbag::Bag bag;
  tf2::BufferCore tf{ros::Duration(kTfCacheS)};
};

BagMapping::BagMapping(const BagMappingOptions& options)
    : options_(options), bag_(std::make_unique<Bag>()) {
  const std::string& path = options_.bag_path;
  if (options_.scan_topic.empty() == options_.cloud_topic.empty()) {
    throw InputError(path + ": give one scan topic (LaserScan) or one cloud topic (PointCloud2)");
  }
  try {
    bag_->bag.open(path, rosbag::bagmode::Read);
  } catch (const rosbag::BagException& e) {
    throw InputError(path + ": not a readable ROS 1 bag: " + e.what());
  }
  std::set<std::string> topics;
  std::map<std::string, std::string> types;  // topic -> message type
  {
    rosbag::View all(bag_->bag);
    for (const rosbag::ConnectionInfo* c : all.getConnections()) {
      topics.insert(c->topic);
      types[c->topic] = c->datatype;
    }
  }
  // Messages of another type would be passed over one by one and the run
  // would end saying no pose was there: the wrong topic is named at once.
  auto require_type = [&](const std::string& topic, const std::string& option, const std::set<std::string>& wanted,
                          const std::string& hint) {
    if (topic.empty() || !types.count(topic) || wanted.count(types[topic])) return;
    std::string list;
    for (const std::string& w : wanted) list += (list.empty() ? "" : " or ") + w;
    throw InputError(path + ": " + option + " '" + topic + "' carries " + types[topic] + ", not " + list + hint);
  };
  auto require = [&](const std::string& topic, const std::string& what) {
    if (topic.empty() || topics.count(topic)) return;
    std::string list;
    for (const std::string& t : topics) list += (list.empty() ? "" : ", ") + t;
    throw InputError(path + ": no " + what + " topic '" + topic + "' in the bag; its topics: " +
                     (list.empty() ? "none" : list));
  };
  require(options_.scan_topic, "scan");
  require(options_.cloud_topic, "cloud");
  require(options_.pose_topic, "pose");
  require_type(options_.scan_topic, "--scan-topic", {"sensor_msgs/LaserScan"}, "");
  require_type(options_.cloud_topic, "--cloud-topic", {"sensor_msgs/PointCloud2"}, "");
  require_type(options_.pose_topic, "--pose-topic", {"geometry_msgs/PoseStamped", "nav_msgs/Odometry"},
               types[options_.pose_topic] == "tf2_msgs/TFMessage" ? " (TF: use --tf)" : "");
  if (options_.pose_topic.empty()) {
    require("/tf", "TF");
    poses_ = std::make_unique<TfPoseSource>(bag_->tf, options_.mapper.map_frame);
  } else {
    auto topic = std::make_unique<TopicPoseSource>(options_.mapper.max_pose_gap_s);
    topic_poses_ = topic.get();
    poses_ = std::move(topic);
  }
  mapper_ = std::make_unique<MessageMapper>(options_.mapper, *poses_);
}

BagMapping::~BagMapping() = default;

void BagMapping::run(const std::function<void(std::size_t, std::size_t)>& progress) {
  std::vector<std::string> topics;
  for (const std::string& t : {options_.scan_topic, options_.cloud_topic, options_.pose_topic}) {
    if (!t.empty()) topics.push_back(t);
  }
  if (options_.pose_topic.empty()) {
    topics.emplace_back("/tf");
    topics.emplace_back("/tf_static");
  }
  try {
    rosbag::View view(bag_->bag, rosbag::TopicQuery(topics));
    const std::size_t total = view.size();
    LaserScanData scan;
    PointCloudData cloud;
    std::string why;
    for (const rosbag::MessageInstance& m : view) {
      const double now = m.getTime().toSec();
      const std::string& topic = m.getTopic();
      if (topic == options_.scan_topic) {
        if (auto msg = m.instantiate<sensor_msgs::LaserScan>()) {
          read_laser_scan(*msg, scan);
          mapper_->add(scan, now);
        }
      } else if (topic == options_.cloud_topic) {
        if (auto msg = m.instantiate<sensor_msgs::PointCloud2>()) {
          if (point_cloud_data(*msg, cloud, why)) {
            mapper_->add(cloud, now);
          } else {
            mapper_->add_unreadable(msg->header.frame_id, why);
          }
        }
      } else if (topic == options_.pose_topic) {
        if (auto p = m.instantiate<geometry_msgs::PoseStamped>()) {
          mapper_->count_pose(p->header.frame_id == options_.mapper.map_frame &&
                              topic_poses_->add(p->header.stamp.toSec(), to_isometry(p->pose)));
        } else if (auto o = m.instantiate<nav_msgs::Odometry>()) {
          mapper_->count_pose(o->header.frame_id == options_.mapper.map_frame &&
                              topic_poses_->add(o->header.stamp.toSec(), to_isometry(o->pose.pose)));
        }
      } else if (auto tf = m.instantiate<tf2_msgs::TFMessage>()) {
        const bool is_static = topic == "/tf_static";
        for (const geometry_msgs::TransformStamped& t : tf->transforms) {
          bag_->tf.setTransform(t, "bag", is_static);  // a bad transform is refused (and logged) by tf2
        }
      }
      mapper_->process(now, false);
      ++messages_;
      if (progress) progress(messages_, total);
    }
    mapper_->process(0.0, true);
  } catch (const rosbag::BagException& e) {
    throw InputError(options_.bag_path + ": " + e.what() + " (after " + std::to_string(messages_) + " messages)");
  } catch (const ros::Exception& e) {
    throw InputError(options_.bag_path + ": " + e.what() + " (after " + std::to_string(messages_) + " messages)");
  }
}

}  // namespace stridemap::ros_adapter
