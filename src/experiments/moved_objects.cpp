#include "stridemap/experiments/moved_objects.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <map>
#include <memory>

#include "stridemap/core/error.hpp"
#include "stridemap/pipeline/mapping_pipeline.hpp"
#include "stridemap/sim/cart_rail.hpp"

namespace stridemap {
namespace {

// How far ahead of the cart the tilted scanner looks, and behind it the
// beams' origin: the fixed window covers both ends of the rail with this.
constexpr double kWindowBehind_m = 0.3, kWindowAhead_m = 1.0;

std::vector<CellIndex> footprint_cells(const ElevationMap& map, const BoxObject& box) {
  std::vector<CellIndex> cells;
  const int n = map.cells_per_side();
  for (int i = 0; i < n; ++i) {
    for (int j = 0; j < n; ++j) {
      const CellIndex c = map.cell_at_local(i, j);
      const Eigen::Vector2d centre = map.cell_center(c);
      if (footprint_contains(box, centre.x(), centre.y())) cells.push_back(c);
    }
  }
  return cells;
}

double truth_of(const Scene& scene, const ElevationMap& map, CellIndex c) {
  const double size = map.cell_size_m();
  const double x = static_cast<double>(c.x) * size, y = static_cast<double>(c.y) * size;
  return scene.max_height_in_rect(x, y, x + size, y + size);
}

std::size_t standing_cells(const ElevationMap& map, const Scene& now, const std::vector<CellIndex>& cells, double above) {
  std::size_t standing = 0;
  for (const CellIndex c : cells) {
    const float h = map.elevation(c);
    standing += std::isfinite(h) && static_cast<double>(h) > truth_of(now, map, c) + above;
  }
  return standing;
}

MovedObjectsRun run_once(const Scene& scene, const MovedObjectsOptions& o, const std::vector<TrunkPose>& poses,
                         bool visibility, std::size_t progress_offset, std::size_t progress_total) {
  PipelineOptions p;
  p.sensor = SensorKind::urg;
  p.urg = o.urg;
  p.mount = o.mount;
  p.mapper.update = o.update;
  p.mapper.follow_robot = false;
  p.foothold.enabled = false;
  p.visibility = o.visibility;
  p.visibility.enabled = visibility;
  const double lo_x = std::min(poses.front().x_m, poses.back().x_m) - kWindowBehind_m;
  const double hi_x = std::max(poses.front().x_m, poses.back().x_m) + kWindowAhead_m;
  p.mapper.grid.cell_size_m = o.cell_size_m;
  p.mapper.grid.cells_per_side = cells_per_side_to_cover(std::max(hi_x - lo_x, 2.0 * kWindowAhead_m), o.cell_size_m);
  MappingPipeline pipeline(p);
  ElevationMap& map = pipeline.mapper().map();
  map.move_to(0.5 * (lo_x + hi_x), poses.front().y_m);

  MovedObjectsRun run;
  run.visibility = visibility;
  std::vector<const BoxObject*> leaving;
  std::vector<std::vector<CellIndex>> cells;
  for (const BoxObject& box : scene.boxes) {
    if (!std::isfinite(box.present_until_s)) continue;
    leaving.push_back(&box);
    cells.push_back(footprint_cells(map, box));
    run.objects.push_back({box.name, box.present_until_s, 0, 0, {}, std::nullopt, std::nullopt});
  }
  // One simulator per set of boxes present: the scene changes only when a box comes or goes.
  std::map<std::vector<bool>, std::unique_ptr<UrgSimulator>> simulators;
  UrgRawScan raw;
  std::uint64_t counted = 0;
  for (std::size_t k = 0; k < poses.size(); ++k) {
    const double time_s = static_cast<double>(k) * o.urg.scan_period_s;
    const Scene now = scene.at_time(time_s);
    std::vector<bool> present;
    for (const BoxObject& box : scene.boxes) present.push_back(box.present_at(time_s));
    std::unique_ptr<UrgSimulator>& simulator = simulators[present];
    if (!simulator) simulator = std::make_unique<UrgSimulator>(now, o.urg, o.sim, o.seed);
    simulator->reset(o.seed * 1000003u + k);  // the noise of scan k, whichever scene it sees
    for (std::size_t b = 0; b < leaving.size(); ++b) {
      if (time_s >= leaving[b]->present_until_s && run.objects[b].standing.empty()) {
        run.objects[b].left_at_scan = k;
        run.objects[b].standing_when_left = standing_cells(map, now, cells[b], o.standing_above_m);
      }
    }
    simulator->scan(poses[k], o.mount, time_s, raw);
    pipeline.add(raw, poses[k]);
    if (const VisibilityClearing* v = pipeline.integrator().visibility(); v && v->scans() != counted) {
      counted = v->scans();
      run.cells_cleared += v->stats().cells_cleared;
      run.cells_contradicted += v->stats().cells_contradicted;
      for (const ClearedCell& c : v->cleared()) {
        run.cells_wrongly_cleared += static_cast<double>(c.elevation_m) <= truth_of(now, map, c.cell) + o.standing_above_m;
      }
    }
    for (std::size_t b = 0; b < leaving.size(); ++b) {
      MovedObjectTrack& t = run.objects[b];
      if (time_s < leaving[b]->present_until_s) continue;
      t.standing.push_back(standing_cells(map, now, cells[b], o.standing_above_m));
      if (!t.scans_until_cleared && t.standing.back() == 0) t.scans_until_cleared = t.standing.size();
      if (!t.scans_until_half_cleared && t.standing_when_left > 0 && 2 * t.standing.back() <= t.standing_when_left) {
        t.scans_until_half_cleared = t.standing.size();
      }
    }
    if (o.progress) o.progress(progress_offset + k + 1, progress_total);
  }
  return run;
}

}  // namespace

MovedObjectsResult run_moved_objects(const Scene& scene, const MovedObjectsOptions& options) {
  scene.validate();
  options.urg.validate();
  validate_visibility_options(options.visibility);
  if (!(std::isfinite(options.standing_above_m) && options.standing_above_m >= 0.0)) {
    throw InputError("moved objects: standing_above_m must be a number >= 0");
  }
  if (!scene.cart_rail) throw InputError("moved objects: the scene has no cart_rail section to move the sensor along");
  if (std::none_of(scene.boxes.begin(), scene.boxes.end(), [](const BoxObject& b) { return std::isfinite(b.present_until_s); })) {
    throw InputError("moved objects: no box of the scene leaves (give one a present_until_s)");
  }
  // Out and back: a tilted scanner's beams over a cell only rise while its
  // stripe moves away from it, so only a sensor that comes back (a robot
  // stepping back, turning, passing again) can see below what it mapped.
  std::vector<TrunkPose> poses = cart_rail_poses(*scene.cart_rail);
  if (poses.size() < 2) throw InputError("moved objects: the rail must hold at least two scan positions");
  for (std::size_t k = poses.size() - 1; k-- > 0;) poses.push_back(poses[k]);
  MovedObjectsResult result;
  result.scans = poses.size();
  result.off = run_once(scene, options, poses, false, 0, 2 * poses.size());
  result.on = run_once(scene, options, poses, true, poses.size(), 2 * poses.size());
  return result;
}

std::string moved_objects_table(const MovedObjectsResult& r) {
  std::string out;
  char line[320];
  std::snprintf(line, sizeof line, "moved-objects (simulated): %zu scans; cells still standing after each object left\n",
                r.scans);
  out += line;
  out += "object            left at  standing | off: scans to half, to none, left at end | on: to half, to none, left\n";
  for (std::size_t b = 0; b < r.on.objects.size(); ++b) {
    const MovedObjectTrack& off = r.off.objects[b];
    const MovedObjectTrack& on = r.on.objects[b];
    const auto scans = [](const std::optional<std::size_t>& n) { return n ? std::to_string(*n) : std::string("never"); };
    const auto left = [](const MovedObjectTrack& t) { return t.standing.empty() ? std::size_t{0} : t.standing.back(); };
    std::snprintf(line, sizeof line, "%-16s  %6.1f s  %8zu | %5s, %5s, %4zu | %5s, %5s, %4zu\n", on.name.c_str(),
                  on.left_at_s, on.standing_when_left, scans(off.scans_until_half_cleared).c_str(),
                  scans(off.scans_until_cleared).c_str(), left(off), scans(on.scans_until_half_cleared).c_str(),
                  scans(on.scans_until_cleared).c_str(), left(on));
    out += line;
  }
  std::snprintf(line, sizeof line,
                "clean-up on: %zu cells passed below (summed over scans), %zu cleared, %zu of them wrongly (within "
                "their truth)\n",
                r.on.cells_contradicted, r.on.cells_cleared, r.on.cells_wrongly_cleared);
  out += line;
  return out;
}

}  // namespace stridemap
