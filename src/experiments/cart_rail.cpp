#include "stridemap/experiments/cart_rail.hpp"

#include <algorithm>
#include <array>
#include <functional>
#include <cmath>
#include <limits>
#include <memory>

#include "cart_rail_internal.hpp"
#include "stridemap/core/error.hpp"
#include "stridemap/core/sensor_transform.hpp"

namespace stridemap {
namespace {

// The ideal filter of CartRailOptions::drop_labelled_mixed: one label per beam.
void drop_labelled_mixed_beams(const std::vector<BeamLabel>& labels, PlanarScan& scan) {
  for (std::size_t i = 0; i < labels.size() && i < scan.range_m.size(); ++i) {
    if (labels[i] == BeamLabel::mixed) scan.range_m[i] = std::numeric_limits<double>::quiet_NaN();
  }
}

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

TerrainMapper make_rail_mapper(const Eigen::Vector2d& lo, const Eigen::Vector2d& hi, const CartRailOptions& options,
                               const SensorMount& mount) {
  // A fixed window around everything the sensor can sweep, so the whole
  // scene stays in the map (the test bed, unlike the robot, need not forget).
  MapperOptions mapper_options;
  mapper_options.follow_robot = false;
  mapper_options.update = options.update;
  const double margin_m = 0.1;
  const int cells = options.cells_per_side > 0
                        ? options.cells_per_side
                        : cells_per_side_to_cover((hi - lo).maxCoeff() + 2 * margin_m, options.cell_size_m);
  mapper_options.grid = {cells, options.cell_size_m};
  TerrainMapper mapper(mapper_options, mount);
  const Eigen::Vector2d centre = 0.5 * (lo + hi);
  mapper.map().move_to(centre.x(), centre.y());
  return mapper;
}

void finish_rail_map(const Scene& scene, const CartRailOptions& options, TerrainMapper& mapper,
                     const std::function<CellMask(const ElevationMap&)>& swept_area, CartRailResult& result) {
  result.mapper_totals = mapper.totals();
  switch (options.map_filter) {
    case MapFilter::none: break;
    case MapFilter::fill: result.filled_cells = WeightedMedianFill(options.fill).apply(mapper.map()); break;
    case MapFilter::cas: {
      const CasResult cas = CasFilter(options.cas).apply(mapper.map());
      result.filled_cells = cas.filled;
      result.cas_removed_cells = cas.removed;
      break;
    }
  }
  result.snapshot = snapshot_with_truth(mapper.map(), scene);
  result.swept_area = swept_area(mapper.map());
  result.score = score_map(result.snapshot, result.swept_area, options.score);
  result.objects = measure_objects(result.snapshot, scene, options.objects);
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
  TerrainMapper mapper = detail::make_rail_mapper(lo, hi, options, options.mount);

  UrgModel sensor(options.urg, options.calibration);
  std::unique_ptr<BeamModel> beam_model;
  if (options.mixed_pixels) {
    beam_model = std::make_unique<FootprintBeamModel>(options.footprint);
  } else {
    beam_model = std::make_unique<SingleRayBeamModel>();
  }
  UrgSimulator simulator(scene, options.urg, options.sim, options.seed, std::move(beam_model));
  ScanFilterChain filters(options.filters, options.filter_options);
  UrgRawScan raw;
  PlanarScan scan, filtered;
  // The chain may hand back the previous scan: keep the labels of the last
  // two scans, indexed by scan number, to score the one that comes out.
  std::array<std::vector<BeamLabel>, 2> labels;
  std::size_t scans_out = 0;
  const auto integrate_output = [&] {
    const std::vector<BeamLabel>& truth = labels[scans_out % 2];
    const std::vector<std::uint8_t>& removed = filters.removed_by_any();
    for (std::size_t i = 0; i < truth.size(); ++i) {
      const bool was_removed = (i < removed.size() && removed[i]) ||
                               (options.drop_labelled_mixed && truth[i] == BeamLabel::mixed);
      switch (truth[i]) {
        case BeamLabel::clean: ++result.beams.clean; result.beams.clean_removed += was_removed; break;
        case BeamLabel::mixed: ++result.beams.mixed; result.beams.mixed_removed += was_removed; break;
        case BeamLabel::dropped: ++result.beams.dropped; break;
      }
    }
    mapper.integrate(filtered, poses[scans_out]);
    ++scans_out;
  };
  for (std::size_t k = 0; k < poses.size(); ++k) {
    const double time_s = static_cast<double>(k) * options.urg.scan_period_s;
    simulator.scan(poses[k], options.mount, time_s, raw, &labels[k % 2]);
    const UrgConversionStats converted = sensor.to_planar_scan(raw, scan);
    if (options.drop_labelled_mixed) drop_labelled_mixed_beams(labels[k % 2], scan);
    result.sensor_totals.valid += converted.valid;
    result.sensor_totals.error_codes += converted.error_codes;
    result.sensor_totals.beyond_max_range += converted.beyond_max_range;
    if (filters.push(scan, filtered)) integrate_output();
  }
  if (filters.flush(filtered)) integrate_output();
  result.scans = poses.size();
  detail::finish_rail_map(scene, options, mapper, [&](const ElevationMap& map) {
    return swept_floor_area(map, poses, options.mount, options.urg, floor_m, options.swept_max_range_m);
  }, result);
  return result;
}

}  // namespace stridemap
