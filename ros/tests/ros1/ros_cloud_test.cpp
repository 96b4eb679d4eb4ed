// The stripe camera's sensor_msgs/PointCloud2 input against a real
// roscore: simulated structured-light frames (Ragno's camera + laser
// stripe on the cart rail, the stripe back-projected to points in the
// sensor frame, written to a bag with TF first) played to stridemap_node;
// its published elevation against the scene (simulated truth); its saved
// map against `stridemap map --bag --cloud-topic` bit for bit; bad clouds
// counted and reported, never fatal.
#include <cmath>
#include <cstring>
#include <fstream>
#include <limits>
#include <memory>
#include <string>
#include <vector>

#include <diagnostic_msgs/DiagnosticArray.h>
#include <gtest/gtest.h>
#include <nav_msgs/MapMetaData.h>
#include <ros/ros.h>
#include <rosbag/bag.h>
#include <sensor_msgs/Image.h>
#include <sensor_msgs/LaserScan.h>
#include <sensor_msgs/PointCloud2.h>
#include <std_srvs/Trigger.h>
#include <tf2_msgs/TFMessage.h>

#include "ros_fixture.hpp"
#include "sim_truth.hpp"
#include "test_paths.hpp"

namespace stridemap::ros_test {
namespace ros_cloud_test {
namespace {

// The objects lined up on the rail, inside the camera's narrow view.
const std::string kScene = std::string(STRIDEMAP_SOURCE_DIR) + "/scenes/cart_rail_narrow.yaml";
const std::string kFrame = "stripe_camera";
// The frames come every 40 ms: each frame's two TF samples within +-10 ms of it.
constexpr double kTfHalfWidthS = 0.01;

// x, y, z and sigma as float32, one row.
sensor_msgs::PointCloud2 cloud_message(const SimulatedCloud& frame, double stamp_s, const std::string& frame_id = kFrame) {
  sensor_msgs::PointCloud2 msg;
  msg.header.stamp.fromSec(stamp_s);
  msg.header.frame_id = frame_id;
  for (const char* name : {"x", "y", "z", "sigma"}) {
    sensor_msgs::PointField f;
    f.name = name;
    f.offset = static_cast<std::uint32_t>(msg.fields.size() * sizeof(float));
    f.datatype = sensor_msgs::PointField::FLOAT32;
    f.count = 1;
    msg.fields.push_back(f);
  }
  msg.point_step = 4 * sizeof(float);
  msg.height = 1;
  msg.width = static_cast<std::uint32_t>(frame.points_m.size());
  msg.row_step = msg.width * msg.point_step;
  msg.is_dense = true;
  msg.data.resize(msg.row_step);
  for (std::size_t k = 0; k < frame.points_m.size(); ++k) {
    const float v[4] = {static_cast<float>(frame.points_m[k].x()), static_cast<float>(frame.points_m[k].y()),
                        static_cast<float>(frame.points_m[k].z()), static_cast<float>(frame.height_sigma_m[k])};
    std::memcpy(msg.data.data() + k * msg.point_step, v, sizeof v);
  }
  return msg;
}

// The mapper configuration the node and `map --bag` read: Ragno's mount, 5 mm
// cells (the paper's for structured light) in a window that holds the run.
std::string write_config(const std::string& folder, const SimulatedCloudRun& run) {
  const std::string path = folder + "/structured_light_mapper.yaml";
  std::ofstream(path) << "mount:\n  height_m: " << run.mount_height_m << "\n  pitch_deg: " << run.mount_pitch_deg
                      << "\nmap:\n  cells_per_side: 400\n  cell_size_m: 0.005\n";
  return path;
}

void write_static_tf(rosbag::Bag& bag, const SimulatedCloudRun& run) {
  tf2_msgs::TFMessage static_tf;
  static_tf.transforms.push_back(stamped(run.sensor_on_trunk, "base_link", kFrame, kStart));
  bag.write("/tf_static", ros::Time(kStart), static_tf);
}

TEST_F(RosNodeTest, MapsStripeCloudsLikeTheTruthAndLikeMapBagBitForBit) {
  const SimulatedCloudRun run = simulate_structured_light_rail(kScene, 100, 5);
  const std::string bag_path = *folder_ + "/stripe.bag";
  {
    rosbag::Bag bag(bag_path, rosbag::bagmode::Write);
    write_static_tf(bag, run);
    for (const SimulatedCloud& frame : run.frames) {
      const double t = kStart + frame.time_s;
      write_trunk_tf(bag, frame.trunk_in_map, t, kTfHalfWidthS);
      bag.write("/stripe", ros::Time(t), cloud_message(frame, t));
    }
  }
  const std::string config = write_config(*folder_, run);
  const std::string node_map = *folder_ + "/stripe_node.smap";
  std::unique_ptr<Child> node =
      start_node("stridemap_stripe", {{"config", config}, {"cloud_topic", "/stripe"}, {"pose_wait_s", "30.0"},
                                      // every frame may wait: a loaded CI host must lose none
                                      {"cloud_queue_size", std::to_string(run.frames.size() + 10)},
                                      {"publish_every_s", "0.2"}, {"map_file", node_map}});
  listen_to_diagnostics("stridemap_stripe");
  sensor_msgs::Image::ConstPtr elevation;
  nav_msgs::MapMetaData::ConstPtr info;
  ros::Subscriber s1 = nh_->subscribe<sensor_msgs::Image>(
      "/stridemap_stripe/layers/elevation", 1, [&](const sensor_msgs::Image::ConstPtr& m) { elevation = m; });
  ros::Subscriber s2 = nh_->subscribe<nav_msgs::MapMetaData>(
      "/stridemap_stripe/map_info", 1, [&](const nav_msgs::MapMetaData::ConstPtr& m) { info = m; });

  const auto players = play(*nh_, bag_path, "stridemap_stripe");
  // With a cloud topic the node takes no LaserScan from the default `scan`.
  ros::Publisher scan_pub = nh_->advertise<sensor_msgs::LaserScan>("/scan", 1);
  EXPECT_FALSE(wait_for([&] { return scan_pub.getNumSubscribers() > 0; }, 2.0, pump));
  const double n = static_cast<double>(run.frames.size());
  ASSERT_TRUE(wait_for([&] { return diag("scans_mapped") + diag("scans_dropped") >= n; }, 120.0, pump))
      << "the node did not account for every cloud; scans " << diag("scans") << "\n" << read_text(log_);
  EXPECT_EQ(diag("scans_mapped"), n) << message_;
  EXPECT_EQ(diag("scans_dropped"), 0.0) << message_;
  EXPECT_EQ(diag("beams_not_finite"), 0.0);
  EXPECT_EQ(level_, diagnostic_msgs::DiagnosticStatus::OK);
  const double last = kStart + run.frames.back().time_s - 1e-6;
  ASSERT_TRUE(wait_for([&] { return elevation && info && elevation->header.stamp.toSec() >= last &&
                                    info->map_load_time.toSec() >= last; },
                       60.0, pump));

  // The published elevation against the scene's surface (simulated truth).
  ASSERT_EQ(elevation->header.frame_id, "map");
  ASSERT_EQ(elevation->width, info->width);
  ASSERT_NEAR(info->resolution, 0.005, 1e-9);
  const SceneTruth truth(kScene);
  const auto* z = reinterpret_cast<const float*>(elevation->data.data());
  double sum2 = 0.0;
  int known = 0, on_objects = 0;
  for (std::uint32_t r = 0; r < elevation->height; ++r) {
    for (std::uint32_t c = 0; c < elevation->width; ++c) {
      const float v = z[r * elevation->width + c];
      if (!std::isfinite(v)) continue;
      const double x = info->origin.position.x + (c + 0.5) * info->resolution;
      const double y = info->origin.position.y + (r + 0.5) * info->resolution;
      const double h = truth.surface_height_m(x, y);
      sum2 += (v - h) * (v - h);
      ++known;
      if (h > 0.05) ++on_objects;
    }
  }
  ASSERT_GT(known, 5000) << "too few cells mapped";
  EXPECT_GT(on_objects, 500) << "the boxes' tops are not in the map";
  const double rms = std::sqrt(sum2 / known);
  EXPECT_LT(rms, 0.010) << "elevation RMS against the simulator's truth over " << known << " cells";
  RecordProperty("stripe_elevation_rms_mm", std::to_string(rms * 1000.0));
  RecordProperty("stripe_known_cells", std::to_string(known));

  // The node's saved map and `map --bag --cloud-topic` of the same bag: the same, bit for bit.
  std_srvs::Trigger save;
  ASSERT_TRUE(ros::service::waitForService("/stridemap_stripe/save_map", 30000));
  ASSERT_TRUE(ros::service::call("/stridemap_stripe/save_map", save));
  ASSERT_TRUE(save.response.success) << save.response.message;
  const std::string out = *folder_ + "/stripe_from_bag";
  const std::string log = *folder_ + "/stripe_map_bag.log";
  ASSERT_EQ(run_tool(std::string(STRIDEMAP_CLI_PATH) + " map --bag " + bag_path + " --cloud-topic /stripe --tf " +
                         "--pose-wait-s 30 --config " + config + " --out " + out, log),
            0)
      << read_text(log);
  EXPECT_EQ(compare_map_files(node_map, out + "/map.smap"), "");
  EXPECT_TRUE(node->running()) << read_text(log_);
}

TEST_F(RosNodeTest, BadCloudsAreCountedAndReportedNeverFatal) {
  const SimulatedCloudRun run = simulate_structured_light_rail(kScene, 12, 9);
  const std::string bag_path = *folder_ + "/bad_stripe.bag";
  const float nan = std::numeric_limits<float>::quiet_NaN();
  std::size_t nan_points = 0;
  {
    rosbag::Bag bag(bag_path, rosbag::bagmode::Write);
    write_static_tf(bag, run);
    for (std::size_t k = 0; k < 10; ++k) {
      const SimulatedCloud& frame = run.frames[k];
      const double t = kStart + frame.time_s;
      write_trunk_tf(bag, frame.trunk_in_map, t, kTfHalfWidthS);
      SimulatedCloud points = frame;
      if (k == 3) {  // every point NaN
        for (Eigen::Vector3d& p : points.points_m) p.x() = nan;
        nan_points += points.points_m.size();
      }
      if (k == 4) {  // one NaN coordinate
        points.points_m[10].z() = nan;
        ++nan_points;
      }
      bag.write("/stripe", ros::Time(t), cloud_message(points, t));
      if (k == 5) bag.write("/stripe", ros::Time(t), cloud_message(frame, t + 0.01, "camera_optical"));  // wrong frame
      if (k == 6) bag.write("/stripe", ros::Time(t), cloud_message(frame, t - 0.5));  // stamp going back
      if (k == 7) {  // no z field
        sensor_msgs::PointCloud2 msg = cloud_message(frame, t + 0.01);
        msg.fields.erase(msg.fields.begin() + 2);
        bag.write("/stripe", ros::Time(t), msg);
      }
      if (k == 8) {  // fewer bytes than the header says
        sensor_msgs::PointCloud2 msg = cloud_message(frame, t + 0.01);
        msg.data.resize(msg.data.size() / 2);
        bag.write("/stripe", ros::Time(t), msg);
      }
    }
    // TF never reaches this cloud's stamp: it times out (pose_wait_s).
    bag.write("/stripe", ros::Time(kStart + 5.0), cloud_message(run.frames[11], kStart + 5.0));
  }
  const std::string config = write_config(*folder_, run);
  const std::string node_map = *folder_ + "/bad_stripe_node.smap";
  std::unique_ptr<Child> node =
      // 5 s of waiting for TF: on a loaded machine a good cloud's TF may come
      // late, and only the cloud whose TF never comes is meant to time out.
      start_node("stridemap_bad_stripe", {{"config", config}, {"cloud_topic", "/stripe"}, {"pose_wait_s", "5.0"},
                                          {"publish_every_s", "0.2"}, {"map_file", node_map}});
  listen_to_diagnostics("stridemap_bad_stripe");
  const auto players = play(*nh_, bag_path, "stridemap_bad_stripe");
  ASSERT_TRUE(wait_for([&] { return diag("scans") >= 15 && diag("dropped_pose_timeout") >= 1; }, 120.0, pump))
      << "diagnostics never showed the last cloud timed out: scans " << diag("scans") << ", mapped "
      << diag("scans_mapped") << ", pose timeouts " << diag("dropped_pose_timeout") << "\n"
      << read_text(log_);
  EXPECT_EQ(diag("scans"), 15.0);
  EXPECT_EQ(diag("scans_mapped"), 9.0);
  EXPECT_EQ(diag("dropped_no_valid_beams"), 1.0);
  EXPECT_EQ(diag("scans_with_nan_ranges"), 2.0);
  EXPECT_EQ(diag("beams_not_finite"), static_cast<double>(nan_points));
  EXPECT_EQ(diag("dropped_wrong_frame"), 1.0);
  EXPECT_EQ(diag("dropped_stamp_not_increasing"), 1.0);
  EXPECT_EQ(diag("dropped_unreadable"), 2.0);
  EXPECT_EQ(diag("dropped_pose_timeout"), 1.0);
  EXPECT_EQ(level_, diagnostic_msgs::DiagnosticStatus::WARN);
  EXPECT_NE(message_.find("6 scans dropped"), std::string::npos) << message_;
  EXPECT_TRUE(node->running()) << read_text(log_);

  // `map --bag` counts the same clouds the same way and makes the same map.
  std_srvs::Trigger save;
  ASSERT_TRUE(ros::service::waitForService("/stridemap_bad_stripe/save_map", 30000));
  ASSERT_TRUE(ros::service::call("/stridemap_bad_stripe/save_map", save));
  ASSERT_TRUE(save.response.success) << save.response.message;
  const std::string out = *folder_ + "/bad_stripe_from_bag";
  const std::string log = *folder_ + "/bad_stripe_map_bag.log";
  ASSERT_EQ(run_tool(std::string(STRIDEMAP_CLI_PATH) + " map --bag " + bag_path + " --cloud-topic /stripe --tf " +
                         "--pose-wait-s 1 --config " + config + " --out " + out, log),
            0)
      << read_text(log);
  EXPECT_NE(read_text(log).find("9 scans mapped of 15, 0 before the first pose (dropped: 1 wrong frame, 1 stamp not increasing, 2 unreadable, "
                                "0 bad scan fields, 1 no valid beams, 1 pose timeout"),
            std::string::npos)
      << read_text(log);
  EXPECT_EQ(compare_map_files(node_map, out + "/map.smap"), "");
  EXPECT_TRUE(node->running()) << read_text(log_);
}

}  // namespace
}  // namespace ros_cloud_test
}  // namespace stridemap::ros_test
