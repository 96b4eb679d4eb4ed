#pragma once
// ROS 1 <-> the adapter's plain data (message_mapper.hpp), and the map as
// ROS messages. Everything ROS-specific the node and `map --bag` share is
// here and in node_callbacks.hpp (a LaserScan read, a pose taken); a ROS 2
// port rewrites these two files and the node, nothing else (docs/ros.md,
// "Porting to ROS 2").
#include <optional>
#include <string>
#include <vector>

#include <diagnostic_msgs/DiagnosticArray.h>
#include <geometry_msgs/Pose.h>
#include <geometry_msgs/Transform.h>
#include <grid_map_msgs/GridMap.h>  // generated from ros/msg by gencpp
#include <nav_msgs/MapMetaData.h>
#include <nav_msgs/OccupancyGrid.h>
#include <sensor_msgs/Image.h>
#include <sensor_msgs/LaserScan.h>
#include <sensor_msgs/PointCloud2.h>
#include <tf2/buffer_core.h>
#include <visualization_msgs/Marker.h>

#include "stridemap_ros/message_mapper.hpp"

namespace stridemap::ros_adapter {

/// x, y, z (FLOAT32 or FLOAT64) and an optional "sigma" field. False with
/// `why` for a cloud without them or with sizes that do not add up.
bool point_cloud_data(const sensor_msgs::PointCloud2& msg, PointCloudData& out, std::string& why);

Eigen::Isometry3d to_isometry(const geometry_msgs::Pose& pose);
Eigen::Isometry3d to_isometry(const geometry_msgs::Transform& transform);
geometry_msgs::Transform to_transform(const Eigen::Isometry3d& pose);

/// The sensor's pose from TF: `map_frame` -> the scan's frame at its stamp,
/// interpolated by tf2. Not there yet (TF has not reached the stamp, or
/// the frame is not known yet) is `not_yet`, so the mapper's bounded wait
/// decides.
class TfPoseSource final : public PoseSource {
 public:
  TfPoseSource(const tf2::BufferCore& buffer, std::string map_frame)
      : buffer_(buffer), map_frame_(std::move(map_frame)) {}
  PoseAnswer sensor_in_map(const std::string& frame_id, double stamp_s, Eigen::Isometry3d& out,
                           std::string* why) override;

 private:
  /// TF has the transform a while before `stamp`: then `stamp` is not in
  /// TF's past, and a failure at it means the transform has not come yet.
  bool holds_before(const std::string& frame_id, const ros::Time& stamp) const;

  const tf2::BufferCore& buffer_;
  std::string map_frame_;
};

/// The map as messages, all stamped `stamp` in `map_frame`.
struct MapMessages {
  /// One 32FC1 image per layer, in `layer_names` order: row r, column c is
  /// the cell at origin + ((c + 0.5) res, (r + 0.5) res) (nav_msgs/OccupancyGrid's layout); NaN: unknown.
  std::vector<sensor_msgs::Image> images;
  nav_msgs::MapMetaData info;  ///< the images' geometry
  /// One point per known cell: x, y, z = elevation, then one float32 field per layer.
  sensor_msgs::PointCloud2 cloud;
  /// A CUBE_LIST of the known cells coloured by height, for RViz.
  visualization_msgs::Marker marker;
};

MapMessages map_messages(const MapLayers& map, const std::string& map_frame, const ros::Time& stamp);

/// Occupancy for a foothold score in [0, 1] (values outside clamped):
/// round(100 (1 - score)), so 0 is a perfect foothold and 100 none; NaN
/// (unknown) is -1.
std::int8_t occupancy_of_score(float score);

/// Layer `layer` of `map` read as a score, as nav_msgs/OccupancyGrid: the
/// images' geometry (MapMessages::info) and cell order, occupancy_of_score per cell.
nav_msgs::OccupancyGrid occupancy_grid(const MapLayers& map, std::size_t layer, const std::string& map_frame,
                                       const ros::Time& stamp);

/// Every layer of `map` as grid_map_msgs/GridMap, in grid_map's storage
/// order (docs/ros.md): the pose is the map's centre, lengths in metres,
/// each layer a column-major Float32MultiArray ("column_index",
/// "row_index") whose row index runs against the map's x and column index
/// against its y, from the cell at the map's (max x, max y) corner.
/// "elevation", when published, is the basic layer.
grid_map_msgs::GridMap grid_map_message(const MapLayers& map, const std::string& map_frame, const ros::Time& stamp);

/// The mapper's counts as one DiagnosticStatus: OK while every scan is
/// mapped, WARN once one was dropped (the message names the last reason).
/// With `last_mapped_stamp_s`, also how old the newest data in the map is
/// at `stamp`.
diagnostic_msgs::DiagnosticArray diagnostics(const MessageMapperStats& stats, const std::string& last_drop,
                                             const std::string& node_name, const ros::Time& stamp,
                                             std::optional<double> last_mapped_stamp_s = std::nullopt);

}  // namespace stridemap::ros_adapter
