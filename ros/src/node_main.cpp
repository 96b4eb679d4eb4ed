// stridemap_node: the ROS 1 node (docs/ros.md). Scans (LaserScan or
// PointCloud2) and poses (TF or a pose topic) in, through MessageMapper to
// the library's MappingPipeline; the map out as images, a cloud, a marker,
// an OccupancyGrid of the foothold score, a grid_map_msgs/GridMap and
// diagnostics; services to save and clear the map.
#include <algorithm>
#include <cstdio>
#include <cstdint>
#include <memory>
#include <set>
#include <sstream>
#include <string>
#include <vector>

#include <geometry_msgs/PoseStamped.h>
#include <nav_msgs/Odometry.h>
#include <ros/ros.h>
#include <std_srvs/Trigger.h>
#include <tf2_ros/buffer.h>
#include <tf2_ros/transform_listener.h>
#include <topic_tools/shape_shifter.h>

#include "stridemap/core/error.hpp"
#include "stridemap_ros/map_saving.hpp"
#include "stridemap_ros/node_callbacks.hpp"
#include "stridemap_ros/node_parameters.hpp"
#include "stridemap_ros/ros1_messages.hpp"

namespace stridemap::ros_adapter {
namespace {

std::vector<std::string> split_names(const std::string& text) {
  std::vector<std::string> names;
  std::stringstream in(text);
  for (std::string name; std::getline(in, name, ',');) {
    if (!name.empty()) names.push_back(name);
  }
  return names;
}

double wall_now() { return ros::WallTime::now().toSec(); }

/// Everything the node reads from `~`, declared once for reading, `--help`
/// and the start-up line.
struct NodeSettings {
  MessageMapperOptions mapper;
  std::string scan_topic, cloud_topic, pose_topic, layers, occupancy_layer, map_file;
  double publish_every_s = 0.5;
  int scan_queue_size = 200, cloud_queue_size = 50;
};

NodeSettings read_node_settings(ParameterReader& read) {
  NodeSettings s;
  MessageMapperOptions& m = s.mapper;
  const std::string home = ros_home();
  m.config_path = read.path("config", "", home, "the mapper YAML (docs/config.md); empty: the defaults");
  m.map_frame = read.text("map_frame", m.map_frame, "TF's fixed frame; the pose topic's and the outputs' frame");
  m.sensor_frame = read.text("sensor_frame", m.sensor_frame, "the frame scans must carry; empty: the first scan's");
  m.range_error_m = read.number("range_error_m", m.range_error_m, 1e-6, 1.0, "Delta r: a beam's range error bound [m]");
  m.range_error_fraction =
      read.number("range_error_fraction", m.range_error_fraction, 0.0, 1.0, "Delta r's part proportional to the range");
  m.min_intensity = read.number("min_intensity", m.min_intensity, 0.0, 1e12, "beams below this intensity are not used; 0: all");
  m.pose_wait_s = read.number("pose_wait_s", m.pose_wait_s, 0.0, 3600.0, "how long a scan waits for its pose [s]");
  m.max_pose_gap_s =
      read.number("max_pose_gap_s", m.max_pose_gap_s, 1e-6, 3600.0, "pose topic: no interpolation across wider gaps [s]");
  s.cloud_topic = read.text("cloud_topic", "", "PointCloud2 stripes (x, y, z in the sensor frame); empty: none");
  // A stripe camera's node does not also take whatever LaserScan is on
  // `scan` (two sensors in one map would drop each other's frames).
  s.scan_topic = read.text("scan_topic", s.cloud_topic.empty() ? "scan" : "",
                           "LaserScan topic; empty by default when ~cloud_topic is given");
  s.pose_topic = read.text("pose_topic", "", "PoseStamped or Odometry in ~map_frame; empty: TF");
  s.layers = read.text("layers", "elevation,certainty,mean_elevation,state",
                       "layers published as images, cloud and GridMap; fused_elevation or fused_variance keeps both");
  for (const std::string& name : split_names(s.layers)) {
    m.fused_heights = m.fused_heights || name == "fused_elevation" || name == "fused_variance";
  }
  s.occupancy_layer =
      read.text("occupancy_layer", "foothold_score", "the score in [0, 1] behind ~traversability; empty: no OccupancyGrid");
  s.publish_every_s = read.number("publish_every_s", s.publish_every_s, 1e-3, 3600.0, "how often the map is published [s]");
  // roscpp drops the oldest message past a subscriber's queue without a
  // word, so these are the node's only say in what a busy host loses.
  s.scan_queue_size = read.integer("scan_queue_size", s.scan_queue_size, 1, 100000, "LaserScans queued for the node");
  s.cloud_queue_size = read.integer("cloud_queue_size", s.cloud_queue_size, 1, 100000, "clouds queued for the node");
  s.map_file = read.path("map_file", "stridemap_map.smap", home, "where ~save_map writes; relative: under ROS_HOME");
  return s;
}

class Node {
 public:
  explicit Node(ros::NodeHandle& nh, ros::NodeHandle& pnh) : pnh_(pnh), tf_(ros::Duration(30.0)), listener_(tf_) {
    const ServerParameters server(pnh);
    ParameterReader read(server);
    NodeSettings settings = read_node_settings(read);
    read.refuse_unknown();
    ROS_INFO("stridemap_node: %s", read.summary().c_str());
    const MessageMapperOptions& options = settings.mapper;
    const std::string& scan_topic = settings.scan_topic;
    const std::string& cloud_topic = settings.cloud_topic;
    const std::string& pose_topic = settings.pose_topic;
    const double publish_every_s = settings.publish_every_s;
    const int scan_queue_size = settings.scan_queue_size, cloud_queue_size = settings.cloud_queue_size;
    map_file_ = settings.map_file;
    occupancy_layer_ = settings.occupancy_layer;
    layer_names_ = split_names(settings.layers);
    if (scan_topic.empty() && cloud_topic.empty()) throw InputError("~scan_topic and ~cloud_topic: both empty");

    if (pose_topic.empty()) {
      poses_ = std::make_unique<TfPoseSource>(tf_, options.map_frame);
    } else {
      auto topic = std::make_unique<TopicPoseSource>(options.max_pose_gap_s);
      topic_poses_ = topic.get();
      poses_ = std::move(topic);
      pose_sub_ = nh.subscribe(pose_topic, 100, &Node::on_pose, this);
    }
    mapper_ = std::make_unique<MessageMapper>(options, *poses_);
    // The map is checked against the layer names once, so a typo fails at start.
    (void)mapper_->layers(layer_names_);
    grid_map_names_ = layer_names_;
    if (!occupancy_layer_.empty()) {
      try {
        (void)mapper_->layers({occupancy_layer_});
      } catch (const InputError& e) {
        throw InputError(std::string("~occupancy_layer (empty: no OccupancyGrid): ") + e.what());
      }
      const auto at = std::find(layer_names_.begin(), layer_names_.end(), occupancy_layer_);
      occupancy_index_ = static_cast<std::size_t>(at - layer_names_.begin());
      if (at == layer_names_.end()) grid_map_names_.push_back(occupancy_layer_);
    }
    if (!scan_topic.empty()) scan_sub_ = nh.subscribe(scan_topic, static_cast<std::uint32_t>(scan_queue_size), &Node::on_scan, this);
    if (!cloud_topic.empty()) cloud_sub_ = nh.subscribe(cloud_topic, static_cast<std::uint32_t>(cloud_queue_size), &Node::on_cloud, this);
    for (const std::string& name : layer_names_) {
      image_pubs_.push_back(pnh.advertise<sensor_msgs::Image>("layers/" + name, 1, true));
    }
    info_pub_ = pnh.advertise<nav_msgs::MapMetaData>("map_info", 1, true);
    grid_map_pub_ = pnh.advertise<grid_map_msgs::GridMap>("grid_map", 1, true);
    if (!occupancy_layer_.empty()) occupancy_pub_ = pnh.advertise<nav_msgs::OccupancyGrid>("traversability", 1, true);
    cloud_pub_ = pnh.advertise<sensor_msgs::PointCloud2>("cloud", 1, true);
    marker_pub_ = pnh.advertise<visualization_msgs::Marker>("marker", 1, true);
    diag_pub_ = nh.advertise<diagnostic_msgs::DiagnosticArray>("/diagnostics", 10);
    save_srv_ = pnh.advertiseService("save_map", &Node::on_save, this);
    clear_srv_ = pnh.advertiseService("clear_map", &Node::on_clear, this);
    process_timer_ = nh.createWallTimer(ros::WallDuration(0.05), [this](const ros::WallTimerEvent&) { guarded("timer", [&] { process(); }); });
    publish_timer_ =
        nh.createWallTimer(ros::WallDuration(publish_every_s), [this](const ros::WallTimerEvent&) { guarded("publish", [&] { publish(); }); });
    // Flushed: a node whose output goes to a file or pipe is asked about its settings first.
    std::fflush(stdout);
  }

 private:
  // A message the library refuses must not end the node: said, and mapping goes on.
  template <typename Body>
  void guarded(const char* what, Body&& body) {
    try {
      body();
    } catch (const std::exception& e) {
      ROS_ERROR_THROTTLE(2.0, "stridemap_node: %s: %s", what, e.what());
    }
  }

  void on_scan(const sensor_msgs::LaserScan::ConstPtr& msg) {
    guarded("scan", [&] { warn_if_dropped(take_laser_scan(*msg, scan_, *mapper_, wall_now)); });
  }

  void on_cloud(const sensor_msgs::PointCloud2::ConstPtr& msg) {
    guarded("cloud", [&] { warn_if_dropped(take_point_cloud(*msg, cloud_, *mapper_, wall_now)); });
  }

  // PoseStamped or Odometry, whichever the topic carries.
  void on_pose(const topic_tools::ShapeShifter::ConstPtr& msg) {
    guarded("pose", [&] { pose_message(*msg); });
  }

  void pose_message(const topic_tools::ShapeShifter& msg) {
    if (msg.getDataType() == "geometry_msgs/PoseStamped") {
      const auto p = msg.instantiate<geometry_msgs::PoseStamped>();
      warn_if_dropped(
          ros_adapter::take_pose(*mapper_, *topic_poses_, p->header.frame_id, p->header.stamp, p->pose, wall_now));
    } else if (msg.getDataType() == "nav_msgs/Odometry") {
      const auto o = msg.instantiate<nav_msgs::Odometry>();
      warn_if_dropped(
          ros_adapter::take_pose(*mapper_, *topic_poses_, o->header.frame_id, o->header.stamp, o->pose.pose, wall_now));
    } else {
      ROS_WARN_THROTTLE(5.0, "stridemap_node: pose topic carries %s, not PoseStamped or Odometry",
                        msg.getDataType().c_str());
      mapper_->count_pose(false);
      process();
    }
  }

  void process() { warn_if_dropped(map_waiting(*mapper_, wall_now())); }

  void warn_if_dropped(bool dropped) {
    if (dropped) ROS_WARN_THROTTLE(2.0, "stridemap_node: scan dropped: %s", mapper_->last_drop().c_str());
  }

  void publish() {
    const ros::Time stamp = mapper_->last_mapped_stamp_s() ? ros::Time(*mapper_->last_mapped_stamp_s()) : ros::Time(0);
    diag_pub_.publish(diagnostics(mapper_->stats(), mapper_->last_drop(), ros::this_node::getName(), ros::Time::now(),
                                  mapper_->last_mapped_stamp_s()));
    if (mapper_->stats().mapped == published_at_) return;
    published_at_ = mapper_->stats().mapped;
    const std::string& frame = mapper_->options().map_frame;
    // One copy of the map for every message: the GridMap carries the
    // occupancy layer too, the images, cloud and marker only ~layers.
    MapLayers layers = mapper_->layers(grid_map_names_);
    grid_map_pub_.publish(grid_map_message(layers, frame, stamp));
    if (!occupancy_layer_.empty()) occupancy_pub_.publish(occupancy_grid(layers, occupancy_index_, frame, stamp));
    layers.names.resize(layer_names_.size());
    layers.values.resize(layer_names_.size());
    const MapMessages m = map_messages(layers, frame, stamp);
    for (std::size_t k = 0; k < image_pubs_.size(); ++k) image_pubs_[k].publish(m.images[k]);
    info_pub_.publish(m.info);
    cloud_pub_.publish(m.cloud);
    marker_pub_.publish(m.marker);
  }

  bool on_save(std_srvs::Trigger::Request&, std_srvs::Trigger::Response& res) {
    try {
      // Read at each call, so `rosparam set` then a call saves elsewhere.
      const ServerParameters server(pnh_);
      ParameterReader read(server);
      const std::string path = read.path("map_file", map_file_, ros_home(), "");
      save_map(*mapper_, path, "stridemap_node " + ros::this_node::getName(), written_);
      res.success = true;
      res.message = path + ": " + std::to_string(mapper_->stats().mapped) + " scans";
    } catch (const std::exception& e) {
      res.success = false;
      res.message = e.what();
    }
    return true;
  }

  bool on_clear(std_srvs::Trigger::Request&, std_srvs::Trigger::Response& res) {
    mapper_->clear();
    published_at_ = static_cast<std::size_t>(-1);
    res.success = true;
    res.message = "map cleared";
    return true;
  }

  ros::NodeHandle& pnh_;
  tf2_ros::Buffer tf_;
  tf2_ros::TransformListener listener_;
  std::unique_ptr<PoseSource> poses_;
  TopicPoseSource* topic_poses_ = nullptr;
  std::unique_ptr<MessageMapper> mapper_;
  std::vector<std::string> layer_names_;
  std::vector<std::string> grid_map_names_;  ///< layer_names_, then occupancy_layer_ if not among them
  std::string occupancy_layer_;
  std::size_t occupancy_index_ = 0;  ///< in grid_map_names_
  std::string map_file_;
  std::set<std::string> written_;
  LaserScanData scan_;  // the frame name's storage reused from scan to scan
  PointCloudData cloud_;
  std::size_t published_at_ = 0;
  ros::Subscriber scan_sub_, cloud_sub_, pose_sub_;
  std::vector<ros::Publisher> image_pubs_;
  ros::Publisher grid_map_pub_, occupancy_pub_;
  ros::Publisher info_pub_, cloud_pub_, marker_pub_, diag_pub_;
  ros::ServiceServer save_srv_, clear_srv_;
  ros::WallTimer process_timer_, publish_timer_;
};

}  // namespace
}  // namespace stridemap::ros_adapter

int main(int argc, char** argv) {
  using namespace stridemap::ros_adapter;
  if (asks_for_help(argc, argv)) {
    const std::string help =
        node_help("stridemap_node", "scans and poses in, the terrain map out (docs/ros.md)", read_node_settings);
    std::fputs(help.c_str(), stdout);
    return 0;
  }
  ros::init(argc, argv, "stridemap_node");
  ros::NodeHandle nh;
  ros::NodeHandle pnh("~");
  try {
    Node node(nh, pnh);
    ros::spin();
  } catch (const std::exception& e) {  // a bad parameter or config file: said, exit 2
    ROS_FATAL("stridemap_node: %s", e.what());
    return 2;
  }
  return 0;
}
