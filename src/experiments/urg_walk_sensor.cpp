#include "stridemap/experiments/urg_walk_sensor.hpp"

#include <cmath>
#include <limits>

#include "stridemap/core/error.hpp"
#include "stridemap/core/sensor_transform.hpp"

namespace stridemap {
namespace {

std::unique_ptr<BeamModel> beam_model_for(const UrgWalkSensorOptions& o) {
  if (o.mixed_pixels) return std::make_unique<FootprintBeamModel>(o.footprint);
  return std::make_unique<SingleRayBeamModel>();
}

}  // namespace

UrgWalkSensor::UrgWalkSensor(const Scene& scene, const UrgWalkSensorOptions& options, const UpdateOptions& update,
                             std::uint64_t seed)
    : options_(options),
      update_(update),
      model_(options.urg, options.calibration),
      simulator_(scene, options.urg, options.sim, seed, beam_model_for(options)),
      filters_(options.filters, options.filter_options) {
  const int beams = options_.urg.beam_count();
  for (int i = 0; i < beams; ++i) {
    const double t = options_.urg.step_angle_rad(options_.urg.first_step + i);
    cos_beam_.push_back(std::cos(t));
    sin_beam_.push_back(std::sin(t));
  }
}

ScanStats UrgWalkSensor::integrate(const PlanarScan& scan, const TrunkPose& estimate, TerrainMapper& mapper) {
  const ScanStats stats = mapper.integrate(scan, estimate);
  points_.clear();
  if (!collect_ || stats.pose_rejected) return stats;
  const Eigen::Matrix3d rotation = sensor_to_map_rotation(estimate, options_.mount);
  const Eigen::Vector3d origin = sensor_origin_in_map(estimate, options_.mount);
  for (std::size_t i = 0; i < scan.size(); ++i) {
    const double r = scan.range_m[i];
    if (!std::isfinite(r) || r <= 0.0) continue;
    const double t = scan.angle_rad[i];
    ObservedPoint p;
    p.range_m = r;
    p.map_m = origin + r * (std::cos(t) * rotation.col(0) + std::sin(t) * rotation.col(1));
    const ElevationPartials partials =
        beam_elevation_partials(r, t, estimate.pitch_rad, estimate.roll_rad, options_.mount);
    p.height_uncertainty_m = elevation_error_bound_m(partials, scan.range_error_m[i], update_);
    points_.push_back(p);
  }
  return stats;
}

ScanStats UrgWalkSensor::measure(const TrunkPose& truth, const TrunkPose& estimate, double time_s,
                                 TerrainMapper& mapper) {
  simulator_.scan(truth, options_.mount, time_s, raw_);
  const UrgConversionStats converted = model_.to_planar_scan(raw_, scan_);
  sensor_totals_.valid += converted.valid;
  sensor_totals_.error_codes += converted.error_codes;
  sensor_totals_.beyond_max_range += converted.beyond_max_range;
  // With a one-scan delay the scan that comes out is the previous one, and
  // it belongs with the estimate taken when it was measured.
  const TrunkPose used = filters_.delay_scans() > 0 ? held_estimate_ : estimate;
  const bool had_previous = holding_ || filters_.delay_scans() == 0;
  held_estimate_ = estimate;
  holding_ = filters_.delay_scans() > 0;
  ScanStats stats;
  if (filters_.push(scan_, filtered_) && had_previous) stats = integrate(filtered_, used, mapper);
  else points_.clear();
  return stats;
}

ScanStats UrgWalkSensor::flush(TerrainMapper& mapper) {
  ScanStats stats;
  points_.clear();
  if (holding_ && filters_.flush(filtered_)) stats = integrate(filtered_, held_estimate_, mapper);
  holding_ = false;
  return stats;
}

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
