#include "stridemap_ros/ros1_messages.hpp"

#include <algorithm>
#include <cmath>
#include <cstring>
#include <limits>

#include <sensor_msgs/image_encodings.h>
#include <tf2/exceptions.h>

namespace stridemap::ros_adapter {

namespace {

const sensor_msgs::PointField* field(const sensor_msgs::PointCloud2& msg, const std::string& name) {
  for (const sensor_msgs::PointField& f : msg.fields) {
    if (f.name == name) return &f;
  }
  return nullptr;
}

bool readable(const sensor_msgs::PointCloud2& msg, const sensor_msgs::PointField* f) {
  if (!f || f->count != 1) return false;
  const std::size_t size = f->datatype == sensor_msgs::PointField::FLOAT32   ? 4
                           : f->datatype == sensor_msgs::PointField::FLOAT64 ? 8
                                                                              : 0;
  return size != 0 && static_cast<std::size_t>(f->offset) + size <= msg.point_step;
}

double read(const std::uint8_t* point, const sensor_msgs::PointField& f) {
  if (f.datatype == sensor_msgs::PointField::FLOAT32) {
    float v;
    std::memcpy(&v, point + f.offset, sizeof v);
    return v;
  }
  double v;
  std::memcpy(&v, point + f.offset, sizeof v);
  return v;
}

}  // namespace

bool point_cloud_data(const sensor_msgs::PointCloud2& msg, PointCloudData& out, std::string& why) {
  out.stamp_s = msg.header.stamp.toSec();
  out.frame_id = msg.header.frame_id;
  out.points_m.clear();
  out.height_sigma_m.clear();
  const sensor_msgs::PointField* x = field(msg, "x");
  const sensor_msgs::PointField* y = field(msg, "y");
  const sensor_msgs::PointField* z = field(msg, "z");
  const sensor_msgs::PointField* sigma = field(msg, "sigma");
  if (!readable(msg, x) || !readable(msg, y) || !readable(msg, z) || (sigma && !readable(msg, sigma))) {
    std::string names;
    for (const sensor_msgs::PointField& f : msg.fields) names += (names.empty() ? "" : ", ") + f.name;
    why = "needs float32 or float64 fields x, y, z (and optionally sigma) of count 1 inside point_step " +
          std::to_string(msg.point_step) + "; its fields: " + (names.empty() ? "none" : names);
    return false;
  }
  if (msg.is_bigendian) {
    why = "big-endian clouds are not read";
    return false;
  }
  // row_step may pad each row beyond width x point_step (the message allows it).
  const std::size_t row_bytes = static_cast<std::size_t>(msg.width) * msg.point_step;
  if (msg.row_step < row_bytes || msg.data.size() != static_cast<std::size_t>(msg.row_step) * msg.height) {
    why = "width " + std::to_string(msg.width) + ", height " + std::to_string(msg.height) + ", point_step " +
          std::to_string(msg.point_step) + " and row_step " + std::to_string(msg.row_step) + " do not match the " +
          std::to_string(msg.data.size()) + " bytes of data";
    return false;
  }
  out.points_m.reserve(static_cast<std::size_t>(msg.width) * msg.height);
  for (std::size_t row = 0; row < msg.height; ++row) {
    for (std::size_t k = 0; k < msg.width; ++k) {
      const std::uint8_t* p = msg.data.data() + row * msg.row_step + k * msg.point_step;
      out.points_m.emplace_back(read(p, *x), read(p, *y), read(p, *z));
      if (sigma) out.height_sigma_m.push_back(read(p, *sigma));
    }
  }
  return true;
}

Eigen::Isometry3d to_isometry(const geometry_msgs::Pose& pose) {
  Eigen::Isometry3d t = Eigen::Isometry3d::Identity();
  const Eigen::Quaterniond q(pose.orientation.w, pose.orientation.x, pose.orientation.y, pose.orientation.z);
  // A quaternion far from unit length is a broken message: NaN makes the mapper drop it.
  const double n = q.norm();
  t.linear() = std::abs(n - 1.0) < 1e-3 ? q.normalized().toRotationMatrix()
                                          : Eigen::Matrix3d::Constant(std::numeric_limits<double>::quiet_NaN());
  t.translation() = Eigen::Vector3d(pose.position.x, pose.position.y, pose.position.z);
  return t;
}

Eigen::Isometry3d to_isometry(const geometry_msgs::Transform& transform) {
  geometry_msgs::Pose pose;
  pose.position.x = transform.translation.x;
  pose.position.y = transform.translation.y;
  pose.position.z = transform.translation.z;
  pose.orientation = transform.rotation;
  return to_isometry(pose);
}

geometry_msgs::Transform to_transform(const Eigen::Isometry3d& pose) {
  geometry_msgs::Transform t;
  t.translation.x = pose.translation().x();
  t.translation.y = pose.translation().y();
  t.translation.z = pose.translation().z();
  const Eigen::Quaterniond q(pose.rotation());
  t.rotation.w = q.w();
  t.rotation.x = q.x();
  t.rotation.y = q.y();
  t.rotation.z = q.z();
  return t;
}

PoseAnswer TfPoseSource::sensor_in_map(const std::string& frame_id, double stamp_s, Eigen::Isometry3d& out,
                                       std::string* why) {
  ros::Time stamp;
  try {
    stamp.fromSec(stamp_s);
  } catch (const std::exception&) {
    if (why) *why = "the stamp is not a ROS time";
    return PoseAnswer::never;
  }
  if (!buffer_.canTransform(map_frame_, frame_id, stamp)) {
    // tf2 puts its reason into words (allocating) only when asked: a scan
    // that only waits, the usual case, needs none.
    if (!why && holds_before(frame_id, stamp)) return PoseAnswer::not_yet;
    std::string reason;
    buffer_.canTransform(map_frame_, frame_id, stamp, &reason);
    if (why) *why = reason;
    // Older than everything TF holds: waiting cannot help.
    return reason.find("into the past") != std::string::npos ? PoseAnswer::never : PoseAnswer::not_yet;
  }
  try {
    out = to_isometry(buffer_.lookupTransform(map_frame_, frame_id, stamp).transform);
  } catch (const tf2::TransformException& e) {
    if (why) *why = e.what();
    return PoseAnswer::not_yet;
  }
  return PoseAnswer::ok;
}

bool TfPoseSource::holds_before(const std::string& frame_id, const ros::Time& stamp) const {
  // A second: far more than TF lags on a working robot, far less than the
  // time it keeps. Asking at time 0 (the newest TF) instead allocates in tf2.
  constexpr double kLookBackS = 1.0;
  return stamp.toSec() > kLookBackS && buffer_.canTransform(map_frame_, frame_id, stamp - ros::Duration(kLookBackS));
}

namespace {

void add_field(sensor_msgs::PointCloud2& cloud, const std::string& name) {
  sensor_msgs::PointField f;
  f.name = name;
  f.offset = static_cast<std::uint32_t>(cloud.fields.size() * sizeof(float));
  f.datatype = sensor_msgs::PointField::FLOAT32;
  f.count = 1;
  cloud.fields.push_back(f);
}

std_msgs::ColorRGBA height_colour(float z, float lo, float hi) {
  // Blue (low) through green to red (high), as the CLI's elevation PNGs run.
  const float t = hi > lo ? std::clamp((z - lo) / (hi - lo), 0.0f, 1.0f) : 0.5f;
  std_msgs::ColorRGBA c;
  c.r = std::clamp(2.0f * t - 1.0f, 0.0f, 1.0f);
  c.g = 1.0f - std::abs(2.0f * t - 1.0f);
  c.b = std::clamp(1.0f - 2.0f * t, 0.0f, 1.0f);
  c.a = 1.0f;
  return c;
}

// The grid's geometry, shared by the layer images' info and the
// OccupancyGrid, so that the two cannot disagree.
nav_msgs::MapMetaData map_meta_data(const MapLayers& map, const ros::Time& stamp) {
  nav_msgs::MapMetaData info;
  const double res = map.cell_size_m;
  info.map_load_time = stamp;
  info.resolution = static_cast<float>(res);
  info.width = static_cast<std::uint32_t>(map.cells_per_side);
  info.height = static_cast<std::uint32_t>(map.cells_per_side);
  info.origin.position.x = static_cast<double>(map.min_cell_x) * res;
  info.origin.position.y = static_cast<double>(map.min_cell_y) * res;
  info.origin.orientation.w = 1.0;
  return info;
}

}  // namespace

MapMessages map_messages(const MapLayers& map, const std::string& map_frame, const ros::Time& stamp) {
  MapMessages m;
  const int n = map.cells_per_side;
  const std::size_t cells = static_cast<std::size_t>(n) * static_cast<std::size_t>(n);
  const double res = map.cell_size_m;
  m.info = map_meta_data(map, stamp);

  std_msgs::Header header;
  header.stamp = stamp;
  header.frame_id = map_frame;
  // MapLayers is (i = x index, j = y index); an image row is one y.
  for (const std::vector<float>& values : map.values) {
    sensor_msgs::Image image;
    image.header = header;
    image.height = static_cast<std::uint32_t>(n);
    image.width = static_cast<std::uint32_t>(n);
    image.encoding = sensor_msgs::image_encodings::TYPE_32FC1;
    image.is_bigendian = 0;
    image.step = static_cast<std::uint32_t>(n * sizeof(float));
    std::vector<float> rows(cells);
    for (int r = 0; r < n; ++r) {
      for (int c = 0; c < n; ++c) rows[static_cast<std::size_t>(r) * n + c] = values[static_cast<std::size_t>(c) * n + r];
    }
    image.data.resize(cells * sizeof(float));
    std::memcpy(image.data.data(), rows.data(), image.data.size());
    m.images.push_back(std::move(image));
  }

  const auto elevation_at = std::find(map.names.begin(), map.names.end(), "elevation");
  m.cloud.header = header;
  for (const char* axis : {"x", "y", "z"}) add_field(m.cloud, axis);
  for (const std::string& name : map.names) add_field(m.cloud, name);
  m.cloud.point_step = static_cast<std::uint32_t>(m.cloud.fields.size() * sizeof(float));
  m.cloud.is_bigendian = false;
  m.cloud.is_dense = true;
  m.cloud.height = 1;

  m.marker.header = header;
  m.marker.ns = "stridemap";
  m.marker.id = 0;
  m.marker.type = visualization_msgs::Marker::CUBE_LIST;
  m.marker.action = visualization_msgs::Marker::ADD;
  m.marker.pose.orientation.w = 1.0;
  m.marker.scale.x = res;
  m.marker.scale.y = res;
  m.marker.scale.z = res;
  if (elevation_at == map.names.end()) {
    m.cloud.width = 0;
    m.cloud.row_step = 0;
    return m;  // the cloud and marker need the elevation layer
  }
  const std::vector<float>& elevation = map.values[static_cast<std::size_t>(elevation_at - map.names.begin())];
  float lo = std::numeric_limits<float>::infinity(), hi = -lo;
  for (const float z : elevation) {
    if (std::isfinite(z)) lo = std::min(lo, z), hi = std::max(hi, z);
  }
  std::vector<float> point(m.cloud.fields.size());
  for (int i = 0; i < n; ++i) {
    for (int j = 0; j < n; ++j) {
      const std::size_t k = static_cast<std::size_t>(i) * n + j;
      const float z = elevation[k];
      if (!std::isfinite(z)) continue;
      const double x = (static_cast<double>(map.min_cell_x + i) + 0.5) * res;
      const double y = (static_cast<double>(map.min_cell_y + j) + 0.5) * res;
      point[0] = static_cast<float>(x);
      point[1] = static_cast<float>(y);
      point[2] = z;
      for (std::size_t l = 0; l < map.values.size(); ++l) point[3 + l] = map.values[l][k];
      const auto* bytes = reinterpret_cast<const std::uint8_t*>(point.data());
      m.cloud.data.insert(m.cloud.data.end(), bytes, bytes + m.cloud.point_step);
      geometry_msgs::Point p;
      p.x = x;
      p.y = y;
      p.z = z - 0.5 * res;  // the cube's top face at the cell's elevation
      m.marker.points.push_back(p);
      m.marker.colors.push_back(height_colour(z, lo, hi));
    }
  }
  m.cloud.width = static_cast<std::uint32_t>(m.marker.points.size());
  m.cloud.row_step = m.cloud.width * m.cloud.point_step;
  return m;
}

std::int8_t occupancy_of_score(float score) {
  if (std::isnan(score)) return -1;
  return static_cast<std::int8_t>(std::lround(100.0f * (1.0f - std::clamp(score, 0.0f, 1.0f))));
}

nav_msgs::OccupancyGrid occupancy_grid(const MapLayers& map, std::size_t layer, const std::string& map_frame,
                                       const ros::Time& stamp) {
  nav_msgs::OccupancyGrid grid;
  grid.header.stamp = stamp;
  grid.header.frame_id = map_frame;
  const int n = map.cells_per_side;
  grid.info = map_meta_data(map, stamp);
  const std::vector<float>& values = map.values.at(layer);
  grid.data.resize(static_cast<std::size_t>(n) * static_cast<std::size_t>(n));
  // Row r of the grid is one y (j = r), as the images.
  for (int r = 0; r < n; ++r) {
    for (int c = 0; c < n; ++c) {
      grid.data[static_cast<std::size_t>(r) * n + c] = occupancy_of_score(values[static_cast<std::size_t>(c) * n + r]);
    }
  }
  return grid;
}

grid_map_msgs::GridMap grid_map_message(const MapLayers& map, const std::string& map_frame, const ros::Time& stamp) {
  grid_map_msgs::GridMap msg;
  const int n = map.cells_per_side;
  const double res = map.cell_size_m;
  msg.info.header.stamp = stamp;
  msg.info.header.frame_id = map_frame;
  msg.info.resolution = res;
  msg.info.length_x = n * res;
  msg.info.length_y = n * res;
  msg.info.pose.position.x = (static_cast<double>(map.min_cell_x) + 0.5 * n) * res;
  msg.info.pose.position.y = (static_cast<double>(map.min_cell_y) + 0.5 * n) * res;
  msg.info.pose.orientation.w = 1.0;
  msg.layers = map.names;
  if (std::find(map.names.begin(), map.names.end(), "elevation") != map.names.end()) msg.basic_layers = {"elevation"};
  // grid_map's circular buffer starts at (0, 0): nothing to unwrap.
  msg.outer_start_index = 0;
  msg.inner_start_index = 0;
  const std::size_t un = static_cast<std::size_t>(n);
  for (const std::vector<float>& values : map.values) {
    std_msgs::Float32MultiArray array;
    array.layout.dim.resize(2);
    array.layout.dim[0].label = "column_index";
    array.layout.dim[0].size = static_cast<std::uint32_t>(n);
    array.layout.dim[0].stride = static_cast<std::uint32_t>(un * un);
    array.layout.dim[1].label = "row_index";
    array.layout.dim[1].size = static_cast<std::uint32_t>(n);
    array.layout.dim[1].stride = static_cast<std::uint32_t>(n);
    array.layout.data_offset = 0;
    array.data.resize(un * un);
    // grid_map's (row, column) = (n-1-i, n-1-j) of MapLayers' (i, j); column-major.
    for (std::size_t col = 0; col < un; ++col) {
      for (std::size_t row = 0; row < un; ++row) {
        array.data[col * un + row] = values[(un - 1 - row) * un + (un - 1 - col)];
      }
    }
    msg.data.push_back(std::move(array));
  }
  return msg;
}

diagnostic_msgs::DiagnosticArray diagnostics(const MessageMapperStats& s, const std::string& last_drop,
                                             const std::string& node_name, const ros::Time& stamp,
                                             std::optional<double> last_mapped_stamp_s) {
  diagnostic_msgs::DiagnosticArray array;
  array.header.stamp = stamp;
  diagnostic_msgs::DiagnosticStatus status;
  status.name = node_name + ": mapping";
  status.hardware_id = "stridemap";
  const std::size_t dropped = s.dropped();
  status.level = dropped == 0 && (s.mapped > 0 || s.scans == 0) ? diagnostic_msgs::DiagnosticStatus::OK
                                                                 : diagnostic_msgs::DiagnosticStatus::WARN;
  if (dropped > 0) {
    status.message = std::to_string(dropped) + " scans dropped; last: " + last_drop;
  } else if (s.mapped == 0) {
    status.message = s.scans == 0 ? "no scan yet" : "no scan mapped yet: waiting for the first pose";
  } else {
    status.message = "every scan mapped";
    if (s.before_first_pose > 0) status.message += " since the first pose";
  }
  auto add = [&](const std::string& key, double value) {
    diagnostic_msgs::KeyValue kv;
    kv.key = key;
    kv.value = std::to_string(value);
    status.values.push_back(kv);
  };
  auto count = [&](const std::string& key, std::size_t value) {
    diagnostic_msgs::KeyValue kv;
    kv.key = key;
    kv.value = std::to_string(value);
    status.values.push_back(kv);
  };
  count("scans", s.scans);
  count("scans_mapped", s.mapped);
  count("scans_dropped", dropped);
  count("dropped_wrong_frame", s.wrong_frame);
  count("dropped_stamp_not_increasing", s.stamp_not_increasing);
  count("dropped_bad_geometry", s.bad_geometry);
  count("dropped_unreadable", s.unreadable);
  count("dropped_no_valid_beams", s.no_valid_beams);
  count("dropped_pose_timeout", s.pose_timeout);
  count("dropped_pose_unavailable", s.pose_unavailable);
  count("before_first_pose", s.before_first_pose);
  count("dropped_queue_full", s.queue_full);
  count("dropped_rejected_by_mapper", s.rejected_by_mapper);
  count("beams", s.beams);
  count("beams_not_finite", s.beams_not_finite);
  count("beams_out_of_range", s.beams_out_of_range);
  count("beams_low_intensity", s.beams_low_intensity);
  count("scans_with_nan_ranges", s.scans_with_bad_beams);
  count("poses", s.poses);
  count("poses_rejected", s.poses_rejected);
  add("latency_mean_ms", s.mapped ? 1000.0 * s.latency_sum_s / static_cast<double>(s.mapped) : 0.0);
  add("latency_max_ms", 1000.0 * s.latency_max_s);
  // Driver, transport, TF wait and mapping together (if the clocks agree).
  if (last_mapped_stamp_s) add("newest_mapped_age_ms", 1000.0 * (stamp.toSec() - *last_mapped_stamp_s));
  array.status.push_back(status);
  return array;
}

}  // namespace stridemap::ros_adapter
