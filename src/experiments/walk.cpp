#include "stridemap/experiments/walk.hpp"

#include <algorithm>
#include <cmath>
#include <numbers>
#include <utility>

#include "stridemap/core/error.hpp"
#include "stridemap/core/sensor_transform.hpp"

namespace stridemap {
namespace {

// The mosaic reaches this far beyond the terrain's extent: the robot-centred
// window does when the robot walks along the extent's edge.
constexpr double kMosaicMargin_m = 0.6;

// Yaw changes below this between scans do not count as exercising the
// turning term (rounding of a straight walk's heading).
constexpr double kYawChangeCounted_rad = 1e-4;

ElevationMap mosaic_for(const HeightField& terrain, double cell_size_m) {
  const double side = std::max(terrain.max_x_m - terrain.min_x_m, terrain.max_y_m - terrain.min_y_m) + 2 * kMosaicMargin_m;
  int cells = 0;
  try {
    cells = cells_per_side_to_cover(side, cell_size_m);
  } catch (const GridSizeError& e) {
    throw GridSizeError(std::string("walk: the whole-scene mosaic: ") + e.what() +
                        "; or switch the mosaic off for scenes this large");
  }
  ElevationMap mosaic(GridOptions{cells, cell_size_m});
  mosaic.move_to(0.5 * (terrain.min_x_m + terrain.max_x_m), 0.5 * (terrain.min_y_m + terrain.max_y_m));
  return mosaic;
}

}  // namespace

std::size_t count_invalid_cells(const ElevationMap& map, double certainty_max) {
  std::size_t bad = 0;
  const std::size_t n = static_cast<std::size_t>(map.cells_per_side()) * static_cast<std::size_t>(map.cells_per_side());
  const float* h = map.elevation_data();
  const float* c = map.certainty_data();
  const std::uint8_t* s = map.state_data();
  const auto ceiling = static_cast<float>(certainty_max);
  for (std::size_t k = 0; k < n; ++k) {
    switch (static_cast<CellState>(s[k])) {
      case CellState::measured: bad += !(std::isfinite(h[k]) && c[k] > 0.0f && c[k] <= ceiling); break;
      case CellState::unknown: bad += !(std::isnan(h[k]) && c[k] == 0.0f); break;
      case CellState::filled: bad += !(std::isfinite(h[k]) && c[k] == 0.0f); break;
      default: ++bad; break;
    }
  }
  return bad;
}

WalkRun::WalkRun(const Scene& scene, const WalkPath& path, WalkSensor& sensor, const WalkOptions& options)
    : sensor_(sensor),
      options_(options),
      motion_(scene, path, options.gait),
      estimator_(options.pose_errors, options.gait, options.seed),
      mapper_(options.mapper, sensor.mount()) {
  if (options_.mosaic_every_scans < 1) {
    throw InputError("walk options: mosaic_every_scans must be at least 1, got " +
                     std::to_string(options_.mosaic_every_scans));
  }
  if (!(std::isfinite(options_.swept_max_range_m) && options_.swept_max_range_m > 0.0)) {
    throw InputError("walk options: swept_max_range_m must be a positive number");
  }
  if (!(std::isfinite(options_.imu_pitch_correction_rad) && std::isfinite(options_.imu_roll_correction_rad))) {
    throw InputError("walk options: imu_pitch_correction_rad and imu_roll_correction_rad must be finite");
  }
  check_mount_sees_ground(sensor_, options_.swept_max_range_m, sensor_.name());
  const double period = sensor_.frame_period_s();
  if (!(std::isfinite(period) && period > 0.0)) throw InputError("walk: the sensor's frame period must be positive");
  const double frames = std::floor(motion_.duration_s() / period + 1e-9) + 1.0;
  if (frames > 1e8) throw InputError("walk: the path needs " + std::to_string(frames) + " scans, more than 1e8");
  total_scans_ = static_cast<std::size_t>(frames);
  trajectory_.reserve(total_scans_);
  if (options_.pose_errors.reference == ReferenceElevationSource::map_footholds) height_errors_.reserve(total_scans_);

  const HeightField& terrain = motion_.scene().terrain;
  if (!options_.mapper.follow_robot) {
    // A fixed window over the whole scene: nothing is ever forgotten.
    ElevationMap whole = mosaic_for(terrain, options_.mapper.grid.cell_size_m);
    MapperOptions fixed = options_.mapper;
    fixed.grid.cells_per_side = whole.cells_per_side();
    mapper_ = TerrainMapper(fixed, sensor_.mount());
    mapper_.map().move_corner_to(whole.min_cell());
  }
  // A walk with the true h_ref keeps the layers too, to say what the map
  // alone would give a robot reading its height there; they never touch
  // the elevation.
  if (reads_fused_layer(options_.pose_errors.reference) ||
      options_.pose_errors.reference == ReferenceElevationSource::truth) {
    fusion_.emplace(mapper_.map(), options_.height_fusion);
    soles_reader_.emplace(std::as_const(mapper_).map());
    sensor_.set_collect_points(true);
  }
  estimator_.set_attitude_correction(options_.imu_pitch_correction_rad, options_.imu_roll_correction_rad);
  if (options_.build_mosaic) {
    mosaic_ = mosaic_for(terrain, options_.mapper.grid.cell_size_m);
    swept_ = CellMask::Zero(mosaic_->cells_per_side(), mosaic_->cells_per_side());
  }
}

void WalkRun::read_fused_under_soles() {
  const ElevationMap& map = std::as_const(mapper_).map();
  const StanceHeightReader& reader = *soles_reader_;
  double sum = 0.0;
  int feet = 0;
  for (const FootState& foot : truth_.feet) {
    if (!foot.in_stance) continue;
    const std::optional<SoleGround> ground = reader.ground_under(map, foot.position_m.x(), foot.position_m.y());
    if (!ground || ground->known_share < reader.options().min_known_share) continue;
    sum += ground->height_m - foot.position_m.z();
    ++feet;
  }
  if (feet == 0) return;
  fused_under_soles_error_sum_m_ += sum / feet;
  ++fused_under_soles_scans_;
}

void WalkRun::trace_swept(const TrunkPose& truth) {
  const double floor_m = options_.swept_floor == WalkOptions::SweptFloor::robot_ground
                             ? truth.reference_elevation_m
                             : motion_.scene().terrain.base_elevation_m;
  sensor_.floor_trace(truth, floor_m, options_.swept_max_range_m, trace_);
  const ElevationMap& local = std::as_const(mapper_).map();
  const ElevationMap& mosaic = *mosaic_;
  const double step = local.cell_size_m() / 4.0;
  const auto mark = [&](const Eigen::Vector2d& p) {
    const CellIndex c = local.cell_of(p.x(), p.y());
    if (!local.contains(c) || !mosaic.contains(c)) return;
    swept_(c.x - mosaic.min_cell().x, c.y - mosaic.min_cell().y) = 1;
  };
  for (std::size_t i = 0; i < trace_.size(); ++i) {
    const Eigen::Vector2d& now = trace_[i];
    if (!now.allFinite()) continue;
    const bool paired = have_previous_trace_ && i < previous_trace_.size() && previous_trace_[i].allFinite();
    if (!paired) {
      mark(now);
      continue;
    }
    // The ray's floor point moved from its previous place to this one; the
    // cells between were swept too (a turn moves far points by more than a cell).
    const Eigen::Vector2d delta = now - previous_trace_[i];
    const int samples = 1 + static_cast<int>(std::min(1000.0, std::ceil(delta.norm() / step)));
    for (int k = 1; k <= samples; ++k) mark(previous_trace_[i] + delta * (static_cast<double>(k) / samples));
  }
  std::swap(trace_, previous_trace_);
  have_previous_trace_ = true;
}

void WalkRun::copy_into_mosaic() {
  const ElevationMap& local = std::as_const(mapper_).map();
  ElevationMap& mosaic = *mosaic_;
  const int n = local.cells_per_side();
  for (int i = 0; i < n; ++i) {
    for (int j = 0; j < n; ++j) {
      const CellIndex c = local.cell_at_local(i, j);
      if (local.state(c) != CellState::measured || !mosaic.contains(c)) continue;
      const std::size_t from = local.slot(c), to = mosaic.slot(c);
      mosaic.elevation_data()[to] = local.elevation_data()[from];
      mosaic.certainty_data()[to] = local.certainty_data()[from];
      mosaic.state_data()[to] = local.state_data()[from];
    }
  }
}

void WalkRun::step() {
  const double time_s = static_cast<double>(next_scan_) * sensor_.frame_period_s();
  truth_ = motion_.at(time_s);
  estimate_ = estimator_.estimate(truth_, std::as_const(mapper_).map());  // a read: not counted (TerrainMapper::changes())
  if (fusion_) read_fused_under_soles();
  if (std::abs(mapper_.motion_to(estimate_).yaw_change_rad) > kYawChangeCounted_rad) ++yaw_change_scans_;
  last_stats_ = sensor_.measure(truth_.pose, estimate_, time_s, mapper_);
  count_visibility();
  if (fusion_) {  // writes the fused layers only, never the elevation: not counted
    for (const ObservedPoint& p : sensor_.last_points()) {
      fusion_->add(mapper_.map_without_raising(), p.map_m.x(), p.map_m.y(), p.map_m.z(), p.height_uncertainty_m);
    }
  }
  // Nothing in the walk reads the changed rows but the next scan's
  // clean-up, which needs only that scan's: cleared here, its maxima are
  // kept from scan to scan instead of taken from the whole map once the
  // rows grow past a quarter of the window (docs/visibility.md).
  mapper_.clear_changed_cells();

  const TrunkPose& t = truth_.pose;
  const TrunkPose& e = estimate_;
  const double height_error = (e.reference_elevation_m + e.height_change_m) - (t.reference_elevation_m + t.height_change_m);
  const double errors[6] = {e.x_m - t.x_m, e.y_m - t.y_m, std::remainder(e.yaw_rad - t.yaw_rad, 2 * std::numbers::pi),
                            e.pitch_rad - t.pitch_rad, e.roll_rad - t.roll_rad, height_error};
  for (int k = 0; k < 6; ++k) sum_sq_[k] += errors[k] * errors[k];
  sum_height_error_ += height_error;
  trajectory_.emplace_back(t.x_m, t.y_m);
  if (options_.pose_errors.reference == ReferenceElevationSource::map_footholds) {
    height_errors_.push_back(estimator_.last_height_error());
  }

  if (mosaic_) {
    trace_swept(t);
    if (options_.mapper.follow_robot && next_scan_ % static_cast<std::size_t>(options_.mosaic_every_scans) == 0) {
      copy_into_mosaic();
    }
  }
  ++next_scan_;
}

void WalkRun::count_visibility() {
  const VisibilityClearing* v = sensor_.visibility();
  if (!v || v->scans() == visibility_scans_) return;
  visibility_scans_ = v->scans();
  visibility_cleared_ += v->stats().cells_cleared;
  visibility_contradicted_ += v->stats().cells_contradicted;
  ++visibility_scans_counted_;
  visibility_whole_map_ += v->stats().maxima_from_whole_map;
  if (!options_.score_against_truth) return;
  const Scene& scene = motion_.scene();
  const double size = std::as_const(mapper_).map().cell_size_m();
  for (const ClearedCell& c : v->cleared()) {
    const double x = static_cast<double>(c.cell.x) * size, y = static_cast<double>(c.cell.y) * size;
    const double truth = scene.max_height_in_rect(x, y, x + size, y + size);
    if (static_cast<double>(c.elevation_m) <= truth + options_.visibility_correct_m) {
      ++visibility_wrong_;
    } else {
      ++visibility_artifacts_;
    }
  }
}

WalkResult WalkRun::finish() {
  sensor_.flush(mapper_);
  count_visibility();
  WalkResult r;
  r.scans = next_scan_;
  r.duration_s = truth_.time_s;
  r.distance_m = truth_.distance_m;
  r.turned_rad = truth_.turned_rad;
  r.mapper_totals = mapper_.totals();
  r.scans_with_yaw_change = yaw_change_scans_;
  r.visibility_enabled = sensor_.visibility() != nullptr;
  r.visibility_correct_m = options_.visibility_correct_m;
  r.visibility_cleared = visibility_cleared_;
  r.visibility_wrongly_cleared = visibility_wrong_;
  r.visibility_artifacts_cleared = visibility_artifacts_;
  r.visibility_cells_contradicted = visibility_contradicted_;
  r.visibility_scans = visibility_scans_counted_;
  r.visibility_whole_map_scans = visibility_whole_map_;
  r.trajectory = trajectory_;
  r.height_errors = height_errors_;
  r.fused_under_soles_error_sum_m = fused_under_soles_error_sum_m_;
  r.fused_under_soles_scans = fused_under_soles_scans_;
  if (next_scan_ > 0) {
    const double n = static_cast<double>(next_scan_);
    PoseErrorStats& p = r.pose_errors;
    double* fields[6] = {&p.x_m, &p.y_m, &p.yaw_rad, &p.pitch_rad, &p.roll_rad, &p.sensor_height_m};
    for (int k = 0; k < 6; ++k) *fields[k] = std::sqrt(sum_sq_[k] / n);
    p.mean_sensor_height_m = sum_height_error_ / n;
  }
  if (mosaic_) copy_into_mosaic();

  const auto filter = [&](ElevationMap& map, bool count) {
    const MapFilterResult done = apply_map_filter({options_.map_filter, options_.fill, options_.cas}, map);
    if (count) r.filled_cells = done.filled, r.cas_removed_cells = done.cas_removed;
  };
  const Scene& scene = motion_.scene();
  r.map_config.mount = mapper_.mount();
  r.map_config.mapper = mapper_.options();
  r.map_config.fill = options_.fill;
  const auto snapshot = [&](const ElevationMap& map) {
    if (options_.score_against_truth) return snapshot_with_truth(map, scene);
    MapSnapshot s{export_map(map), {}, {}, {}, {}};
    s.truth_m = Eigen::MatrixXf::Constant(map.cells_per_side(), map.cells_per_side(), NAN);
    return s;
  };
  filter(mapper_.map(), !mosaic_);
  // A fixed window is the mosaic already: no second snapshot of it.
  if (options_.mapper.follow_robot || !mosaic_) r.local = snapshot(mapper_.map());
  if (!mosaic_) {
    r.map = mapper_.map();
    return r;
  }

  filter(*mosaic_, true);
  r.map = *mosaic_;
  r.mosaic = snapshot(*mosaic_);
  r.mosaic_swept = swept_;
  if (options_.score_against_truth) r.mosaic_score = score_map(r.mosaic, swept_, options_.score);
  const CellMask& mosaic_states = r.mosaic.state();
  for (Eigen::Index i = 0; i < swept_.rows(); ++i)
    for (Eigen::Index j = 0; j < swept_.cols(); ++j)
      r.unknown_swept_cells += swept_(i, j) && static_cast<CellState>(mosaic_states(i, j)) == CellState::unknown;

  if (!options_.mapper.follow_robot) return r;
  const ElevationMap& local = std::as_const(mapper_).map();
  const int n = local.cells_per_side();
  r.local_swept = CellMask::Zero(n, n);
  for (int i = 0; i < n; ++i) {
    for (int j = 0; j < n; ++j) {
      const CellIndex c = local.cell_at_local(i, j);
      if (mosaic_->contains(c)) r.local_swept(i, j) = swept_(c.x - mosaic_->min_cell().x, c.y - mosaic_->min_cell().y);
    }
  }
  if (options_.score_against_truth) r.local_score = score_map(r.local, r.local_swept, options_.score);
  return r;
}

WalkResult run_walk(const Scene& scene, const WalkPath& path, WalkSensor& sensor, const WalkOptions& options) {
  WalkRun run(scene, path, sensor, options);
  while (!run.done()) run.step();
  return run.finish();
}

}  // namespace stridemap
