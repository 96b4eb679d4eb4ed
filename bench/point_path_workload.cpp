// The fixed workload of `make bench-instructions` (tools/bench-instructions.sh):
// raw URG-04LX scans through the whole per-point path (raw millimetres ->
// calibrated beams -> the map), 1 cm cells, 100 x 100 window, the robot
// walking and turning. Run under callgrind, which counts the instructions
// of the conversion and the integration separately; it prints the valid
// points so that the script can divide, and a digest of every layer's bytes
// and of the changed rows after each scan, so that two builds' maps can be
// compared bit for bit.
//
//   point_path_workload [packed|packed-walk|planar|pipeline|pipeline-paper|pipeline-walk|pipeline-foothold|
//                        pipeline-foothold-every10|walk-every10|pipeline-visibility|walk-visibility] [scans]
//     packed: UrgModel::to_beams + TerrainMapper::integrate(PlanarBeams) (default)
//     planar: UrgModel::to_planar_scan + TerrainMapper::integrate(PlanarScan)
//     pipeline: ScanIntegrator::push, no scan filters (its packed route)
//     pipeline-paper: the same with the paper's scan filters
//     pipeline-walk: pipeline-paper on the scans of make bench-compare's walk
//       (bench/compare.cpp), whose rocks give the line extraction more to fit
//       than the floor; simulating them is counted apart (UrgSimulator::scan)
//     pipeline-foothold: MappingPipeline::add with foothold.update_every_scan
//       (the foothold layers refreshed after every scan, as they are layers
//       of the digest read from mapper().map(); otherwise its defaults)
//     pipeline-foothold-every10: MappingPipeline::add with its defaults and
//       map() read after every 10th scan (pipeline_bench's FootholdEvery10)
//     packed-walk, walk-every10: packed and pipeline-foothold-every10 on the
//       walk's scans, the two sides of make bench-compare's "map read every
//       10th scan" ratio
//     pipeline-visibility: MappingPipeline::add with its defaults and the
//       visibility clean-up on; the floor's tilted scans give it cells to
//       contradict, and the digest covers what it traced, contradicted and
//       cleared; walk-visibility: the same on the walk's scans (true poses:
//       nothing to contradict, so the clean-up's cost on a clean map)
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <random>
#include <string>
#include <vector>

#include "stridemap/config/scene_yaml.hpp"
#include "stridemap/core/terrain_mapper.hpp"
#include "stridemap/pipeline/mapping_pipeline.hpp"
#include "stridemap/sensors/urg04lx.hpp"
#include "stridemap/sim/urg_simulator.hpp"
#include "stridemap/sim/walk_motion.hpp"
#include "test_paths.hpp"

using namespace stridemap;

namespace {

// A floor with a low step seen from the paper's mount (as pipeline_bench's),
// with a little range noise so that cells see plausible and implausible
// readings alike.
UrgRawScan floor_scan(const UrgParameters& urg, const SensorMount& mount, std::mt19937_64& rng) {
  std::normal_distribution<double> noise_mm(0.0, 3.0);
  UrgRawScan raw;
  raw.first_step = urg.first_step;
  for (int step = urg.first_step; step <= urg.last_step; ++step) {
    const double down = std::cos(urg.step_angle_rad(step)) * std::sin(mount.pitch_rad);
    const double range_mm = down > 0.1 ? 1000.0 * mount.height_m / down * (step % 50 < 10 ? 0.8 : 1.0) : 0.0;
    raw.values_mm.push_back(range_mm > 0.0 ? static_cast<std::uint32_t>(std::lround(range_mm + noise_mm(rng))) : 0u);
  }
  return raw;
}

}  // namespace

int main(int argc, char** argv) {
  const int scans = argc > 2 ? std::atoi(argv[2]) : 750;
  const std::string mode_arg = argc > 1 ? argv[1] : "packed";
  const bool walk = mode_arg == "pipeline-walk" || mode_arg == "packed-walk" || mode_arg == "walk-every10" ||
                    mode_arg == "walk-visibility";
  // The walk's variants run as their floor counterparts on the walk's scans.
  const std::string mode = mode_arg == "packed-walk"    ? "packed"
                           : mode_arg == "walk-every10" ? "pipeline-foothold-every10"
                           : mode_arg == "walk-visibility" ? "pipeline-visibility"
                                                        : mode_arg;
  if ((mode != "packed" && mode != "planar" && mode != "pipeline" && mode != "pipeline-paper" &&
       mode != "pipeline-walk" && mode != "pipeline-foothold" && mode != "pipeline-foothold-every10" &&
       mode != "pipeline-visibility") ||
      scans < 1) {
    std::fprintf(stderr,
                 "usage: point_path_workload [packed|packed-walk|planar|pipeline|pipeline-paper|pipeline-walk|"
                 "pipeline-foothold|pipeline-foothold-every10|walk-every10|pipeline-visibility|walk-visibility] "
                 "[scans >= 1]\n");
    return 2;
  }
  const UrgParameters urg;
  const SensorMount mount;
  const UrgModel model(urg);
  MapperOptions options;
  options.window_ahead_m = 0.3;
  PipelineOptions pipeline_options;
  pipeline_options.mapper = options;
  pipeline_options.urg = urg;
  pipeline_options.mount = mount;
  if (mode == "pipeline-paper" || mode == "pipeline-walk") {
    pipeline_options.filters = parse_scan_filter_list(std::string_view("paper"));
  }
  const bool every10 = mode == "pipeline-foothold-every10";
  const bool visibility = mode == "pipeline-visibility";
  pipeline_options.foothold.update_every_scan = !every10 && !visibility;
  pipeline_options.visibility.enabled = visibility;
  // The modes whose scans go through MappingPipeline::add, which clears its own changed rows.
  const bool whole_pipeline = mode == "pipeline-foothold" || every10 || visibility;
  ScanIntegrator integrator(pipeline_options);
  MappingPipeline pipeline(pipeline_options);
  TerrainMapper own_mapper(options, mount);
  TerrainMapper& mapper = whole_pipeline ? pipeline.mapper() : own_mapper;
  std::mt19937_64 rng(1);
  std::normal_distribution<double> tilt(0.0, 0.02);
  // A handful of different scans, made before the measured loop.
  std::vector<UrgRawScan> raw_scans;
  std::vector<TrunkPose> walk_poses;
  if (walk) {
    // As bench/compare.cpp makes them: true poses, seed 1, 0.1 s apart.
    const Scene scene = load_scene_yaml(std::string(STRIDEMAP_SOURCE_DIR) + "/scenes/rocky_mockup.yaml");
    const WalkMotion motion(scene);
    UrgSimulator simulator(scene, urg, UrgSimOptions{}, 1);
    raw_scans.resize(static_cast<std::size_t>(scans));
    for (std::size_t k = 0; k < raw_scans.size(); ++k) {
      walk_poses.push_back(motion.pose_at(std::min(0.1 * static_cast<double>(k), motion.duration_s())));
      simulator.scan(walk_poses.back(), mount, 0.1 * static_cast<double>(k + 1), raw_scans[k]);
    }
  } else {
    for (int k = 0; k < 8; ++k) raw_scans.push_back(floor_scan(urg, mount, rng));
  }
  PlanarScan planar;
  PlanarBeams beams;
  TrunkPose pose;
  std::size_t valid = 0;
  std::size_t contradicted = 0;
  std::uint64_t digest = 1469598103934665603ull;  // FNV-1a, 64 bits
  const auto mix = [&digest](const void* bytes, std::size_t size) {
    const auto* b = static_cast<const unsigned char*>(bytes);
    for (std::size_t i = 0; i < size; ++i) digest = (digest ^ b[i]) * 1099511628211ull;
  };
  for (int k = 0; k < scans; ++k) {
    UrgRawScan& raw = raw_scans[static_cast<std::size_t>(k) % raw_scans.size()];
    pose.x_m += 0.003;
    pose.yaw_rad += 0.002;
    pose.pitch_rad = tilt(rng);
    pose.roll_rad = tilt(rng);
    raw.time_s = 0.1 * (k + 1);
    if (walk) pose = walk_poses[static_cast<std::size_t>(k)];
    ScanStats stats;
    if (mode == "packed") {
      model.to_beams(raw, beams);
      stats = mapper.integrate(beams, pose);
    } else if (mode == "planar") {
      model.to_planar_scan(raw, planar);
      stats = mapper.integrate(planar, pose);
    } else if (mode == "pipeline-foothold" || visibility) {
      stats = pipeline.add(raw, pose).stats;
    } else if (every10) {
      stats = pipeline.add(raw, pose).stats;
      if ((k + 1) % 10 == 0) pipeline.map();
    } else {
      stats = integrator.push(raw, pose, mapper).stats;
    }
    valid += stats.integrated + stats.outside_map;
    const CellBox& rows = mapper.changed_rows().bounds();
    if (!rows.empty()) {
      std::int64_t lo = 0, hi = 0;
      for (std::int64_t x = rows.min.x; x <= rows.max.x; ++x) {
        if (mapper.changed_rows().span(x, lo, hi)) mix(&lo, sizeof lo), mix(&hi, sizeof hi);
      }
    }
    const std::size_t counts[] = {stats.integrated, stats.outside_map, stats.first, stats.plausible,
                                  stats.implausible, stats.replaced};
    mix(counts, sizeof counts);
    if (const VisibilityClearing* v = pipeline.integrator().visibility(); visibility && v != nullptr) {
      // What the clean-up did, not how: a faster walk over the same cells keeps the digest.
      const VisibilityStats& done = v->stats();
      const std::size_t seen[] = {done.beams_traced, done.cells_contradicted, done.cells_cleared};
      mix(seen, sizeof seen);
      contradicted += done.cells_contradicted;
    }
    if (!whole_pipeline) mapper.clear_changed_cells();
  }
  // The layers as a reader sees them (every10: refreshed for the last scans).
  const ElevationMap& map = every10 || visibility ? pipeline.map() : mapper.map();
  const std::size_t cells = static_cast<std::size_t>(map.cells_per_side()) * map.cells_per_side();
  for (std::size_t layer = 0; layer < map.layer_count(); ++layer) {
    mix(map.layer_bytes(layer), cells * layer_type_bytes(map.layer_spec(layer).type));
  }
  std::printf("scans %d valid_points %zu cells_measured_certainty_sum %.1f map_digest %016llx\n", scans, valid,
              [&] {
                double sum = 0.0;
                const ElevationMap& map = mapper.map();
                const std::size_t n = static_cast<std::size_t>(map.cells_per_side()) * map.cells_per_side();
                for (std::size_t s = 0; s < n; ++s) sum += map.certainty_data()[s];
                return sum;
              }(),
              static_cast<unsigned long long>(digest));
  if (visibility) std::printf("cells_contradicted %zu\n", contradicted);
  return 0;
}
