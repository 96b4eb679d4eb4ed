#include "ros_fixture.hpp"

#include <cstdlib>
#include <filesystem>
#include <set>

#include <diagnostic_msgs/DiagnosticArray.h>
#include <tf2_msgs/TFMessage.h>
#include <rosbag/view.h>
#include <topic_tools/shape_shifter.h>

#include "stridemap_ros/ros1_messages.hpp"
#include "test_paths.hpp"

namespace stridemap::ros_test {

geometry_msgs::TransformStamped stamped(const Eigen::Isometry3d& pose, const std::string& parent,
                                        const std::string& child, double stamp_s) {
  geometry_msgs::TransformStamped t;
  t.header.stamp.fromSec(stamp_s);
  t.header.frame_id = parent;
  t.child_frame_id = child;
  t.transform = ros_adapter::to_transform(pose);
  return t;
}

void write_trunk_tf(rosbag::Bag& bag, const Eigen::Isometry3d& trunk_in_map, double t, double half_width_s) {
  for (const double dt : {-half_width_s, half_width_s}) {
    tf2_msgs::TFMessage tf;
    tf.transforms.push_back(stamped(trunk_in_map, "map", "base_link", t + dt));
    bag.write("/tf", ros::Time(t), tf);
  }
}

std::map<std::string, ros::Publisher> play(ros::NodeHandle& nh, const std::string& bag_path, const std::string& node) {
  rosbag::Bag bag(bag_path, rosbag::bagmode::Read);
  std::map<std::string, ros::Publisher> publishers;
  for (const rosbag::MessageInstance& m : rosbag::View(bag)) {
    if (publishers.count(m.getTopic())) continue;
    const auto message = m.instantiate<topic_tools::ShapeShifter>();
    publishers[m.getTopic()] = message->advertise(nh, m.getTopic(), 1000, m.getTopic() == "/tf_static");
  }
  const bool subscribed = wait_for(
      [&] {
        for (const auto& [topic, publisher] : publishers) {
          if (publisher.getNumSubscribers() == 0) return false;
        }
        return true;
      },
      60.0, [] { ros::spinOnce(); });
  EXPECT_TRUE(subscribed) << node << " did not subscribe to every topic of " << bag_path << " within 60 s";
  if (!subscribed) return {};
  for (const rosbag::MessageInstance& m : rosbag::View(bag)) {
    publishers[m.getTopic()].publish(m.instantiate<topic_tools::ShapeShifter>());
    ros::WallDuration(0.003).sleep();
  }
  return publishers;
}

std::string* RosNodeTest::folder_ = nullptr;
Child* RosNodeTest::roscore_ = nullptr;
bool RosNodeTest::master_up_ = false;

void RosNodeTest::SetUpTestSuite() {
  folder_ = new std::string(temp_folder("node"));
  const int port = free_port();
  const std::string uri = "http://127.0.0.1:" + std::to_string(port);
  // This process and its children only: roscore, the node and the tool.
  ::setenv("ROS_MASTER_URI", uri.c_str(), 1);
  ::setenv("ROS_HOSTNAME", "127.0.0.1", 1);
  ::setenv("ROS_HOME", folder_->c_str(), 1);
  ::setenv("ROS_LOG_DIR", folder_->c_str(), 1);
  roscore_ = new Child({"roscore", "-p", std::to_string(port)}, *folder_ + "/roscore.log");
  int argc = 0;
  ros::init(argc, nullptr, "stridemap_ros_test", ros::init_options::NoSigintHandler | ros::init_options::AnonymousName);
  master_up_ = wait_for([] { return ros::master::check(); }, 60.0);
}

void RosNodeTest::TearDownTestSuite() {
  if (ros::isStarted()) ros::shutdown();
  delete roscore_;
  roscore_ = nullptr;
  // Kept when a test failed: the logs of roscore and the node are there.
  if (!::testing::UnitTest::GetInstance()->Failed()) std::filesystem::remove_all(*folder_);
}

void RosNodeTest::SetUp() {
  ASSERT_TRUE(master_up_) << "roscore did not come up within 60 s:\n" << read_text(*folder_ + "/roscore.log");
  nh_ = std::make_unique<ros::NodeHandle>();
}

std::unique_ptr<Child> RosNodeTest::start_node(const std::string& name,
                                               const std::map<std::string, std::string>& params) {
  std::vector<std::string> argv{STRIDEMAP_NODE_PATH, "__name:=" + name};
  for (const auto& [key, value] : params) argv.push_back("_" + key + ":=" + value);
  log_ = *folder_ + "/" + name + ".log";
  return std::make_unique<Child>(argv, log_);
}

void RosNodeTest::listen_to_diagnostics(const std::string& name) {
  diag_sub_ = nh_->subscribe<diagnostic_msgs::DiagnosticArray>(
      "/diagnostics", 10, [this, name](const diagnostic_msgs::DiagnosticArray::ConstPtr& msg) {
        for (const auto& status : msg->status) {
          if (status.name != "/" + name + ": mapping") continue;
          for (const auto& kv : status.values) diagnostics_[kv.key] = std::stod(kv.value);
          level_ = status.level;
          message_ = status.message;
        }
      });
}

double RosNodeTest::diag(const std::string& key) const {
  const auto it = diagnostics_.find(key);
  return it == diagnostics_.end() ? -1.0 : it->second;
}

int RosNodeTest::run_tool(const std::string& command, const std::string& log) const {
  return std::system((command + " > " + log + " 2>&1").c_str());
}

}  // namespace stridemap::ros_test
