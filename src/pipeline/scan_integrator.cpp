#include "stridemap/pipeline/scan_integrator.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstring>
#include <limits>
#include <string>
#include <utility>

#include "stridemap/core/error.hpp"
#include "stridemap/core/planar_scan_points.hpp"
#include "stridemap/core/sensor_transform.hpp"
#include "stridemap/preprocess/scan_checks.hpp"

namespace stridemap {
namespace {

constexpr std::array<std::pair<std::string_view, SensorKind>, 4> kSensorNames{{
    {"urg", SensorKind::urg},
    {"structured-light", SensorKind::structured_light},
    {"points", SensorKind::points},
    {"custom", SensorKind::custom},
}};

// Keeps each integrated point when the caller asked for them.
struct CollectingSink {
  std::vector<IntegratedPoint>& out;
  void operator()(std::size_t, const Eigen::Vector3d& map_m, const SensorPoint& p) const {
    out.push_back({map_m, p.range_m, p.height_error_m});
  }
};

}  // namespace

std::string_view sensor_kind_name(SensorKind kind) {
  for (const auto& [name, value] : kSensorNames) {
    if (value == kind) return name;
  }
  return "unknown";
}

SensorKind parse_sensor_kind(std::string_view name) {
  for (const auto& [known, value] : kSensorNames) {
    if (known == name) return value;
  }
  throw InputError("'" + std::string(name) + "' is not a sensor; use urg, structured-light, points or custom");
}

PipelineStats& PipelineStats::operator+=(const PipelineStats& o) {
  scans += o.scans;
  integrated += o.integrated;
  before_first_pose += o.before_first_pose;
  after_last_pose += o.after_last_pose;
  pose_gap += o.pose_gap;
  rejected += o.rejected;
  cells_contradicted += o.cells_contradicted;
  cells_cleared += o.cells_cleared;
  beams += o.beams;
  stripe += o.stripe;
  points += o.points;
  return *this;
}

ScanIntegrator::ScanIntegrator(const PipelineOptions& options)
    : options_(options),
      urg_(options.urg, options.calibration),
      points_sensor_(options.points),
      filters_(options.filters, options.filter_options) {
  if (options_.sensor != SensorKind::urg && !options_.filters.empty()) {
    throw InputError("pipeline: the scan filters (" + scan_filter_list_name(options_.filters) +
                     ") work on planar scans; the " + std::string(sensor_kind_name(options_.sensor)) +
                     " sensor takes none");
  }
  if (options_.sensor == SensorKind::structured_light) structured_light_.emplace(options_.structured_light);
  validate_visibility_options(options_.visibility);
}

void ScanIntegrator::require(SensorKind kind) const {
  if (options_.sensor != kind) {
    throw InputError("pipeline: configured for the " + std::string(sensor_kind_name(options_.sensor)) +
                     " sensor, given " + std::string(sensor_kind_name(kind)) + " data");
  }
}

ScanOutcome ScanIntegrator::push(const UrgRawScan& raw, const TrunkPose& pose, TerrainMapper& mapper,
                                 std::span<const std::uint8_t> beam_tags) {
  require(SensorKind::urg);
  points_.clear();
  if (packed_route(beam_tags)) return push_packed(raw, pose, mapper, beam_tags);
  try {
    stats_.beams += urg_.to_planar_scan(raw, scan_);
  } catch (const InputError&) {
    ++stats_.rejected;  // steps the sensor's parameters do not have: not this sensor's scan
    return {};
  }
  if (options_.drop_beams_tagged) {
    for (std::size_t i = 0; i < beam_tags.size() && i < scan_.range_m.size(); ++i) {
      if (beam_tags[i] == *options_.drop_beams_tagged) scan_.range_m[i] = std::numeric_limits<double>::quiet_NaN();
    }
  }
  bool out = false;
  try {
    out = filters_.push(scan_, pose, beam_tags, filtered_);
  } catch (const InputError&) {
    ++stats_.rejected;  // e.g. a scan of another length after a reconnection: the sequence starts anew
    return {};
  }
  return out ? integrate_planar(mapper) : ScanOutcome{};
}

// The planar route is kept where something reads the PlanarScan: a filter,
// the reference runs' dropped beams.
bool ScanIntegrator::packed_route(std::span<const std::uint8_t> beam_tags) const {
  return filters_.chain().stage_count() == 0 && !(options_.drop_beams_tagged && !beam_tags.empty());
}

ScanOutcome ScanIntegrator::push_packed(const UrgRawScan& raw, const TrunkPose& pose, TerrainMapper& mapper,
                                        std::span<const std::uint8_t> beam_tags) {
  try {
    stats_.beams += urg_.to_beams(raw, beams_);
  } catch (const InputError&) {
    ++stats_.rejected;  // as the planar route: not this sensor's scan
    return {};
  }
  filters_.pass(pose, beam_tags);
  last_packed_ = true;
  last_raw_converted_ = false;
  last_raw_.time_s = raw.time_s;
  last_raw_.first_step = raw.first_step;
  last_raw_.cluster = raw.cluster;
  last_raw_.values_mm.assign(raw.values_mm.begin(), raw.values_mm.end());  // in place once grown
  // An empty chain removes nothing; observers still get one flag a beam.
  if (no_removals_.size() != raw.values_mm.size()) no_removals_.assign(raw.values_mm.size(), 0);
  ScanOutcome outcome;
  outcome.integrated = true;
  if (collect_) mapper.keep_beam_hits(true);
  outcome.stats = mapper.integrate(beams_, pose);
  ++stats_.integrated;
  if (!outcome.stats.pose_rejected && !outcome.stats.time_rejected) {
    if (collect_ && !collect_hits(mapper)) collect_beams(pose, mapper);
    clear_visible(beams_, pose, mapper);
  }
  report(filters_.output(), raw.time_s, outcome.stats, no_removals_);
  return outcome;
}

// The points of the mapper's packed pass, which keeps each valid beam's
// hit (keep_beam_hits): the doubles the per-point way's sink would be
// handed, formed once. False where it took its per-point way (a window
// beyond 2^30 cells) and kept none.
bool ScanIntegrator::collect_hits(const TerrainMapper& mapper) {
  const TerrainMapper::BeamHits* hits = mapper.last_beam_hits();
  if (hits == nullptr) return false;
  points_.resize(hits->count);  // emptied before the scan; grows once
  IntegratedPoint* out = points_.data();
  for (std::size_t k = 0; k < hits->count; ++k) {
    out[k].map_m = Eigen::Vector3d(hits->x_m[k], hits->y_m[k], hits->z_m[k]);
    out[k].range_m = hits->range_m[k];
    out[k].height_uncertainty_m = hits->height_error_m[k];
  }
  return true;
}

// The packed beams' points where the mapper kept no hits, by the formula
// its per-point way uses.
void ScanIntegrator::collect_beams(const TrunkPose& pose, const TerrainMapper& mapper) {
  const PlanarBeamGeometry geometry(pose, mapper.mount());
  const UpdateOptions& update = mapper.options().update;
  const Eigen::Vector3d origin = sensor_origin_in_map(pose, mapper.mount());
  for (std::size_t k = 0; k < beams_.count; ++k) {
    const double r = beams_.range_m[k], c = beams_.cos_angle[k], s = beams_.sin_angle[k];
    points_.push_back({origin + geometry.offset(r, c, s), r,
                       geometry.height_error(r, beams_.range_error_m[k], c, s, update)});
  }
}

// A planar scan's points where the mapper kept no hits: its sink's, from
// the same source.
void ScanIntegrator::collect_scan(const PlanarScan& scan, const TrunkPose& pose, const TerrainMapper& mapper) {
  const std::size_t n = scan.size();
  if (scan_cos_.size() < n) {
    scan_cos_.resize(n);
    scan_sin_.resize(n);
  }
  for (std::size_t i = 0; i < n; ++i) {
    scan_cos_[i] = std::cos(scan.angle_rad[i]);
    scan_sin_[i] = std::sin(scan.angle_rad[i]);
  }
  const PlanarScanPoints source(scan, scan_cos_.data(), scan_sin_.data(), pose, mapper.mount(),
                                mapper.options().update);
  const Eigen::Vector3d origin = sensor_origin_in_map(pose, mapper.mount());
  SensorPoint p;
  for (std::size_t i = 0; i < n; ++i) {
    if (source.point(i, p) == PointStatus::ok) points_.push_back({origin + p.offset_m, p.range_m, p.height_error_m});
  }
}

// The mapper's packed pass for a planar scan, its points collected when asked.
ScanStats ScanIntegrator::integrate_collecting(const PlanarScan& scan, const TrunkPose& pose, TerrainMapper& mapper) {
  if (collect_) mapper.keep_beam_hits(true);
  const ScanStats stats = mapper.integrate(scan, pose);
  if (collect_ && !stats.pose_rejected && !stats.time_rejected && !collect_hits(mapper)) {
    collect_scan(scan, pose, mapper);
  }
  return stats;
}

const PlanarScan& ScanIntegrator::last_scan() const {
  if (!last_packed_) return filtered_;
  if (!last_raw_converted_) {
    // What the empty chain would have handed out: every unusable range NaN.
    urg_.to_planar_scan(last_raw_, unfiltered_);
    prepare_scan_for_filter(unfiltered_, normalize_mask_, "scan filter chain");
    last_raw_converted_ = true;
  }
  return unfiltered_;
}

ScanOutcome ScanIntegrator::flush(TerrainMapper& mapper) {
  points_.clear();
  return filters_.flush(filtered_) ? integrate_planar(mapper) : ScanOutcome{};
}

ScanOutcome ScanIntegrator::integrate_planar(TerrainMapper& mapper) {
  const ScanPayload& payload = filters_.output();
  last_packed_ = false;
  ScanOutcome outcome;
  outcome.integrated = true;
  outcome.stats = integrate_collecting(filtered_, payload.pose, mapper);
  ++stats_.integrated;
  if (!outcome.stats.pose_rejected && !outcome.stats.time_rejected) clear_visible(filtered_, payload.pose, mapper);
  report(payload, filtered_.time_s, outcome.stats, filters_.chain().removed_by_any());
  return outcome;
}

ScanOutcome ScanIntegrator::push_planar(const PlanarScan& scan, const TrunkPose& pose, TerrainMapper& mapper) {
  points_.clear();
  batch_payload_.pose = pose;
  batch_payload_.sequence = pushed_++;
  ScanOutcome outcome;
  outcome.integrated = true;
  outcome.stats = integrate_collecting(scan, pose, mapper);
  ++stats_.integrated;
  if (!outcome.stats.pose_rejected && !outcome.stats.time_rejected) clear_visible(scan, pose, mapper);
  // No filter ran: observers get one flag a beam, none set (grown once).
  if (no_removals_.size() != scan.range_m.size()) no_removals_.assign(scan.range_m.size(), 0);
  report(batch_payload_, scan.time_s, outcome.stats, no_removals_);
  return outcome;
}

ScanOutcome ScanIntegrator::push(std::span<const StripePixel> pixels, std::optional<double> time_s,
                                 const TrunkPose& pose, TerrainMapper& mapper) {
  require(SensorKind::structured_light);
  structured_light_->set_frame(pixels);
  structured_light_->to_points(pose, mapper.mount(), mapper.options().update, batch_);
  stats_.stripe += structured_light_->last_stats();
  return integrate_batch(time_s, pose, mapper);
}

ScanOutcome ScanIntegrator::push(std::span<const Eigen::Vector3d> points_m, std::span<const double> height_sigma_m,
                                 std::optional<double> time_s, const TrunkPose& pose, TerrainMapper& mapper) {
  require(SensorKind::points);
  points_sensor_.set_frame(time_s.value_or(0.0), points_m, height_sigma_m);
  points_sensor_.to_points(pose, mapper.mount(), mapper.options().update, batch_);
  stats_.points += points_sensor_.last_stats();
  return integrate_batch(time_s, pose, mapper);
}

ScanOutcome ScanIntegrator::push(SensorModel& model, std::optional<double> time_s, const TrunkPose& pose,
                                 TerrainMapper& mapper) {
  require(SensorKind::custom);
  model.to_points(pose, mapper.mount(), mapper.options().update, batch_);
  return integrate_batch(time_s, pose, mapper);
}

ScanOutcome ScanIntegrator::integrate_batch(std::optional<double> time_s, const TrunkPose& pose,
                                            TerrainMapper& mapper) {
  points_.clear();
  batch_payload_.pose = pose;
  batch_payload_.sequence = pushed_++;
  ScanOutcome outcome;
  outcome.integrated = true;
  outcome.stats = collect_ ? mapper.integrate_scan(batch_, pose, time_s, CollectingSink{points_})
                           : mapper.integrate_scan(batch_, pose, time_s);
  ++stats_.integrated;
  if (!outcome.stats.pose_rejected && !outcome.stats.time_rejected) clear_visible_batch(pose, mapper);
  report(batch_payload_, time_s, outcome.stats, {});
  return outcome;
}

VisibilityClearing& ScanIntegrator::visibility_for(TerrainMapper& mapper) {
  // Remade only for a mapper with another window size (a caller's second
  // mapper); a steady stream allocates nothing here.
  const ElevationMap& map = std::as_const(mapper).map();
  const std::size_t cells = static_cast<std::size_t>(map.cells_per_side()) * static_cast<std::size_t>(map.cells_per_side());
  if (!visibility_ || visibility_->window_cells() != cells) visibility_.emplace(map, options_.visibility);
  visibility_->begin_scan(std::as_const(mapper));
  return *visibility_;
}

void ScanIntegrator::finish_visibility(TerrainMapper& mapper) {
  mapper.note_changed_cells(visibility_->changed());
  stats_.cells_contradicted += visibility_->stats().cells_contradicted;
  stats_.cells_cleared += visibility_->stats().cells_cleared;
}

// The beams the mapper's packed pass formed for this scan, when it formed
// them: the same hits and bounds as the loops below form (its error bound
// may be +0 where theirs is -0, which no sum or comparison of the walk
// tells apart), so the scan's geometry is not formed twice. The scan is
// the one integrated last by contract; its time, size and pose guard
// against a caller's slip.
bool ScanIntegrator::clear_formed(double time_s, std::size_t beams, const TrunkPose& pose, TerrainMapper& mapper) {
  mapper.keep_beam_hits(true);  // from the next scan on
  const TerrainMapper::BeamHits* hits = std::as_const(mapper).last_beam_hits();
  if (hits == nullptr || hits->beams != beams || !(hits->time_s == time_s) || hits->yaw_rad != pose.yaw_rad ||
      hits->pitch_rad != pose.pitch_rad || hits->roll_rad != pose.roll_rad ||
      hits->origin_m != sensor_origin_in_map(pose, mapper.mount())) {
    return false;
  }
  VisibilityClearing& clearing = visibility_for(mapper);
  ElevationMap& map = mapper.map_without_raising();  // the clean-up only lowers and clears
  clearing.trace_fan(map, {hits->origin_m, hits->count, hits->x_m, hits->y_m, hits->z_m, hits->height_error_m,
                           hits->range_error_m});
  finish_visibility(mapper);
  return true;
}

void ScanIntegrator::clear_visible(const PlanarScan& scan, const TrunkPose& pose, TerrainMapper& mapper) {
  if (!options_.visibility.enabled || clear_formed(scan.time_s, scan.size(), pose, mapper)) return;
  VisibilityClearing& clearing = visibility_for(mapper);
  // A sensor's beam angles rarely change: their sines and cosines are kept,
  // compared bit for bit (a -0 for a 0 is a new angle: its sine differs).
  if (scan.angle_rad.size() != visibility_angles_.size() ||
      (!scan.angle_rad.empty() &&
       std::memcmp(scan.angle_rad.data(), visibility_angles_.data(), scan.angle_rad.size() * sizeof(double)) != 0)) {
    visibility_angles_ = scan.angle_rad;
    visibility_cos_.resize(scan.angle_rad.size());
    visibility_sin_.resize(scan.angle_rad.size());
    for (std::size_t i = 0; i < scan.angle_rad.size(); ++i) {
      visibility_cos_[i] = std::cos(scan.angle_rad[i]);
      visibility_sin_[i] = std::sin(scan.angle_rad[i]);
    }
  }
  const PlanarBeamGeometry geometry(pose, mapper.mount());
  const UpdateOptions& update = mapper.options().update;
  ElevationMap& map = mapper.map_without_raising();  // the clean-up only lowers and clears
  VisibilityBeam beam;
  beam.origin_m = sensor_origin_in_map(pose, mapper.mount());
  const std::size_t n = std::min({scan.range_m.size(), scan.range_error_m.size(), visibility_cos_.size()});
  for (std::size_t i = 0; i < n; ++i) {
    const double r = scan.range_m[i], dr = scan.range_error_m[i];
    if (!(r > 0.0 && std::isfinite(r) && dr >= 0.0 && std::isfinite(dr) && std::isfinite(scan.angle_rad[i]))) continue;
    // A beam the fan's thinning leaves out needs no error bound.
    beam.hit_m = beam.origin_m + geometry.offset(r, visibility_cos_[i], visibility_sin_[i]);
    if (clearing.thinned(beam.hit_m.x(), beam.hit_m.y())) continue;
    beam.height_error_m = geometry.height_error(r, dr, visibility_cos_[i], visibility_sin_[i], update);
    beam.range_error_m = dr;
    clearing.trace_unthinned(map, beam);
  }
  finish_visibility(mapper);
}

// The planar clean-up's loop over the beams it would not skip, in the same
// order and with the same doubles (the URG's angle table is std::cos and
// std::sin of the angles the planar scan holds).
void ScanIntegrator::clear_visible(const PlanarBeams& beams, const TrunkPose& pose, TerrainMapper& mapper) {
  if (!options_.visibility.enabled || clear_formed(beams.time_s, beams.beams, pose, mapper)) return;
  VisibilityClearing& clearing = visibility_for(mapper);
  const PlanarBeamGeometry geometry(pose, mapper.mount());
  const UpdateOptions& update = mapper.options().update;
  ElevationMap& map = mapper.map_without_raising();  // the clean-up only lowers and clears
  VisibilityBeam beam;
  beam.origin_m = sensor_origin_in_map(pose, mapper.mount());
  for (std::size_t i = 0; i < beams.count; ++i) {
    const double r = beams.range_m[i], dr = beams.range_error_m[i], c = beams.cos_angle[i], s = beams.sin_angle[i];
    beam.hit_m = beam.origin_m + geometry.offset(r, c, s);
    if (clearing.thinned(beam.hit_m.x(), beam.hit_m.y())) continue;
    beam.height_error_m = geometry.height_error(r, dr, c, s, update);
    beam.range_error_m = dr;
    clearing.trace_unthinned(map, beam);
  }
  finish_visibility(mapper);
}

void ScanIntegrator::clear_visible_batch(const TrunkPose& pose, TerrainMapper& mapper) {
  if (!options_.visibility.enabled) return;
  VisibilityClearing& clearing = visibility_for(mapper);
  ElevationMap& map = mapper.map_without_raising();  // the clean-up only lowers and clears
  VisibilityBeam beam;
  beam.origin_m = sensor_origin_in_map(pose, mapper.mount());
  SensorPoint p;
  for (std::size_t i = 0; i < batch_.size(); ++i) {
    if (batch_.point(i, p) != PointStatus::ok || !std::isfinite(p.height_error_m)) continue;
    const double length = p.offset_m.norm();
    if (!(length > 0.0)) continue;
    // The points carry a height bound, not a range error: the way along the
    // ray that moves the height by that bound (all of it for a level ray).
    const double rise = std::abs(p.offset_m.z()) / length;
    beam.range_error_m = rise > 0.0 ? std::min(length, p.height_error_m / rise) : length;
    beam.height_error_m = p.height_error_m;
    beam.hit_m = beam.origin_m + p.offset_m;
    clearing.trace(map, beam);
  }
  finish_visibility(mapper);
}

void ScanIntegrator::report(const ScanPayload& payload, std::optional<double> time_s, const ScanStats& stats,
                            std::span<const std::uint8_t> removed) {
  if (observers_.empty()) return;
  const ScanReport r{payload, time_s, stats, removed};
  for (PipelineObserver* observer : observers_) observer->on_scan(r);
}

}  // namespace stridemap
