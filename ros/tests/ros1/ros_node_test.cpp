// The node against a real roscore: simulated scans and TF (the cart rail,
// written to a bag first) played to stridemap_node; its published layers
// against the simulator's truth; its saved map against `stridemap map
// --bag` on the same bag, bit for bit; bad messages counted, never fatal.
#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <map>
#include <memory>
#include <string>

#include <sys/wait.h>

#include <diagnostic_msgs/DiagnosticArray.h>
#include <gtest/gtest.h>
#include <nav_msgs/MapMetaData.h>
#include <nav_msgs/Odometry.h>
#include <ros/ros.h>
#include <rosbag/bag.h>
#include <rosbag/view.h>
#include <sensor_msgs/Image.h>
#include <sensor_msgs/LaserScan.h>
#include <sensor_msgs/PointCloud2.h>
#include <std_srvs/Trigger.h>
#include <tf2_msgs/TFMessage.h>
#include <visualization_msgs/Marker.h>

#include "ros_harness.hpp"
#include "sim_truth.hpp"
#include "stridemap_ros/ros1_messages.hpp"

namespace stridemap::ros_test {
namespace {

constexpr double kStart = 1000.0;  // the bag's clock: stamps from here
const std::string kScene = std::string(STRIDEMAP_SOURCE_DIR) + "/scenes/cart_rail_boxes.yaml";

geometry_msgs::TransformStamped stamped(const Eigen::Isometry3d& pose, const std::string& parent,
                                        const std::string& child, double stamp_s) {
  geometry_msgs::TransformStamped t;
  t.header.stamp.fromSec(stamp_s);
  t.header.frame_id = parent;
  t.child_frame_id = child;
  t.transform = ros_adapter::to_transform(pose);
  return t;
}

sensor_msgs::LaserScan laser_scan(const SimulatedRun& run, const SimulatedScan& scan, double stamp_s,
                                  const std::string& frame = "laser") {
  sensor_msgs::LaserScan msg;
  msg.header.stamp.fromSec(stamp_s);
  msg.header.frame_id = frame;
  msg.angle_min = static_cast<float>(run.angle_min_rad);
  msg.angle_increment = static_cast<float>(run.angle_increment_rad);
  msg.angle_max = static_cast<float>(run.angle_min_rad + run.angle_increment_rad * (scan.ranges_m.size() - 1));
  msg.scan_time = 0.1f;
  msg.range_min = static_cast<float>(run.range_min_m);
  msg.range_max = static_cast<float>(run.range_max_m);
  msg.ranges = scan.ranges_m;
  return msg;
}

// The trunk's TF for a scan at `t`: two samples of its pose around the
// stamp, never at it, so tf2 interpolates between the same two samples
// whenever the lookup happens (in the node as in the bag), and a scan's
// pose is never an exact sample in one and an interpolation in the other.
void write_tf(rosbag::Bag& bag, const SimulatedScan& scan, double t) {
  for (const double dt : {-0.04, 0.04}) {
    tf2_msgs::TFMessage tf;
    tf.transforms.push_back(stamped(scan.trunk_in_map, "map", "base_link", t + dt));
    bag.write("/tf", ros::Time(t), tf);
  }
}

// The run as a bag: per scan, the trunk's TF around the scan's stamp, then the scan.
void write_bag(const std::string& path, const SimulatedRun& run) {
  rosbag::Bag bag(path, rosbag::bagmode::Write);
  tf2_msgs::TFMessage static_tf;
  static_tf.transforms.push_back(stamped(run.sensor_on_trunk, "base_link", "laser", kStart));
  bag.write("/tf_static", ros::Time(kStart), static_tf);
  for (const SimulatedScan& scan : run.scans) {
    const double t = kStart + scan.time_s;
    write_tf(bag, scan, t);
    bag.write("/scan", ros::Time(t), laser_scan(run, scan, t));
  }
  bag.close();
}

// One roscore for the test program, started on a free port; this process
// is the publisher and the listener.
class RosNodeTest : public ::testing::Test {
 protected:
  static void SetUpTestSuite() {
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

  static void TearDownTestSuite() {
    if (ros::isStarted()) ros::shutdown();
    delete roscore_;
    roscore_ = nullptr;
    // Kept when a test failed: the logs of roscore and the node are there.
    if (!::testing::UnitTest::GetInstance()->Failed()) std::filesystem::remove_all(*folder_);
  }

  void SetUp() override {
    ASSERT_TRUE(master_up_) << "roscore did not come up within 60 s:\n" << read_text(*folder_ + "/roscore.log");
    nh_ = std::make_unique<ros::NodeHandle>();
  }

  // Starts the node under `name` with the given private parameters.
  std::unique_ptr<Child> start_node(const std::string& name, const std::map<std::string, std::string>& params) {
    std::vector<std::string> argv{STRIDEMAP_NODE_PATH, "__name:=" + name};
    for (const auto& [key, value] : params) argv.push_back("_" + key + ":=" + value);
    log_ = *folder_ + "/" + name + ".log";
    return std::make_unique<Child>(argv, log_);
  }

  // The latest diagnostics of `name`, as key -> value.
  void listen_to_diagnostics(const std::string& name) {
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

  double diag(const std::string& key) const {
    const auto it = diagnostics_.find(key);
    return it == diagnostics_.end() ? -1.0 : it->second;
  }

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

std::string* RosNodeTest::folder_ = nullptr;
Child* RosNodeTest::roscore_ = nullptr;
bool RosNodeTest::master_up_ = false;

// Plays a bag's messages in their recorded order, each on its topic, once
// the node listens on all of them. The pacing keeps the node's queues from
// overflowing on a loaded machine; the tests then wait on the node's own
// counts, not on time.
void play(ros::NodeHandle& nh, const std::string& bag_path, const std::string& node) {
  ros::Publisher scan_pub = nh.advertise<sensor_msgs::LaserScan>("/scan", 1000);
  ros::Publisher tf_pub = nh.advertise<tf2_msgs::TFMessage>("/tf", 1000);
  ros::Publisher static_pub = nh.advertise<tf2_msgs::TFMessage>("/tf_static", 10, true);
  ros::Publisher odom_pub = nh.advertise<nav_msgs::Odometry>("/odom", 1000);
  rosbag::Bag bag(bag_path, rosbag::bagmode::Read);
  bool odom = false;
  for (const rosbag::ConnectionInfo* c : rosbag::View(bag).getConnections()) odom = odom || c->topic == "/odom";
  ASSERT_TRUE(wait_for([&] { return scan_pub.getNumSubscribers() > 0 && (odom ? odom_pub.getNumSubscribers() > 0 :
                                    tf_pub.getNumSubscribers() > 0 && static_pub.getNumSubscribers() > 0); },
                       60.0, [] { ros::spinOnce(); }))
      << node << " did not subscribe to /scan and its poses within 60 s";
  for (const rosbag::MessageInstance& m : rosbag::View(bag)) {
    if (m.getTopic() == "/scan") scan_pub.publish(m.instantiate<sensor_msgs::LaserScan>());
    if (m.getTopic() == "/tf") tf_pub.publish(m.instantiate<tf2_msgs::TFMessage>());
    if (m.getTopic() == "/tf_static") static_pub.publish(m.instantiate<tf2_msgs::TFMessage>());
    if (m.getTopic() == "/odom") odom_pub.publish(m.instantiate<nav_msgs::Odometry>());
    ros::WallDuration(0.003).sleep();
  }
}

TEST_F(RosNodeTest, MapsSimulatedScansLikeTheTruthAndLikeMapBagBitForBit) {
  const SimulatedRun run = simulate_cart_rail(kScene, 120, 7);
  const std::string bag = *folder_ + "/cart_rail.bag";
  write_bag(bag, run);

  const std::string node_map = *folder_ + "/node.smap";
  std::unique_ptr<Child> node = start_node(
      "stridemap_mapper", {{"pose_wait_s", "30.0"}, {"publish_every_s", "0.2"}, {"map_file", node_map}});
  listen_to_diagnostics("stridemap_mapper");
  sensor_msgs::Image::ConstPtr elevation;
  nav_msgs::MapMetaData::ConstPtr info;
  sensor_msgs::PointCloud2::ConstPtr cloud;
  visualization_msgs::Marker::ConstPtr marker;
  ros::Subscriber s1 = nh_->subscribe<sensor_msgs::Image>(
      "/stridemap_mapper/layers/elevation", 1, [&](const sensor_msgs::Image::ConstPtr& m) { elevation = m; });
  ros::Subscriber s2 = nh_->subscribe<nav_msgs::MapMetaData>(
      "/stridemap_mapper/map_info", 1, [&](const nav_msgs::MapMetaData::ConstPtr& m) { info = m; });
  ros::Subscriber s3 = nh_->subscribe<sensor_msgs::PointCloud2>(
      "/stridemap_mapper/cloud", 1, [&](const sensor_msgs::PointCloud2::ConstPtr& m) { cloud = m; });
  ros::Subscriber s4 = nh_->subscribe<visualization_msgs::Marker>(
      "/stridemap_mapper/marker", 1, [&](const visualization_msgs::Marker::ConstPtr& m) { marker = m; });

  play(*nh_, bag, "stridemap_mapper");
  const double n = static_cast<double>(run.scans.size());
  ASSERT_TRUE(wait_for([&] { return diag("scans_mapped") + diag("scans_dropped") >= n; }, 120.0, pump))
      << "the node did not account for every scan; diagnostics: scans " << diag("scans") << "\n"
      << read_text(log_);
  EXPECT_EQ(diag("scans_mapped"), n) << message_;
  EXPECT_EQ(diag("scans_dropped"), 0.0) << message_;
  EXPECT_EQ(level_, diagnostic_msgs::DiagnosticStatus::OK);
  // Every output from the publication after the last scan (they arrive on separate connections).
  const double last = kStart + run.scans.back().time_s - 1e-6;
  ASSERT_TRUE(wait_for([&] { return elevation && info && cloud && marker && elevation->header.stamp.toSec() >= last &&
                                    cloud->header.stamp.toSec() >= last && marker->header.stamp.toSec() >= last &&
                                    info->map_load_time.toSec() >= last; },
                       60.0, pump));

  // The published elevation image against the scene's surface (simulator truth).
  ASSERT_EQ(elevation->encoding, "32FC1");
  ASSERT_EQ(elevation->width, info->width);
  ASSERT_EQ(elevation->height, info->height);
  const SceneTruth truth(kScene);
  const auto* z = reinterpret_cast<const float*>(elevation->data.data());
  double sum2 = 0.0;
  int known = 0;
  for (std::uint32_t r = 0; r < elevation->height; ++r) {
    for (std::uint32_t c = 0; c < elevation->width; ++c) {
      const float v = z[r * elevation->width + c];
      if (!std::isfinite(v)) continue;
      const double x = info->origin.position.x + (c + 0.5) * info->resolution;
      const double y = info->origin.position.y + (r + 0.5) * info->resolution;
      const double e = v - truth.surface_height_m(x, y);
      sum2 += e * e;
      ++known;
    }
  }
  ASSERT_GT(known, 2000) << "too few cells mapped";
  const double rms = std::sqrt(sum2 / known);
  EXPECT_LT(rms, 0.02) << "elevation RMS against the simulator's truth over " << known << " cells";
  RecordProperty("elevation_rms_mm", std::to_string(rms * 1000.0));
  EXPECT_EQ(cloud->width, static_cast<std::uint32_t>(known));
  EXPECT_EQ(cloud->fields.size(), 3u + 4u);  // x, y, z + elevation, certainty, mean_elevation, state
  EXPECT_EQ(cloud->fields[4].name, "certainty");
  EXPECT_EQ(marker->points.size(), static_cast<std::size_t>(known));

  // Save through the service; the bag through `stridemap map --bag`; the same map.
  std_srvs::Trigger save;
  ASSERT_TRUE(ros::service::waitForService("/stridemap_mapper/save_map", 30000));
  ASSERT_TRUE(ros::service::call("/stridemap_mapper/save_map", save));
  ASSERT_TRUE(save.response.success) << save.response.message;
  const std::string out = *folder_ + "/from_bag";
  const std::string command = std::string(STRIDEMAP_CLI_PATH) + " map --bag " + bag +
                              " --scan-topic /scan --tf --pose-wait-s 30 --out " + out + " > " + *folder_ +
                              "/map_bag.log 2>&1";
  ASSERT_EQ(std::system(command.c_str()), 0) << read_text(*folder_ + "/map_bag.log");
  EXPECT_EQ(compare_map_files(node_map, out + "/map.smap"), "");

  // Clearing empties the published map.
  ASSERT_TRUE(ros::service::call("/stridemap_mapper/clear_map", save));
  EXPECT_TRUE(save.response.success);
  EXPECT_TRUE(node->running()) << read_text(log_);
}

TEST_F(RosNodeTest, BadMessagesAreCountedAndReportedNeverFatal) {
  const SimulatedRun run = simulate_cart_rail(kScene, 12, 3);
  const std::string bag = *folder_ + "/bad.bag";
  {
    rosbag::Bag b(bag, rosbag::bagmode::Write);
    tf2_msgs::TFMessage static_tf;
    static_tf.transforms.push_back(stamped(run.sensor_on_trunk, "base_link", "laser", kStart));
    b.write("/tf_static", ros::Time(kStart), static_tf);
    for (std::size_t k = 0; k < 10; ++k) {
      const SimulatedScan& scan = run.scans[k];
      const double t = kStart + scan.time_s;
      write_tf(b, scan, t);
      sensor_msgs::LaserScan msg = laser_scan(run, scan, t);
      if (k == 3) msg.ranges.assign(msg.ranges.size(), std::nanf(""));  // every range NaN
      if (k == 4) msg.ranges[100] = std::nanf("");                      // one NaN range
      b.write("/scan", ros::Time(t), msg);
      if (k == 5) b.write("/scan", ros::Time(t), laser_scan(run, scan, t + 0.01, "camera"));  // wrong frame
      if (k == 6) b.write("/scan", ros::Time(t), laser_scan(run, scan, t - 0.5));  // stamp going back
    }
    // TF never reaches this scan's stamp: it times out (pose_wait_s).
    b.write("/scan", ros::Time(kStart + 5.0), laser_scan(run, run.scans[11], kStart + 5.0));
    b.close();
  }
  const std::string user_file = *folder_ + "/users_map.smap";
  {
    std::ofstream(user_file) << "a user's file, not the node's\n";
  }
  std::unique_ptr<Child> node = start_node(
      "stridemap_bad", {{"pose_wait_s", "1.0"}, {"publish_every_s", "0.2"}, {"map_file", user_file}});
  listen_to_diagnostics("stridemap_bad");
  play(*nh_, bag, "stridemap_bad");
  ASSERT_TRUE(wait_for([&] { return diag("scans") >= 13 && diag("dropped_pose_timeout") >= 1; }, 120.0, pump))
      << "diagnostics never showed the last scan timed out\n" << read_text(log_);
  EXPECT_EQ(diag("scans"), 13.0);
  EXPECT_EQ(diag("dropped_no_valid_beams"), 1.0);
  EXPECT_EQ(diag("scans_with_nan_ranges"), 2.0);
  EXPECT_EQ(diag("dropped_wrong_frame"), 1.0);
  EXPECT_EQ(diag("dropped_stamp_not_increasing"), 1.0);
  EXPECT_EQ(diag("dropped_pose_timeout"), 1.0);
  EXPECT_EQ(diag("scans_mapped"), 9.0);
  EXPECT_EQ(level_, diagnostic_msgs::DiagnosticStatus::WARN);
  EXPECT_NE(message_.find("4 scans dropped"), std::string::npos) << message_;
  EXPECT_TRUE(node->running()) << read_text(log_);

  // The user's file is not replaced.
  std_srvs::Trigger save;
  ASSERT_TRUE(ros::service::waitForService("/stridemap_bad/save_map", 30000));
  ASSERT_TRUE(ros::service::call("/stridemap_bad/save_map", save));
  EXPECT_FALSE(save.response.success);
  EXPECT_NE(save.response.message.find("was not written by this run"), std::string::npos) << save.response.message;
  EXPECT_EQ(read_text(user_file), "a user's file, not the node's\n");
  EXPECT_TRUE(node->running()) << read_text(log_);
}

TEST_F(RosNodeTest, PosesFromAnOdometryTopicGiveMapBagsMapBitForBit) {
  const SimulatedRun run = simulate_cart_rail(kScene, 40, 11);
  const std::string bag = *folder_ + "/odom.bag";
  {
    rosbag::Bag b(bag, rosbag::bagmode::Write);
    for (const SimulatedScan& scan : run.scans) {
      const double t = kStart + scan.time_s;
      for (const double dt : {-0.04, 0.04}) {  // around the scan, as write_tf
        nav_msgs::Odometry odom;
        odom.header.stamp.fromSec(t + dt);
        odom.header.frame_id = "map";
        odom.child_frame_id = "base_link";
        const geometry_msgs::Transform tr = ros_adapter::to_transform(scan.trunk_in_map);
        odom.pose.pose.position.x = tr.translation.x;
        odom.pose.pose.position.y = tr.translation.y;
        odom.pose.pose.position.z = tr.translation.z;
        odom.pose.pose.orientation = tr.rotation;
        b.write("/odom", ros::Time(t), odom);
      }
      b.write("/scan", ros::Time(t), laser_scan(run, scan, t));
    }
    b.close();
  }
  const std::string node_map = *folder_ + "/odom_node.smap";
  std::unique_ptr<Child> node = start_node("stridemap_odom", {{"pose_topic", "/odom"}, {"pose_wait_s", "30.0"},
                                                             {"publish_every_s", "0.2"}, {"map_file", node_map}});
  listen_to_diagnostics("stridemap_odom");
  play(*nh_, bag, "stridemap_odom");
  const double n = static_cast<double>(run.scans.size());
  ASSERT_TRUE(wait_for([&] { return diag("scans_mapped") + diag("scans_dropped") >= n; }, 120.0, pump))
      << read_text(log_);
  EXPECT_EQ(diag("scans_mapped"), n) << message_;
  EXPECT_EQ(diag("poses"), 2 * n);
  EXPECT_EQ(diag("poses_rejected"), 0.0);
  std_srvs::Trigger save;
  ASSERT_TRUE(ros::service::waitForService("/stridemap_odom/save_map", 30000));
  ASSERT_TRUE(ros::service::call("/stridemap_odom/save_map", save));
  ASSERT_TRUE(save.response.success) << save.response.message;
  const std::string out = *folder_ + "/odom_from_bag";
  const std::string command = std::string(STRIDEMAP_CLI_PATH) + " map --bag " + bag +
                              " --scan-topic /scan --pose-topic /odom --pose-wait-s 30 --out " + out + " > " +
                              *folder_ + "/odom_map_bag.log 2>&1";
  ASSERT_EQ(std::system(command.c_str()), 0) << read_text(*folder_ + "/odom_map_bag.log");
  EXPECT_EQ(compare_map_files(node_map, out + "/map.smap"), "");

  // A topic the bag does not have: exit 2, the bag's topics listed, nothing written.
  const std::string wrong = std::string(STRIDEMAP_CLI_PATH) + " map --bag " + bag +
                            " --scan-topic /laser --tf --out " + *folder_ + "/never > " + *folder_ +
                            "/wrong_topic.log 2>&1";
  const int status = std::system(wrong.c_str());
  EXPECT_TRUE(WIFEXITED(status) && WEXITSTATUS(status) == 2) << read_text(*folder_ + "/wrong_topic.log");
  EXPECT_NE(read_text(*folder_ + "/wrong_topic.log").find("no scan topic '/laser' in the bag; its topics: /odom, /scan"),
            std::string::npos)
      << read_text(*folder_ + "/wrong_topic.log");
  EXPECT_FALSE(std::filesystem::exists(*folder_ + "/never"));
}

}  // namespace
}  // namespace stridemap::ros_test
