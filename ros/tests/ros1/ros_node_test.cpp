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
#include <sstream>
#include <string>

#include <sys/wait.h>

#include <diagnostic_msgs/DiagnosticArray.h>
#include <grid_map_msgs/GridMap.h>
#include <gtest/gtest.h>
#include <nav_msgs/MapMetaData.h>
#include <nav_msgs/OccupancyGrid.h>
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

#include "ros_fixture.hpp"
#include "sim_truth.hpp"
#include "stridemap_ros/ros1_messages.hpp"
#include "test_paths.hpp"

namespace stridemap::ros_test {
namespace ros_node_test {
namespace {

const std::string kScene = std::string(STRIDEMAP_SOURCE_DIR) + "/scenes/cart_rail_boxes.yaml";

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

// The run as a bag: per scan, the trunk's TF around the scan's stamp, then the scan.
void write_bag(const std::string& path, const SimulatedRun& run) {
  rosbag::Bag bag(path, rosbag::bagmode::Write);
  tf2_msgs::TFMessage static_tf;
  static_tf.transforms.push_back(stamped(run.sensor_on_trunk, "base_link", "laser", kStart));
  bag.write("/tf_static", ros::Time(kStart), static_tf);
  for (const SimulatedScan& scan : run.scans) {
    const double t = kStart + scan.time_s;
    write_trunk_tf(bag, scan.trunk_in_map, t);
    bag.write("/scan", ros::Time(t), laser_scan(run, scan, t));
  }
  bag.close();
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
  nav_msgs::OccupancyGrid::ConstPtr occupancy;
  grid_map_msgs::GridMap::ConstPtr grid;
  ros::Subscriber s5 = nh_->subscribe<nav_msgs::OccupancyGrid>(
      "/stridemap_mapper/traversability", 1, [&](const nav_msgs::OccupancyGrid::ConstPtr& m) { occupancy = m; });
  ros::Subscriber s6 = nh_->subscribe<grid_map_msgs::GridMap>(
      "/stridemap_mapper/grid_map", 1, [&](const grid_map_msgs::GridMap::ConstPtr& m) { grid = m; });

  const auto players = play(*nh_, bag, "stridemap_mapper");
  const double n = static_cast<double>(run.scans.size());
  ASSERT_TRUE(wait_for([&] { return diag("scans_mapped") + diag("scans_dropped") >= n; }, 120.0, pump))
      << "the node did not account for every scan; diagnostics: scans " << diag("scans") << "\n"
      << read_text(log_);
  EXPECT_EQ(diag("scans_mapped"), n) << message_;
  EXPECT_EQ(diag("scans_dropped"), 0.0) << message_;
  EXPECT_EQ(level_, diagnostic_msgs::DiagnosticStatus::OK);
  EXPECT_EQ(diag("beams_not_finite"), 0.0);
  EXPECT_GT(diag("beams_out_of_range"), 0.0);  // the URG's error codes and ranges beyond its limit
  EXPECT_GT(diag("newest_mapped_age_ms"), 0.0);  // the bag's stamps are long past
  // Every output from the publication after the last scan (they arrive on separate connections).
  const double last = kStart + run.scans.back().time_s - 1e-6;
  ASSERT_TRUE(wait_for([&] { return elevation && info && cloud && marker && elevation->header.stamp.toSec() >= last &&
                                    cloud->header.stamp.toSec() >= last && marker->header.stamp.toSec() >= last &&
                                    info->map_load_time.toSec() >= last && occupancy && grid &&
                                    occupancy->header.stamp.toSec() >= last && grid->info.header.stamp.toSec() >= last; },
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

  // The OccupancyGrid: the images' geometry in the map frame.
  EXPECT_EQ(occupancy->header.frame_id, "map");
  EXPECT_EQ(occupancy->info.width, info->width);
  EXPECT_EQ(occupancy->info.height, info->height);
  EXPECT_EQ(occupancy->info.resolution, info->resolution);
  EXPECT_EQ(occupancy->info.origin.position.x, info->origin.position.x);
  EXPECT_EQ(occupancy->info.origin.position.y, info->origin.position.y);
  ASSERT_EQ(occupancy->data.size(), static_cast<std::size_t>(info->width) * info->height);

  // The GridMap, read with the generated definitions: ~layers then the
  // foothold score; centre, lengths and grid_map's reversed, column-major order.
  const std::uint32_t w = info->width;
  EXPECT_EQ(grid->info.header.frame_id, "map");
  ASSERT_EQ(grid->layers, (std::vector<std::string>{"elevation", "certainty", "mean_elevation", "state", "foothold_score"}));
  ASSERT_EQ(grid->data.size(), grid->layers.size());
  EXPECT_EQ(grid->basic_layers, std::vector<std::string>{"elevation"});
  EXPECT_NEAR(grid->info.resolution, info->resolution, 1e-6);
  EXPECT_NEAR(grid->info.length_x, w * grid->info.resolution, 1e-9);
  EXPECT_NEAR(grid->info.pose.position.x, info->origin.position.x + 0.5 * grid->info.length_x, 1e-6);
  EXPECT_NEAR(grid->info.pose.position.y, info->origin.position.y + 0.5 * grid->info.length_y, 1e-6);
  for (const std_msgs::Float32MultiArray& layer : grid->data) {
    ASSERT_EQ(layer.layout.dim.size(), 2u);
    EXPECT_EQ(layer.layout.dim[0].label, "column_index");
    EXPECT_EQ(layer.layout.dim[1].label, "row_index");
    ASSERT_EQ(layer.data.size(), static_cast<std::size_t>(w) * w);
  }
  // Image cell (r, c) is grid_map's (row w-1-c, column w-1-r). One known cell
  // first (the middle of the known ones), then every cell.
  auto grid_at = [&](std::size_t layer, std::uint32_t r, std::uint32_t c) {
    return grid->data[layer].data[static_cast<std::size_t>(w - 1 - r) * w + (w - 1 - c)];
  };
  int known_score = 0, seen = 0;
  for (std::uint32_t r = 0; r < w; ++r) {
    for (std::uint32_t c = 0; c < w; ++c) {
      const float v = z[r * w + c];
      if (std::isfinite(v) && ++seen == known / 2) {
        EXPECT_EQ(grid_at(0, r, c), v) << "known cell " << r << ", " << c;
      }
      const float g = grid_at(0, r, c);
      EXPECT_TRUE(std::isnan(v) ? std::isnan(g) : g == v) << r << ", " << c;
      const float score = grid_at(4, r, c);
      const std::int8_t o = occupancy->data[r * w + c];
      EXPECT_EQ(o, stridemap::ros_adapter::occupancy_of_score(score)) << r << ", " << c;
      if (o >= 0) ++known_score;
    }
  }
  EXPECT_GT(known_score, known / 2) << "too few cells with a foothold score";

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
  // The run's counts for scripts, as the summary line gives them.
  const std::string summary = read_text(out + "/summary.json");
  EXPECT_NE(summary.find("\"command\": \"map --bag\""), std::string::npos) << summary;
  EXPECT_NE(summary.find("\"mapped\": "), std::string::npos) << summary;
  EXPECT_EQ(summary.find("\"mapped\": 0,"), std::string::npos) << summary;

  // Clearing empties the published map: the next cloud and marker are empty.
  cloud.reset();
  marker.reset();
  ASSERT_TRUE(ros::service::call("/stridemap_mapper/clear_map", save));
  EXPECT_TRUE(save.response.success);
  ASSERT_TRUE(wait_for([&] { return cloud && marker && cloud->width == 0 && marker->points.empty(); }, 30.0, pump))
      << "no empty map published after ~clear_map; last cloud width "
      << (cloud ? std::to_string(cloud->width) : std::string("none"));
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
      write_trunk_tf(b, scan.trunk_in_map, t);
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
      "stridemap_bad", {{"pose_wait_s", "5.0"}, {"publish_every_s", "0.2"}, {"map_file", user_file}});  // see ros_cloud_test
  listen_to_diagnostics("stridemap_bad");
  const auto players = play(*nh_, bag, "stridemap_bad");
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
  // A relative ~map_file is under ROS_HOME (the fixture's folder), not the node's working folder.
  const std::string node_map = *folder_ + "/odom_node.smap";
  // A scanner less accurate than the URG: the node's parameter and map --bag's option alike.
  std::unique_ptr<Child> node =
      start_node("stridemap_odom", {{"pose_topic", "/odom"}, {"pose_wait_s", "30.0"}, {"range_error_m", "0.03"},
                                    {"publish_every_s", "0.2"}, {"map_file", "odom_node.smap"}});
  listen_to_diagnostics("stridemap_odom");
  const auto players = play(*nh_, bag, "stridemap_odom");
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
  EXPECT_NE(read_text(log_).find("stridemap_node: config='' map_frame='map'"), std::string::npos) << read_text(log_);
  EXPECT_NE(read_text(log_).find("range_error_m=0.03"), std::string::npos) << read_text(log_);
  EXPECT_NE(read_text(log_).find("map_file='" + node_map + "'"), std::string::npos) << read_text(log_);
  const std::string out = *folder_ + "/odom_from_bag";
  const std::string command = std::string(STRIDEMAP_CLI_PATH) + " map --bag " + bag +
                              " --scan-topic /scan --pose-topic /odom --pose-wait-s 30 --range-error-m 0.03 --out " + out + " > " +
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

  // A pose topic of another message type: named with its type, nothing written.
  const std::string wrong_type = std::string(STRIDEMAP_CLI_PATH) + " map --bag " + bag +
                                 " --scan-topic /scan --pose-topic /scan --out " + *folder_ + "/never > " + *folder_ +
                                 "/wrong_type.log 2>&1";
  const int type_status = std::system(wrong_type.c_str());
  EXPECT_TRUE(WIFEXITED(type_status) && WEXITSTATUS(type_status) == 2) << read_text(*folder_ + "/wrong_type.log");
  EXPECT_NE(read_text(*folder_ + "/wrong_type.log")
                .find("--pose-topic '/scan' carries sensor_msgs/LaserScan, not geometry_msgs/PoseStamped or nav_msgs/Odometry"),
            std::string::npos)
      << read_text(*folder_ + "/wrong_type.log");
  EXPECT_FALSE(std::filesystem::exists(*folder_ + "/never"));
  EXPECT_FALSE(std::filesystem::exists(*folder_ + "/never"));
}

TEST_F(RosNodeTest, ABadQueueSizeStopsTheNodeNamingTheParameter) {
  for (const char* name : {"scan_queue_size", "cloud_queue_size"}) {
    // One name each: the first node's private parameters stay on the parameter server.
    std::unique_ptr<Child> node = start_node(std::string("stridemap_bad_") + name, {{name, "0"}, {"cloud_topic", "/stripe"}});
    ASSERT_TRUE(wait_for([&] { return !node->running(); }, 60.0)) << name << " 0 was taken";
    EXPECT_TRUE(WIFEXITED(node->exit_status()) && WEXITSTATUS(node->exit_status()) == 2) << name;
    EXPECT_NE(read_text(log_).find(std::string("~") + name + ": 0 is outside [1, 100000]"), std::string::npos)
        << read_text(log_);
  }
}

TEST_F(RosNodeTest, AnUnknownOccupancyLayerStopsTheNodeNamingTheParameter) {
  std::unique_ptr<Child> node = start_node("stridemap_bad_occupancy", {{"occupancy_layer", "no_such_layer"}});
  ASSERT_TRUE(wait_for([&] { return !node->running(); }, 60.0)) << "an unknown ~occupancy_layer was taken";
  EXPECT_TRUE(WIFEXITED(node->exit_status()) && WEXITSTATUS(node->exit_status()) == 2);
  EXPECT_NE(read_text(log_).find("~occupancy_layer"), std::string::npos) << read_text(log_);
  EXPECT_NE(read_text(log_).find("no_such_layer"), std::string::npos) << read_text(log_);
}

// roscpp's own param() would fall back to the default: a typo in a launch
// file would map with settings nobody chose.
TEST_F(RosNodeTest, AParameterOfTheWrongTypeOrRangeOrNameStopsTheNodeNamingIt) {
  const struct {
    std::string key, value, expected;
  } cases[] = {
      {"pose_wait_s", "abc", "~pose_wait_s: 'abc' is a string, not a number"},
      {"publish_every_s", "-1", "~publish_every_s: -1 is outside [0.001, 3600]"},
      {"scan_queue_size", "2.5", "~scan_queue_size: 2.5 is a double, not an integer"},
      {"map_frame", "7", "~map_frame: 7 is an integer, not a string"},
      {"pose_wiat_s", "1.0", "unknown parameter ~pose_wiat_s; this node reads ~config"},
  };
  int k = 0;
  for (const auto& c : cases) {
    std::unique_ptr<Child> node = start_node("stridemap_bad_param_" + std::to_string(k++), {{c.key, c.value}});
    ASSERT_TRUE(wait_for([&] { return !node->running(); }, 60.0)) << c.key << ":=" << c.value << " was taken";
    EXPECT_TRUE(WIFEXITED(node->exit_status()) && WEXITSTATUS(node->exit_status()) == 2) << c.key;
    EXPECT_NE(read_text(log_).find(c.expected), std::string::npos) << read_text(log_);
  }
}

TEST_F(RosNodeTest, HelpListsTheParametersWithoutAMaster) {
  const std::string dead_master = "http://127.0.0.1:" + std::to_string(free_port());
  const std::string node = STRIDEMAP_NODE_PATH;
  const std::string bridge = (std::filesystem::path(node).parent_path() / "stridemap_urg_bridge").string();
  for (const std::string& program : {node, bridge}) {
    const std::string log = *folder_ + "/help.log";
    const std::string command = "ROS_MASTER_URI=" + dead_master + " timeout 20 " + program + " --help > " + log + " 2>&1";
    const int status = std::system(command.c_str());
    EXPECT_TRUE(WIFEXITED(status) && WEXITSTATUS(status) == 0) << program << "\n" << read_text(log);
    EXPECT_NE(read_text(log).find("_config:=path"), std::string::npos) << read_text(log);
    // docs/ros.md's parameter tables name every parameter the program reads.
    const std::string docs = read_text(std::string(STRIDEMAP_SOURCE_DIR) + "/docs/ros.md");
    std::istringstream lines(read_text(log));
    for (std::string line; std::getline(lines, line);) {
      if (line.rfind("  _", 0) != 0) continue;
      const std::string name = line.substr(3, line.find(":=") - 3);
      EXPECT_NE(docs.find("`~" + name + "`"), std::string::npos) << name << " is not in docs/ros.md";
    }
  }
}

}  // namespace
}  // namespace ros_node_test
}  // namespace stridemap::ros_test
