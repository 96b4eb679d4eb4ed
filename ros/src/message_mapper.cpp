#include "stridemap_ros/message_mapper_library.hpp"

#include <algorithm>
#include <cmath>
#include <numbers>
#include <utility>

#include "stridemap/core/error.hpp"
#include "stridemap/core/exported_map.hpp"
#include "stridemap/core/pose_track.hpp"
#include "stridemap/core/sensor_transform.hpp"

namespace stridemap::ros_adapter {
namespace {

bool finite(const Eigen::Isometry3d& t) { return t.matrix().allFinite(); }

MessageMapper::Impl::Waiting take_spare(MessageMapper::Impl& impl) {
  if (impl.spare.empty()) return {};
  MessageMapper::Impl::Waiting w = std::move(impl.spare.back());
  impl.spare.pop_back();
  return w;
}

}  // namespace

void MessageMapperOptions::validate() const {
  auto positive = [](double v, const char* name) {
    if (!(v > 0.0) || !std::isfinite(v)) throw InputError(std::string(name) + ": must be a positive number");
  };
  if (map_frame.empty()) throw InputError("map_frame: must not be empty");
  positive(range_error_m, "range_error_m");
  if (!(range_error_fraction >= 0.0) || !std::isfinite(range_error_fraction)) {
    throw InputError("range_error_fraction: must be a number >= 0");
  }
  if (!std::isfinite(min_intensity)) throw InputError("min_intensity: must be a number");
  if (!(pose_wait_s >= 0.0) || !std::isfinite(pose_wait_s)) throw InputError("pose_wait_s: must be a number >= 0");
  positive(max_pose_gap_s, "max_pose_gap_s");
  if (max_waiting == 0) throw InputError("max_waiting: must be at least 1");
}

TrunkPose trunk_pose_from_isometry(const Eigen::Isometry3d& trunk_in_map) {
  // R = Rz(yaw) Ry(pitch) Rx(roll), the library's order (core/sensor_transform).
  const Eigen::Matrix3d r = trunk_in_map.rotation();
  TrunkPose pose;
  pose.x_m = trunk_in_map.translation().x();
  pose.y_m = trunk_in_map.translation().y();
  pose.z_m = trunk_in_map.translation().z();
  pose.pitch_rad = std::asin(std::clamp(-r(2, 0), -1.0, 1.0));
  pose.yaw_rad = std::atan2(r(1, 0), r(0, 0));
  pose.roll_rad = std::atan2(r(2, 1), r(2, 2));
  return pose;
}

TrunkPose trunk_pose_from_sensor(const Eigen::Isometry3d& sensor_in_map, const SensorMount& mount) {
  Eigen::Isometry3d trunk = Eigen::Isometry3d::Identity();
  trunk.linear() = sensor_in_map.rotation() * mount_rotation(mount).transpose();
  const Eigen::Vector3d lever(mount.forward_offset_m, mount.lateral_offset_m, mount.height_m);
  trunk.translation() = sensor_in_map.translation() - trunk.linear() * lever;
  return trunk_pose_from_isometry(trunk);
}

struct TopicPoseSource::Track {
  PoseTrack track;
};

TopicPoseSource::TopicPoseSource(double max_gap_s) : track_(std::make_unique<Track>(Track{PoseTrack(max_gap_s)})) {}
TopicPoseSource::~TopicPoseSource() = default;

bool TopicPoseSource::add(double stamp_s, const Eigen::Isometry3d& trunk_in_map) {
  PoseTrack& track = track_->track;
  if (!std::isfinite(stamp_s) || !finite(trunk_in_map)) return false;
  if (!track.empty() && !(stamp_s > track.last_time_s())) return false;
  track.append({stamp_s, trunk_pose_from_isometry(trunk_in_map)});
  return true;
}

void TopicPoseSource::drop_before(double stamp_s) { track_->track.drop_before(stamp_s); }

PipelineOptions message_pipeline_options(const MapperConfig& config) {
  PipelineOptions p;
  p.sensor = SensorKind::points;
  p.mapper = config.mapper;
  p.map_filter = {MapFilter::fill, config.fill, {}};
  p.mount = config.mount;
  p.height_fusion = config.height_fusion;
  return p;
}

MessageMapper::MessageMapper(const MessageMapperOptions& options, PoseSource& poses)
    : options_(options), poses_(poses), impl_(std::make_unique<Impl>()) {
  options_.validate();
  if (!options_.config_path.empty()) impl_->config = load_mapper_config(options_.config_path);
  make_pipeline();
  sensor_frame_ = options_.sensor_frame;
}

void MessageMapper::make_pipeline() {
  PipelineOptions options = message_pipeline_options(impl_->config);
  options.height_fusion.enabled = options.height_fusion.enabled || options_.fused_heights;
  impl_->pipeline = std::make_unique<MappingPipeline>(options);
}

MessageMapper::~MessageMapper() = default;

std::size_t MessageMapper::waiting() const { return impl_->waiting.size(); }

MapLayers MessageMapper::layers(const std::vector<std::string>& names) const {
  const ExportedMap map = export_map(impl_->pipeline->filtered_map(), names);
  MapLayers out;
  out.min_cell_x = map.min_cell.x;
  out.min_cell_y = map.min_cell.y;
  out.cell_size_m = map.cell_size_m;
  out.cells_per_side = map.cells_per_side;
  const Eigen::Index n = map.cells_per_side;
  for (const ExportedLayer& layer : map.layers) {
    out.names.push_back(layer.spec.name);
    std::vector<float>& values = out.values.emplace_back(static_cast<std::size_t>(n * n));
    for (Eigen::Index i = 0; i < n; ++i) {
      for (Eigen::Index j = 0; j < n; ++j) values[static_cast<std::size_t>(i * n + j)] = layer.value(i, j);
    }
  }
  return out;
}

double MessageMapper::range_error(double range_m) const {
  return std::max(options_.range_error_m, options_.range_error_fraction * range_m);
}

void MessageMapper::drop(std::size_t& counter, const std::string& why) {
  ++counter;
  last_drop_ = why;
}

bool MessageMapper::accept_header(double stamp_s, const std::string& frame_id) {
  ++stats_.scans;
  if (sensor_frame_.empty()) sensor_frame_ = frame_id;
  if (frame_id != sensor_frame_) {
    drop(stats_.wrong_frame, "frame '" + frame_id + "' is not the sensor frame '" + sensor_frame_ + "'");
    return false;
  }
  if (!std::isfinite(stamp_s) || (last_stamp_ && !(stamp_s > *last_stamp_))) {
    drop(stats_.stamp_not_increasing, "stamp " + std::to_string(stamp_s) + " is not later than the previous scan's");
    return false;
  }
  last_stamp_ = stamp_s;
  return true;
}

void MessageMapper::make_room() {
  while (impl_->waiting.size() >= options_.max_waiting) {
    drop(stats_.queue_full, "more than " + std::to_string(options_.max_waiting) + " scans waiting for their pose");
    impl_->spare.push_back(std::move(impl_->waiting.front()));
    impl_->waiting.pop_front();
  }
}

void MessageMapper::add(const LaserScanData& scan, double arrival_s) {
  if (!accept_header(scan.stamp_s, scan.frame_id)) return;
  // Intensities matter only when they filter beams; a driver that sends a
  // wrong number of them loses its scans only then.
  const bool use_intensities = options_.min_intensity > 0.0 && scan.intensity_count > 0;
  std::string bad;
  if (!std::isfinite(scan.angle_min_rad) || !std::isfinite(scan.angle_increment_rad)) {
    bad = "angle_min or angle_increment not finite";
  } else if (scan.angle_increment_rad == 0.0 && scan.range_count > 1) {
    bad = "angle_increment 0 with " + std::to_string(scan.range_count) + " ranges";
  } else if (std::abs(scan.angle_min_rad) > 2.0 * std::numbers::pi ||
             std::abs(scan.angle_increment_rad) * static_cast<double>(scan.range_count > 0 ? scan.range_count - 1 : 0) >
                 2.0 * std::numbers::pi + 1e-6) {
    // Finite but no scanner's: the beams would land anywhere around the sensor.
    bad = "angle_min " + std::to_string(scan.angle_min_rad) + " rad and angle_increment " +
          std::to_string(scan.angle_increment_rad) + " rad over " + std::to_string(scan.range_count) +
          " ranges are not angles of one turn (|angle_min| and the span at most 2 pi)";
  } else if (!std::isfinite(scan.range_min_m) || !std::isfinite(scan.range_max_m) ||
             !(scan.range_max_m > scan.range_min_m) || !(scan.range_max_m > 0.0)) {
    bad = "range limits [" + std::to_string(scan.range_min_m) + ", " + std::to_string(scan.range_max_m) +
          "] m make no sense";
  } else if (use_intensities && scan.intensity_count != scan.range_count) {
    bad = std::to_string(scan.intensity_count) + " intensities for " + std::to_string(scan.range_count) +
          " ranges (min_intensity needs one per range)";
  } else if (scan.range_count > 0 && scan.ranges_m == nullptr) {
    bad = "no range data";
  }
  if (!bad.empty()) {
    drop(stats_.bad_geometry, "scan at " + std::to_string(scan.stamp_s) + ": " + bad);
    last_bad_scan_ = last_drop_;
    return;
  }
  Impl::Waiting w = take_spare(*impl_);
  w.planar = true;
  w.time_s = scan.stamp_s;
  w.scan.time_s = scan.stamp_s;
  w.scan.angle_rad.clear();
  w.scan.range_m.clear();
  w.scan.range_error_m.clear();
  w.frame_id = scan.frame_id;
  w.arrival_s = arrival_s;
  bool bad_beam = false;
  for (std::size_t k = 0; k < scan.range_count; ++k) {
    ++stats_.beams;
    const double r = scan.ranges_m[k];
    if (std::isnan(r)) {
      ++stats_.beams_not_finite;
      bad_beam = true;
      continue;
    }
    // REP-117: +-Inf are readings (nothing within range), not errors. A
    // range of 0 is how many drivers say "no echo", even with range_min 0:
    // as a point it would sit at the sensor itself.
    if (std::isinf(r) || r < scan.range_min_m || r > scan.range_max_m || !(r > 0.0)) {
      ++stats_.beams_out_of_range;
      continue;
    }
    if (use_intensities && !(scan.intensities[k] >= options_.min_intensity)) {
      ++stats_.beams_low_intensity;
      continue;
    }
    const double a = scan.angle_min_rad + static_cast<double>(k) * scan.angle_increment_rad;
    w.scan.angle_rad.push_back(a);
    w.scan.range_m.push_back(r);
    w.scan.range_error_m.push_back(range_error(r));
  }
  if (bad_beam) ++stats_.scans_with_bad_beams;
  if (w.scan.range_m.empty()) {
    drop(stats_.no_valid_beams, "no beam with a usable range");
    impl_->spare.push_back(std::move(w));
    return;
  }
  make_room();
  impl_->waiting.push_back(std::move(w));
}

void MessageMapper::add_unreadable(const std::string& frame_id, const std::string& why) {
  ++stats_.scans;
  drop(stats_.unreadable, "cloud in '" + frame_id + "': " + why);
}

void MessageMapper::add(const PointCloudData& cloud, double arrival_s) {
  if (!accept_header(cloud.stamp_s, cloud.frame_id)) return;
  const bool sigma_given = !cloud.height_sigma_m.empty();
  if (sigma_given && cloud.height_sigma_m.size() != cloud.points_m.size()) {
    drop(stats_.bad_geometry, "a sigma field that is not one per point");
    return;
  }
  Impl::Waiting w = take_spare(*impl_);
  w.planar = false;
  w.time_s = cloud.stamp_s;
  w.frame.points_m.clear();
  w.frame.height_sigma_m.clear();
  w.frame.time_s = cloud.stamp_s;
  w.frame_id = cloud.frame_id;
  w.arrival_s = arrival_s;
  bool bad_beam = false;
  for (std::size_t k = 0; k < cloud.points_m.size(); ++k) {
    ++stats_.beams;
    const Eigen::Vector3d& p = cloud.points_m[k];
    const double sigma = sigma_given ? cloud.height_sigma_m[k] : range_error(p.norm()) / 3.0;
    if (!p.allFinite() || !std::isfinite(sigma) || sigma < 0.0) {
      ++stats_.beams_not_finite;
      bad_beam = true;
      continue;
    }
    w.frame.points_m.push_back(p);
    w.frame.height_sigma_m.push_back(sigma);
  }
  if (bad_beam) ++stats_.scans_with_bad_beams;
  if (w.frame.points_m.empty()) {
    drop(stats_.no_valid_beams, "no point with finite coordinates");
    impl_->spare.push_back(std::move(w));
    return;
  }
  make_room();
  impl_->waiting.push_back(std::move(w));
}

std::size_t MessageMapper::process(double now_s, bool end_of_stream) {
  std::size_t mapped = 0;
  auto* topic = dynamic_cast<TopicPoseSource*>(&poses_);
  const SensorMount& mount = impl_->config.mount;
  while (!impl_->waiting.empty()) {
    Impl::Waiting& w = impl_->waiting.front();
    const bool may_wait = !end_of_stream && now_s - w.arrival_s <= options_.pose_wait_s;
    TrunkPose pose;
    std::string why;
    PoseAnswer answer = PoseAnswer::never;
    bool older_than_first_pose = false;
    if (topic) {
      switch (topic->track_->track.interpolate(w.time_s, pose)) {
        case PoseLookup::ok: answer = PoseAnswer::ok; break;
        case PoseLookup::empty:
        case PoseLookup::after_last: answer = PoseAnswer::not_yet; break;
        case PoseLookup::before_first:
          answer = PoseAnswer::never;
          older_than_first_pose = true;
          break;
        case PoseLookup::gap_too_large: answer = PoseAnswer::never; break;
      }
    } else {
      Eigen::Isometry3d sensor;
      answer = poses_.sensor_in_map(w.frame_id, w.time_s, sensor, nullptr);
      // The words only for a scan that will not be mapped: asked again.
      if (answer == PoseAnswer::never || (answer == PoseAnswer::not_yet && !may_wait)) {
        answer = poses_.sensor_in_map(w.frame_id, w.time_s, sensor, &why);
      }
      older_than_first_pose = answer == PoseAnswer::never && why.find("into the past") != std::string::npos;
      if (answer == PoseAnswer::ok) {
        if (!sensor.matrix().allFinite()) {
          answer = PoseAnswer::never;
          why = "the transform is not finite";
        } else {
          pose = trunk_pose_from_sensor(sensor, mount);
        }
      }
    }
    if (answer == PoseAnswer::not_yet && may_wait) break;
    // Put into words for a drop only: a scan mapped or waiting costs no string.
    if (topic && answer != PoseAnswer::ok) why = "the pose topic has no pose at that time";
    if (answer == PoseAnswer::not_yet) {
      drop(stats_.pose_timeout, "no pose for the scan at " + std::to_string(w.time_s) + " within " +
                                    std::to_string(options_.pose_wait_s) + " s: " + why);
    } else if (answer == PoseAnswer::never && older_than_first_pose && stats_.mapped == 0) {
      ++stats_.before_first_pose;
    } else if (answer == PoseAnswer::never) {
      drop(stats_.pose_unavailable, "no pose for the scan at " + std::to_string(w.time_s) + ": " + why);
    } else {
      // A planar scan takes the mapper's own scan path (eq. 6, as the URG's
      // scans do), through the pipeline so that its foothold layers follow.
      const ScanStats stats = w.planar ? impl_->pipeline->add_planar(w.scan, pose)
                                       : impl_->pipeline->add(w.frame, pose).stats;
      if (stats.pose_rejected || stats.time_rejected) {
        drop(stats_.rejected_by_mapper, "the mapper refused the scan's pose or time");
      } else {
        ++stats_.mapped;
        ++mapped;
        const double latency = std::max(0.0, now_s - w.arrival_s);
        stats_.latency_sum_s += latency;
        stats_.latency_max_s = std::max(stats_.latency_max_s, latency);
        last_mapped_stamp_ = w.time_s;
        if (topic) topic->drop_before(w.time_s);
      }
    }
    impl_->spare.push_back(std::move(w));
    impl_->waiting.pop_front();
  }
  return mapped;
}

void MessageMapper::clear() {
  make_pipeline();
  for (; !impl_->waiting.empty(); impl_->waiting.pop_front()) impl_->spare.push_back(std::move(impl_->waiting.front()));
  last_stamp_.reset();
  last_mapped_stamp_.reset();
}

}  // namespace stridemap::ros_adapter
