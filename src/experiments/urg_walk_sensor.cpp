#include "stridemap/experiments/urg_walk_sensor.hpp"

#include <cmath>
#include <limits>
#include <stdexcept>
#include <string>

#include "stridemap/core/error.hpp"
#include "stridemap/core/sensor_transform.hpp"

namespace stridemap {
namespace {

std::unique_ptr<BeamModel> beam_model_for(const UrgWalkSensorOptions& o) {
  if (o.mixed_pixels) return std::make_unique<FootprintBeamModel>(o.footprint);
  return std::make_unique<SingleRayBeamModel>();
}

PipelineOptions urg_pipeline_options(const UrgWalkSensorOptions& o) {
  PipelineOptions p;
  p.sensor = SensorKind::urg;
  p.urg = o.urg;
  p.calibration = o.calibration;
  p.filters = o.filters;
  p.filter_options = o.filter_options;
  p.mount = o.mount;
  p.visibility = o.visibility;
  return p;
}

// Bit for bit: a replay must see exactly the trajectory that was simulated.
bool same_pose(const TrunkPose& a, const TrunkPose& b) {
  return a.x_m == b.x_m && a.y_m == b.y_m && a.yaw_rad == b.yaw_rad && a.pitch_rad == b.pitch_rad &&
         a.roll_rad == b.roll_rad && a.reference_elevation_m == b.reference_elevation_m &&
         a.height_change_m == b.height_change_m && a.z_m == b.z_m;
}

}  // namespace

UrgWalkSensor::UrgWalkSensor(const Scene& scene, const UrgWalkSensorOptions& options, const UpdateOptions&,
                             std::uint64_t seed)
    : options_(options),
      simulator_(scene, options.urg, options.sim, seed, beam_model_for(options)),
      integrator_(urg_pipeline_options(options)) {
  const int beams = options_.urg.beam_count();
  for (int i = 0; i < beams; ++i) {
    const double t = options_.urg.step_angle_rad(options_.urg.first_step + i);
    cos_beam_.push_back(std::cos(t));
    sin_beam_.push_back(std::sin(t));
  }
}

ScanStats UrgWalkSensor::measure(const TrunkPose& truth, const TrunkPose& estimate, double time_s,
                                 TerrainMapper& mapper) {
  if (replayed_) {
    const std::size_t k = next_replayed_++;
    if (k >= replayed_->scans.size() || !same_pose(replayed_->scans[k].truth, truth) ||
        replayed_->scans[k].time_s != time_s) {
      throw std::logic_error("urg walk sensor: replay of scan " + std::to_string(k) +
                             " asked for a true pose or time the recording (" +
                             std::to_string(replayed_->scans.size()) + " scans) does not hold");
    }
    return integrator_.push(replayed_->scans[k].raw, estimate, mapper).stats;
  }
  simulator_.scan(truth, options_.mount, time_s, raw_);
  if (recording_) recording_->scans.push_back({truth, time_s, raw_});
  return integrator_.push(raw_, estimate, mapper).stats;
}

bool UrgWalkSensor::start_recording() {
  recording_ = std::make_shared<UrgWalkRecording>();
  return true;
}

bool UrgWalkSensor::replay(std::shared_ptr<const WalkRecording> recording) {
  auto urg = std::dynamic_pointer_cast<const UrgWalkRecording>(recording);
  if (!urg) return false;
  replayed_ = std::move(urg);
  next_replayed_ = 0;
  return true;
}

ScanStats UrgWalkSensor::flush(TerrainMapper& mapper) { return integrator_.flush(mapper).stats; }

void UrgWalkSensor::floor_trace(const TrunkPose& pose, double floor_elevation_m, double max_range_m,
                                std::vector<Eigen::Vector2d>& out) const {
  out.assign(cos_beam_.size(), Eigen::Vector2d::Constant(std::numeric_limits<double>::quiet_NaN()));
  const Eigen::Matrix3d rotation = sensor_to_map_rotation(pose, options_.mount);
  const Eigen::Vector3d origin = sensor_origin_in_map(pose, options_.mount);
  for (std::size_t i = 0; i < cos_beam_.size(); ++i) {
    const Eigen::Vector3d dir = cos_beam_[i] * rotation.col(0) + sin_beam_[i] * rotation.col(1);
    if (dir.z() >= -1e-9) continue;
    const double range = (floor_elevation_m - origin.z()) / dir.z();
    if (range <= 0.0 || range > max_range_m) continue;
    out[i] = (origin + range * dir).head<2>();
  }
}

double urg_share_in_range_interval(const SensorMount& mount, const UrgParameters& urg, const RangeIntervalOptions& o) {
  const Eigen::Matrix3d rotation = sensor_to_map_rotation(TrunkPose{}, mount);
  const Eigen::Vector3d origin = sensor_origin_in_map(TrunkPose{}, mount);
  std::size_t inside = 0, total = 0;
  for (int level = 0; level < o.levels; ++level) {
    const double h = o.levels == 1 ? o.lowest_m : o.lowest_m + (o.highest_m - o.lowest_m) * level / (o.levels - 1);
    for (int i = 0; i < urg.beam_count(); ++i) {
      const double t = urg.step_angle_rad(urg.first_step + i);
      const Eigen::Vector3d dir = std::cos(t) * rotation.col(0) + std::sin(t) * rotation.col(1);
      if (dir.z() >= -1e-9) continue;
      const double range = (h - origin.z()) / dir.z();
      if (range <= 0.0 || range > urg.max_range_m) continue;
      const Eigen::Vector3d p = origin + range * dir;
      if (p.x() <= origin.x() || std::abs(p.y()) > o.corridor_half_width_m) continue;
      ++total;
      if (range >= o.min_range_m && range <= o.max_range_m) ++inside;
    }
  }
  return total ? static_cast<double>(inside) / static_cast<double>(total) : 0.0;
}

}  // namespace stridemap
