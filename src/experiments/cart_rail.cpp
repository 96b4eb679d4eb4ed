#include "stridemap/experiments/cart_rail.hpp"

#include <algorithm>
#include <functional>
#include <cmath>
#include <limits>
#include <memory>
#include <numbers>
#include <optional>
#include <span>
#include <vector>

#include "cart_rail_internal.hpp"
#include "stridemap/core/error.hpp"
#include "stridemap/core/sensor_transform.hpp"
#include "stridemap/sim/scene_ray_caster.hpp"

namespace stridemap {
namespace {

std::span<const std::uint8_t> beam_tags(const std::vector<BeamLabel>& labels) {
  static_assert(sizeof(BeamLabel) == 1);
  return {reinterpret_cast<const std::uint8_t*>(labels.data()), labels.size()};
}

// Scores the filters on each scan that reaches the map against the
// simulator's labels, which travel with the scan as its beam tags, and
// against where its beams truly end (`in_window`, per scan by sequence
// number: 1 where the ideal ray ends inside the map's window).
class BeamTallyObserver final : public PipelineObserver {
 public:
  BeamTallyObserver(BeamTally& tally, bool drop_labelled_mixed, const std::vector<std::vector<std::uint8_t>>& in_window)
      : tally_(tally), drop_labelled_mixed_(drop_labelled_mixed), in_window_(in_window) {}
  void on_scan(const ScanReport& report) override {
    const std::vector<std::uint8_t>& tags = report.payload.beam_tags;
    const std::size_t sequence = report.payload.sequence;
    const std::vector<std::uint8_t>* in_window = sequence < in_window_.size() ? &in_window_[sequence] : nullptr;
    for (std::size_t i = 0; i < tags.size(); ++i) {
      const auto label = static_cast<BeamLabel>(tags[i]);
      const bool was_removed =
          (i < report.removed.size() && report.removed[i]) || (drop_labelled_mixed_ && label == BeamLabel::mixed);
      switch (label) {
        case BeamLabel::clean:
          ++tally_.clean;
          tally_.clean_removed += was_removed;
          if (in_window != nullptr && i < in_window->size() && (*in_window)[i] != 0) {
            ++tally_.clean_in_window;
            tally_.clean_in_window_removed += was_removed;
          }
          break;
        case BeamLabel::mixed: ++tally_.mixed; tally_.mixed_removed += was_removed; break;
        case BeamLabel::dropped: ++tally_.dropped; break;
      }
    }
  }

 private:
  BeamTally& tally_;
  bool drop_labelled_mixed_;
  const std::vector<std::vector<std::uint8_t>>& in_window_;
};

// Where each beam of one pose meets the floor plane, NaN when it does not
// within the range limit.
std::vector<Eigen::Vector2d> floor_hits(const TrunkPose& pose, const SensorMount& mount, const UrgParameters& urg,
                                        double floor_m, double max_range_m) {
  std::vector<Eigen::Vector2d> hits(static_cast<std::size_t>(urg.beam_count()),
                                    Eigen::Vector2d::Constant(std::numeric_limits<double>::quiet_NaN()));
  const Eigen::Matrix3d rotation = sensor_to_map_rotation(pose, mount);
  const Eigen::Vector3d origin = sensor_origin_in_map(pose, mount);
  for (int i = 0; i < urg.beam_count(); ++i) {
    const double t = urg.step_angle_rad(urg.first_step + i);
    const Eigen::Vector3d dir = rotation * Eigen::Vector3d(std::cos(t), std::sin(t), 0.0);
    if (dir.z() >= -1e-9) continue;
    const double range = (floor_m - origin.z()) / dir.z();
    if (range <= 0.0 || range > max_range_m) continue;
    hits[static_cast<std::size_t>(i)] = (origin + range * dir).head<2>();
  }
  return hits;
}

// The beams of one pose as a sensor without noise or spread sees them;
// `in_window` gets 1 for each beam that ends inside the map's window.
void add_ideal_hits(const SceneRayCaster& caster, const TrunkPose& pose, const SensorMount& mount,
                    const UrgParameters& urg, const ElevationMap& map, TopVisibility& visibility,
                    std::vector<std::uint8_t>& in_window) {
  const Eigen::Matrix3d rotation = sensor_to_map_rotation(pose, mount);
  const Eigen::Vector3d origin = sensor_origin_in_map(pose, mount);
  in_window.assign(static_cast<std::size_t>(urg.beam_count()), 0);
  for (int i = 0; i < urg.beam_count(); ++i) {
    const double t = urg.step_angle_rad(urg.first_step + i);
    const Eigen::Vector3d dir = rotation * Eigen::Vector3d(std::cos(t), std::sin(t), 0.0);
    if (const std::optional<RayHit> hit = caster.cast(origin, dir, urg.max_range_m)) {
      visibility.add_hit(hit->object_index, hit->point_m);
      std::size_t slot = 0;
      in_window[static_cast<std::size_t>(i)] = map.slot_at(hit->point_m.x(), hit->point_m.y(), slot) ? 1 : 0;
    }
  }
}

}  // namespace

CellMask swept_area_between(const ElevationMap& map, const std::vector<Eigen::Vector2d>& first,
                            const std::vector<Eigen::Vector2d>& last) {
  const int n = map.cells_per_side();
  CellMask area = CellMask::Zero(n, n);
  const double step = map.cell_size_m() / 4.0;
  for (std::size_t b = 0; b < first.size() && b < last.size(); ++b) {
    if (!first[b].allFinite() || !last[b].allFinite()) continue;
    const Eigen::Vector2d delta = last[b] - first[b];
    const int samples = 1 + static_cast<int>(std::ceil(delta.norm() / step));
    for (int k = 0; k <= samples; ++k) {
      const Eigen::Vector2d p = first[b] + delta * (static_cast<double>(k) / samples);
      const CellIndex c = map.cell_of(p.x(), p.y());
      if (map.contains(c)) area(c.x - map.min_cell().x, c.y - map.min_cell().y) = 1;
    }
  }
  return area;
}

CellMask swept_floor_area(const ElevationMap& map, const std::vector<TrunkPose>& poses, const SensorMount& mount,
                          const UrgParameters& urg, double floor_elevation_m, double max_range_m) {
  if (poses.empty()) return CellMask::Zero(map.cells_per_side(), map.cells_per_side());
  return swept_area_between(map, floor_hits(poses.front(), mount, urg, floor_elevation_m, max_range_m),
                            floor_hits(poses.back(), mount, urg, floor_elevation_m, max_range_m));
}

namespace detail {

PipelineOptions rail_pipeline_options(const Eigen::Vector2d& lo, const Eigen::Vector2d& hi,
                                      const CartRailOptions& options, const SensorMount& mount) {
  // A fixed window around everything the sensor can sweep, so the whole
  // scene stays in the map (the test bed, unlike the robot, need not forget).
  PipelineOptions p;
  p.mapper.follow_robot = false;
  p.mapper.update = options.update;
  const double margin_m = 0.1;
  const int cells = options.cells_per_side > 0
                        ? options.cells_per_side
                        : cells_per_side_to_cover((hi - lo).maxCoeff() + 2 * margin_m, options.cell_size_m);
  p.mapper.grid = {cells, options.cell_size_m};
  declare_top_point_layers(p.mapper.grid);
  p.map_filter = {options.map_filter, options.fill, options.cas};
  p.mount = mount;
  return p;
}

void centre_rail_map(const Eigen::Vector2d& lo, const Eigen::Vector2d& hi, MappingPipeline& pipeline) {
  const Eigen::Vector2d centre = 0.5 * (lo + hi);
  pipeline.mapper().map().move_to(centre.x(), centre.y());
}

TopVisibility rail_top_visibility(const Scene& scene, const CartRailPath& rail) {
  return TopVisibility(scene, 0.75 * rail.step_m);
}

void finish_rail_map(const Scene& scene, const CartRailOptions& options, MappingPipeline& pipeline,
                     const std::function<CellMask(const ElevationMap&)>& swept_area,
                     const TopVisibility& visibility, CartRailResult& result) {
  result.mapper_totals = pipeline.mapper().totals();
  const MapFilterResult filtered = pipeline.apply_map_filter();
  result.filled_cells = filtered.filled;
  result.cas_removed_cells = filtered.cas_removed;
  const ElevationMap& map = pipeline.map();
  result.snapshot = snapshot_with_truth(map, scene);
  // The objects' sub-cell edges read the top points, which are not in the
  // planner's export.
  const std::string top_layers[] = {"top_point_x", "top_point_y"};
  for (ExportedLayer& layer : export_map(map, top_layers).layers) result.snapshot.layers.push_back(std::move(layer));
  result.map = map;
  result.map_config.mount = pipeline.mapper().mount();
  result.map_config.mapper = pipeline.mapper().options();
  result.map_config.fill = options.fill;
  result.map_config.calibration = options.calibration;
  result.swept_area = swept_area(map);
  result.score = score_map(result.snapshot, result.swept_area, options.score);
  // The URG looks along the trunk's heading, the rail's yaw, for every
  // scan: the faces turned back against it are the ones its beams met
  // (BoxEdgeOptions::facing_edge_quantile; only the URG's figures were
  // measured with it).
  ObjectMeasureOptions objects = options.objects;
  if (options.sensor == CartRailSensor::urg && !std::isfinite(objects.edges.view_heading_rad)) {
    objects.edges.view_heading_rad = result.rail.yaw_rad;
  }
  objects.travel_heading_rad = result.rail.yaw_rad;
  if (!std::isfinite(objects.travel_point_m.x())) {
    objects.travel_point_m = sensor_origin_in_map(cart_rail_poses(result.rail).front(), pipeline.mapper().mount()).head<2>();
  }
  // The URG's readings lie on its beams from that origin; the structured
  // light's errors lie along the camera's rays, which start elsewhere.
  if (options.sensor == CartRailSensor::urg && !std::isfinite(objects.sensor_height_m)) {
    objects.sensor_height_m = sensor_origin_in_map(cart_rail_poses(result.rail).front(), pipeline.mapper().mount()).z();
  }
  // Its beams run ahead cot(pitch) per unit of drop only while the scan
  // plane is turned about the across-track axis alone.
  const SensorMount& mount = pipeline.mapper().mount();
  const TrunkPose rail_start = cart_rail_poses(result.rail).front();
  if (options.sensor == CartRailSensor::urg && std::isnan(objects.sensor_pitch_rad) && mount.roll_rad == 0.0 &&
      mount.yaw_rad == 0.0 && rail_start.roll_rad == 0.0) {
    const double pitch = mount.pitch_rad + rail_start.pitch_rad;
    if (pitch > 0.0 && pitch < std::numbers::pi / 2) objects.sensor_pitch_rad = pitch;
  }
  // The stripe's sheet never lights a far side (ObjectMeasureOptions::unlit_far_side_step_m).
  if (options.sensor == CartRailSensor::structured_light && std::isnan(objects.unlit_far_side_step_m)) {
    objects.unlit_far_side_step_m = result.rail.step_m;
  }
  // A rail step no longer than a cell measures the tops throughout; the
  // cells it leaves to the fill are then the shadows between objects.
  if (result.rail.step_m <= pipeline.mapper().map().cell_size_m() * (1.0 + 1e-9)) objects.region_measured_only = true;
  result.objects = measure_objects(result.snapshot, scene, objects);
  const std::vector<double> seen = visibility.seen_shares();
  for (std::size_t k = 0; k < result.objects.size() && k < seen.size(); ++k) result.objects[k].seen_share = seen[k];
}

}  // namespace detail

CartRailResult run_cart_rail(const Scene& scene, const CartRailOptions& options) {
  scene.validate();
  options.urg.validate();
  CartRailResult result;
  result.rail = scene.cart_rail.value_or(options.default_rail);
  const std::vector<TrunkPose> poses = cart_rail_poses(result.rail);
  if (poses.size() < 2) {
    throw InputError("cart rail: the rail must hold at least two scan positions (start_x_m " +
                     std::to_string(result.rail.start_x_m) + ", end_x_m " + std::to_string(result.rail.end_x_m) + ")");
  }
  if (options.sensor == CartRailSensor::structured_light) {
    detail::run_structured_light_rail(scene, options, poses, result);
    return result;
  }

  const double floor_m = scene.terrain.base_elevation_m;
  Eigen::Vector2d lo = Eigen::Vector2d::Constant(std::numeric_limits<double>::infinity());
  Eigen::Vector2d hi = -lo;
  for (const TrunkPose* pose : {&poses.front(), &poses.back()}) {
    for (const Eigen::Vector2d& h : floor_hits(*pose, options.mount, options.urg, floor_m, options.swept_max_range_m)) {
      if (!h.allFinite()) continue;
      lo = lo.cwiseMin(h);
      hi = hi.cwiseMax(h);
    }
  }
  if (!lo.allFinite()) {
    throw InputError("cart rail: with this mount no beam meets the floor within " +
                     std::to_string(options.swept_max_range_m) + " m");
  }
  PipelineOptions pipeline_options = detail::rail_pipeline_options(lo, hi, options, options.mount);
  pipeline_options.sensor = SensorKind::urg;
  pipeline_options.urg = options.urg;
  pipeline_options.calibration = options.calibration;
  pipeline_options.filters = options.filters;
  pipeline_options.filter_options = options.filter_options;
  if (options.drop_labelled_mixed) pipeline_options.drop_beams_tagged = static_cast<std::uint8_t>(BeamLabel::mixed);
  MappingPipeline pipeline(pipeline_options);
  detail::centre_rail_map(lo, hi, pipeline);
  TopPointObserver top_points(pipeline);
  std::vector<std::vector<std::uint8_t>> in_window(poses.size());
  BeamTallyObserver tally(result.beams, options.drop_labelled_mixed, in_window);
  pipeline.integrator().add_observer(tally);

  std::unique_ptr<BeamModel> beam_model;
  if (options.mixed_pixels) {
    beam_model = std::make_unique<FootprintBeamModel>(options.footprint);
  } else {
    beam_model = std::make_unique<SingleRayBeamModel>();
  }
  UrgSimulator simulator(scene, options.urg, options.sim, options.seed, std::move(beam_model));
  TopVisibility visibility = detail::rail_top_visibility(scene, result.rail);
  const SceneRayCaster ideal_beams(scene);
  UrgRawScan raw;
  std::vector<BeamLabel> labels;
  for (std::size_t k = 0; k < poses.size(); ++k) {
    const double time_s = static_cast<double>(k) * options.urg.scan_period_s;
    add_ideal_hits(ideal_beams, poses[k], options.mount, options.urg, pipeline.mapper().map(), visibility,
                   in_window[k]);
    simulator.scan(poses[k], options.mount, time_s, raw, &labels);
    pipeline.add(raw, poses[k], beam_tags(labels));
    if (options.progress) options.progress(k + 1, poses.size());
  }
  pipeline.finish();
  result.sensor_totals = pipeline.stats().beams;
  result.scans = poses.size();
  detail::finish_rail_map(scene, options, pipeline, [&](const ElevationMap& map) {
    return swept_floor_area(map, poses, options.mount, options.urg, floor_m, options.swept_max_range_m);
  }, visibility, result);
  return result;
}

}  // namespace stridemap
