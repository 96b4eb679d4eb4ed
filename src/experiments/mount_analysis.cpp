#include "stridemap/experiments/mount_analysis.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <numbers>

#include "stridemap/core/error.hpp"

namespace stridemap {
namespace {

constexpr double kRadPerDeg = std::numbers::pi / 180.0;

// Per-mount sums over all measurements of all fields.
struct Tally {
  double uncertainty_sum = 0.0;
  std::size_t points = 0;
  double stripe_sum = 0.0, look_ahead_sum = 0.0;
  std::size_t stripe_scans = 0, look_ahead_scans = 0;
  std::size_t ground_cells = 0, unobserved_cells = 0;
};

WalkPath path_through(const StepFieldOptions& field) {
  // From 0.8 m before the blocks (every mount of the sweep then sees their
  // first row) to 0.2 m before their end, along y = 0.
  WalkPath path;
  path.start_x_m = field.min_x_m - 0.8;
  path.start_y_m = 0.5 * (field.min_y_m + field.max_y_m);
  path.segments.push_back({WalkSegment::Kind::straight, field.max_x_m - field.min_x_m + 0.6, 0.0, 0.0});
  return path;
}

void walk_one_field(const NamedMount& mount, const Scene& scene, const MountSensorFactory& make_sensor,
                    const MountAnalysisOptions& o, std::uint64_t seed, Tally& tally) {
  std::unique_ptr<WalkSensor> sensor = make_sensor(scene, mount, o.update);
  sensor->set_collect_points(true);
  WalkOptions w;
  w.seed = seed;
  w.gait = o.gait;
  // The comparison is of geometry: the trunk glides level at the mount's
  // height over the floor, so gaps in the data come from occlusion, not
  // from the gait's jolts on the blocks.
  w.gait.follow_terrain = false;
  w.gait.bob_amplitude_m = 0.0;
  w.gait.pitch_amplitude_rad = 0.0;
  w.gait.roll_amplitude_rad = 0.0;
  w.pose_errors = PoseErrorOptions::none();
  w.mapper.follow_robot = false;
  w.mapper.grid.cell_size_m = o.cell_size_m;
  w.mapper.update = o.update;
  w.map_filter = MapFilter::none;
  w.swept_max_range_m = o.max_ground_range_m;
  w.swept_floor = WalkOptions::SweptFloor::scene_base;
  w.score_against_truth = false;
  WalkRun run(scene, path_through(o.field), *sensor, w);

  const StepFieldOptions& f = o.field;
  const double centre_y = 0.5 * (f.min_y_m + f.max_y_m);
  std::vector<double> ahead;
  ahead.reserve(4096);
  while (!run.done()) {
    run.step();
    const TrunkPose& pose = run.last_truth().pose;
    const double c = std::cos(pose.yaw_rad), s = std::sin(pose.yaw_rad);
    double lateral_min = std::numeric_limits<double>::infinity(), lateral_max = -lateral_min;
    ahead.clear();
    for (const ObservedPoint& p : sensor->last_points()) {
      const double dx = p.map_m.x() - pose.x_m, dy = p.map_m.y() - pose.y_m;
      const double forward = c * dx + s * dy, left = -s * dx + c * dy;
      if (forward <= 0.0) continue;
      if (p.range_m <= o.stripe_max_range_m) lateral_min = std::min(lateral_min, left), lateral_max = std::max(lateral_max, left);
      const bool in_strip = std::abs(left) <= o.corridor_half_width_m && p.map_m.x() >= f.min_x_m && p.map_m.x() <= f.max_x_m;
      if (!in_strip) continue;
      tally.uncertainty_sum += p.height_uncertainty_m;
      ++tally.points;
      ahead.push_back(forward);
    }
    if (lateral_max >= lateral_min) {
      tally.stripe_sum += lateral_max - lateral_min;
      ++tally.stripe_scans;
    }
    if (!ahead.empty()) {
      std::nth_element(ahead.begin(), ahead.begin() + static_cast<std::ptrdiff_t>(ahead.size() / 2), ahead.end());
      tally.look_ahead_sum += ahead[ahead.size() / 2];
      ++tally.look_ahead_scans;
    }
  }
  const WalkResult result = run.finish();
  const MapSnapshot& m = result.mosaic;
  const CellMask& states = m.state();
  for (Eigen::Index i = 0; i < states.rows(); ++i) {
    for (Eigen::Index j = 0; j < states.cols(); ++j) {
      if (!result.mosaic_swept(i, j)) continue;
      const Eigen::Vector2d centre = m.cell_center(i, j);
      const double x = centre.x(), y = centre.y();
      if (x < f.min_x_m || x > f.max_x_m || std::abs(y - centre_y) > o.corridor_half_width_m) continue;
      ++tally.ground_cells;
      tally.unobserved_cells += static_cast<CellState>(states(i, j)) == CellState::unknown;
    }
  }
}

std::string sweep_name(double height_m, double pitch_rad) {
  char name[48];
  std::snprintf(name, sizeof name, "h%.0fcm_p%.0fdeg", height_m * 100.0, pitch_rad / kRadPerDeg);
  return name;
}

}  // namespace

std::vector<NamedMount> paper_urg_mounts() {
  return {{"fig7a", SensorMount{0.16, 15.0 * kRadPerDeg, 0.0, 0.0}, std::nullopt},
          {"fig7b", SensorMount{0.26, 20.0 * kRadPerDeg, 0.0, 0.0}, std::nullopt},
          {"fig7c", SensorMount{0.26, 35.0 * kRadPerDeg, 0.0, 0.0}, std::nullopt}};
}

std::vector<NamedMount> paper_structured_light_mounts() {
  return {{"fig5a", SensorMount{0.174, 0.0, 0.0, 0.0}, 60.0 * kRadPerDeg},
          {"fig5b", SensorMount{0.174, 0.0, 0.0, 0.0}, 50.0 * kRadPerDeg},
          {"fig5c", SensorMount{0.174, 10.0 * kRadPerDeg, 0.0, 0.0}, 60.0 * kRadPerDeg}};
}

void MountAnalysisOptions::validate() const {
  const auto fail = [](const std::string& what) { throw InputError("mount analysis: " + what); };
  if (sweep_heights_m.empty() || sweep_pitches_rad.empty()) {
    fail("the sweep grid is empty (" + std::to_string(sweep_heights_m.size()) + " heights x " +
         std::to_string(sweep_pitches_rad.size()) + " pitches); give at least one of each");
  }
  for (double h : sweep_heights_m) {
    if (!(std::isfinite(h) && h > 0.0)) fail("sweep height " + std::to_string(h) + " m: heights must be above 0");
  }
  for (double p : sweep_pitches_rad) {
    if (!(std::isfinite(p) && std::abs(p) < std::numbers::pi / 2)) {
      fail("sweep pitch " + std::to_string(p / kRadPerDeg) + " deg: pitches must lie strictly between -90 and 90 deg");
    }
  }
  if (sweep_heights_m.size() * sweep_pitches_rad.size() > 10000) fail("the sweep grid has more than 10000 mounts");
  if (fields < 1 || fields > 1000) fail("fields must be between 1 and 1000, got " + std::to_string(fields));
  for (const auto& [name, value] :
       {std::pair<const char*, double>{"cell_size_m", cell_size_m}, {"corridor_half_width_m", corridor_half_width_m},
        {"max_ground_range_m", max_ground_range_m}, {"stripe_max_range_m", stripe_max_range_m},
        {"score.uncertainty_scale_m", score.uncertainty_scale_m}}) {
    if (!(std::isfinite(value) && value > 0.0)) fail(std::string(name) + " must be a positive number");
  }
  if (!(score.min_stripe_width_m >= 0.0) || !(score.min_look_ahead_m >= 0.0)) {
    fail("score.min_stripe_width_m and score.min_look_ahead_m must be >= 0");
  }
  if (auto problem = field.first_problem()) fail("step field: " + *problem);
  gait.validate();
}

MountMetrics analyse_mount(const NamedMount& mount, const MountSensorFactory& make_sensor,
                           const MountRangeShare& range_share, const MountAnalysisOptions& o) {
  MountMetrics metrics;
  metrics.mount = mount;
  Tally tally;
  for (int k = 0; k < o.fields; ++k) {
    const std::uint64_t seed = o.seed + static_cast<std::uint64_t>(k);
    const Scene scene = make_step_field(o.field, seed);
    if (k == 0) {
      try {
        check_mount_sees_ground(*make_sensor(scene, mount, o.update), o.max_ground_range_m, mount.name);
      } catch (const InputError&) {
        return metrics;  // sees_ground stays false
      }
    }
    walk_one_field(mount, scene, make_sensor, o, seed, tally);
  }
  metrics.sees_ground = true;
  metrics.ground_cells = tally.ground_cells;
  metrics.unobserved_fraction =
      tally.ground_cells ? static_cast<double>(tally.unobserved_cells) / static_cast<double>(tally.ground_cells) : 1.0;
  metrics.mean_height_uncertainty_m = tally.points ? tally.uncertainty_sum / static_cast<double>(tally.points) : 0.0;
  metrics.stripe_width_m = tally.stripe_scans ? tally.stripe_sum / static_cast<double>(tally.stripe_scans) : 0.0;
  metrics.look_ahead_m = tally.look_ahead_scans ? tally.look_ahead_sum / static_cast<double>(tally.look_ahead_scans) : 0.0;
  metrics.favourable_range_share = range_share ? range_share(mount) : std::nullopt;
  const MountScoreOptions& s = o.score;
  const bool eligible = tally.ground_cells > 0 && metrics.stripe_width_m >= s.min_stripe_width_m &&
                        metrics.look_ahead_m >= s.min_look_ahead_m;
  if (eligible) {
    metrics.score = (1.0 - metrics.unobserved_fraction) * metrics.favourable_range_share.value_or(1.0) /
                    (1.0 + metrics.mean_height_uncertainty_m / s.uncertainty_scale_m);
  }
  return metrics;
}

MountAnalysisResult run_mount_analysis(const std::vector<NamedMount>& named, const MountSensorFactory& make_sensor,
                                       const MountRangeShare& range_share, const MountAnalysisOptions& o) {
  o.validate();
  if (named.empty()) throw InputError("mount analysis: no named mounts given");
  const Scene first = make_step_field(o.field, o.seed);
  for (const NamedMount& m : named) {
    check_mount_sees_ground(*make_sensor(first, m, o.update), o.max_ground_range_m, m.name);
  }
  MountAnalysisResult result;
  result.sensor = make_sensor(first, named.front(), o.update)->name();
  result.heights = o.sweep_heights_m.size();
  result.pitches = o.sweep_pitches_rad.size();
  const std::size_t total = named.size() + result.heights * result.pitches;
  const auto report = [&] {
    if (o.progress) o.progress(result.named.size() + result.sweep.size(), total);
  };
  for (const NamedMount& m : named) {
    result.named.push_back(analyse_mount(m, make_sensor, range_share, o));
    report();
  }
  for (const double pitch : o.sweep_pitches_rad) {
    for (const double height : o.sweep_heights_m) {
      NamedMount m = named.front();
      m.name = sweep_name(height, pitch);
      m.mount.height_m = height;
      m.mount.pitch_rad = pitch;
      result.sweep.push_back(analyse_mount(m, make_sensor, range_share, o));
      report();
    }
  }
  for (std::size_t k = 1; k < result.sweep.size(); ++k) {
    if (result.sweep[k].score > result.sweep[result.best].score) result.best = k;
  }
  return result;
}

}  // namespace stridemap
