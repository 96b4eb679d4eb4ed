// One URG-04LX scan's whole way through the mapping pipeline (raw values,
// sensor model, no filters, map update), beside core_bench's
// BM_IntegrateScan, which starts from the converted scan
// (docs/performance.md).
#include <array>
#include <cmath>
#include <cstdint>
#include <optional>
#include <random>
#include <string_view>

#include <benchmark/benchmark.h>

#include "stridemap/core/stance_height.hpp"
#include "stridemap/pipeline/height_fusion_observer.hpp"
#include "stridemap/pipeline/mapping_pipeline.hpp"

namespace {

using namespace stridemap;

// A floor with a low step seen from the paper's mount, as core_bench's scan.
UrgRawScan urg_like_raw_scan(const UrgParameters& urg, const SensorMount& mount) {
  UrgRawScan raw;
  raw.first_step = urg.first_step;
  for (int step = urg.first_step; step <= urg.last_step; ++step) {
    const double down = std::cos(urg.step_angle_rad(step)) * std::sin(mount.pitch_rad);
    const double range = down > 0.1 ? mount.height_m / down * (step % 50 < 10 ? 0.8 : 1.0) : 0.0;
    raw.values_mm.push_back(range > 0.0 ? static_cast<std::uint32_t>(std::lround(range * 1000.0)) : 0u);
  }
  return raw;
}

// The pipeline as the CLI runs it; `options` changes one thing from the
// defaults. With `read_every` > 0 the map is read (map(): the lazy foothold
// layers brought up to date) after every read_every-th scan, as a planner
// slower than the scans reads it.
void pipeline_scans(benchmark::State& state, const PipelineOptions& options, int read_every = 0) {
  MappingPipeline pipeline(options);
  UrgRawScan raw = urg_like_raw_scan(options.urg, options.mount);
  std::mt19937_64 rng(1);
  std::normal_distribution<double> tilt(0.0, 0.02);
  TrunkPose pose;
  int scans = 0;
  for (auto _ : state) {
    pose.x_m += 0.003;
    pose.yaw_rad += 0.002;
    pose.pitch_rad = tilt(rng);
    pose.roll_rad = tilt(rng);
    raw.time_s += 0.1;
    benchmark::DoNotOptimize(pipeline.add(raw, pose));
    if (read_every > 0 && ++scans % read_every == 0) benchmark::DoNotOptimize(&pipeline.map());
  }
  state.counters["scans_per_s"] = benchmark::Counter(static_cast<double>(state.iterations()), benchmark::Counter::kIsRate);
}

PipelineOptions bench_options() {
  PipelineOptions options;
  options.mapper.window_ahead_m = 0.3;
  return options;
}

// Defaults: no scan filters, foothold layers noted per scan and computed
// when the map is read (never here).
void BM_PipelineUrgScan(benchmark::State& state) { pipeline_scans(state, bench_options()); }
BENCHMARK(BM_PipelineUrgScan);

// The map read after every 10th scan: a 1 Hz planner on a 10 Hz URG.
void BM_PipelineUrgScanFootholdEvery10(benchmark::State& state) { pipeline_scans(state, bench_options(), 10); }
BENCHMARK(BM_PipelineUrgScanFootholdEvery10);

// The map read after every scan: the whole cost of current layers.
void BM_PipelineUrgScanFootholdEvery1(benchmark::State& state) { pipeline_scans(state, bench_options(), 1); }
BENCHMARK(BM_PipelineUrgScanFootholdEvery1);

// foothold.update_every_scan: the layers computed after every scan, read or not.
void BM_PipelineUrgScanEagerFoothold(benchmark::State& state) {
  PipelineOptions options = bench_options();
  options.foothold.update_every_scan = true;
  pipeline_scans(state, options);
}
BENCHMARK(BM_PipelineUrgScanEagerFoothold);

// Without the foothold layers: what the scan's own way costs.
void BM_PipelineUrgScanNoFoothold(benchmark::State& state) {
  PipelineOptions options = bench_options();
  options.foothold.enabled = false;
  pipeline_scans(state, options);
}
BENCHMARK(BM_PipelineUrgScanNoFoothold);

// A walking robot's loop (docs/walking.md): the fused height layers fed
// from every scan (HeightFusionObserver) and, before each scan, the trunk's
// height read under six stance feet a little ahead of the sensor's origin.
void BM_PipelineUrgScanFusedHeights(benchmark::State& state) {
  PipelineOptions options = bench_options();
  declare_height_fusion_layers(options.mapper.grid);
  MappingPipeline pipeline(options);
  const HeightFusionObserver fusion(pipeline);
  const ElevationMap& map = pipeline.mapper().map();
  const StanceHeightReader reader(map);
  UrgRawScan raw = urg_like_raw_scan(options.urg, options.mount);
  TrunkPose pose;
  std::array<StanceFoot, 6> feet{};
  for (auto _ : state) {
    for (std::size_t f = 0; f < feet.size(); ++f) {
      feet[f] = {pose.x_m + 0.3 + 0.05 * static_cast<double>(f % 3), 0.08 * (f < 3 ? 1.0 : -1.0), 0.2};
    }
    benchmark::DoNotOptimize(reader.read(map, feet));
    pose.x_m += 0.003;
    raw.time_s += 0.1;
    benchmark::DoNotOptimize(pipeline.add(raw, pose));
  }
}
BENCHMARK(BM_PipelineUrgScanFusedHeights);

// The same loop on planar scans, as the ROS node hands a LaserScan to the
// pipeline (MappingPipeline::add_planar), with and without the fused layers.
void planar_scans(benchmark::State& state, bool fused) {
  PipelineOptions options = bench_options();
  if (fused) declare_height_fusion_layers(options.mapper.grid);
  MappingPipeline pipeline(options);
  std::optional<HeightFusionObserver> fusion;
  std::optional<StanceHeightReader> reader;
  const ElevationMap& map = pipeline.mapper().map();
  if (fused) {
    fusion.emplace(pipeline);
    reader.emplace(map);
  }
  PlanarScan scan;
  UrgModel(options.urg).to_planar_scan(urg_like_raw_scan(options.urg, options.mount), scan);
  TrunkPose pose;
  std::array<StanceFoot, 6> feet{};
  for (auto _ : state) {
    if (fused) {
      for (std::size_t f = 0; f < feet.size(); ++f) {
        feet[f] = {pose.x_m + 0.3 + 0.05 * static_cast<double>(f % 3), 0.08 * (f < 3 ? 1.0 : -1.0), 0.2};
      }
      benchmark::DoNotOptimize(reader->read(map, feet));
    }
    pose.x_m += 0.003;
    scan.time_s += 0.1;
    benchmark::DoNotOptimize(pipeline.add_planar(scan, pose));
  }
}
BENCHMARK_CAPTURE(planar_scans, plain, false)->Name("BM_PipelinePlanarScan");
BENCHMARK_CAPTURE(planar_scans, fused, true)->Name("BM_PipelinePlanarScanFusedHeights");

// With scan filters by their CLI name ("paper" or "urg"), layers as default.
void pipeline_filtered(benchmark::State& state, const char* filters, bool foothold) {
  PipelineOptions options = bench_options();
  options.filters = parse_scan_filter_list(std::string_view(filters));
  options.foothold.enabled = foothold;
  pipeline_scans(state, options);
}
BENCHMARK_CAPTURE(pipeline_filtered, paper, "paper", true)->Name("BM_PipelineUrgScanFilters/paper");
BENCHMARK_CAPTURE(pipeline_filtered, urg, "urg", true)->Name("BM_PipelineUrgScanFilters/urg");
BENCHMARK_CAPTURE(pipeline_filtered, paper_no_foothold, "paper", false)
    ->Name("BM_PipelineUrgScanFiltersNoFoothold/paper");
BENCHMARK_CAPTURE(pipeline_filtered, urg_no_foothold, "urg", false)->Name("BM_PipelineUrgScanFiltersNoFoothold/urg");

// The per-point path alone, raw millimetres to the map (1 cm cells, 100 x
// 100): `packed` converts straight into the mapper's packed beams
// (UrgModel::to_beams), `planar` through a PlanarScan (to_planar_scan +
// integrate), as the pipeline does when scan filters run.
void point_path(benchmark::State& state, bool packed) {
  PipelineOptions options;
  options.mapper.window_ahead_m = 0.3;
  const UrgModel model(options.urg);
  TerrainMapper mapper(options.mapper, options.mount);
  UrgRawScan raw = urg_like_raw_scan(options.urg, options.mount);
  std::mt19937_64 rng(1);
  std::normal_distribution<double> tilt(0.0, 0.02);
  TrunkPose pose;
  PlanarBeams beams;
  PlanarScan scan;
  std::size_t valid = 0;
  for (auto _ : state) {
    pose.x_m += 0.003;
    pose.yaw_rad += 0.002;
    pose.pitch_rad = tilt(rng);
    pose.roll_rad = tilt(rng);
    raw.time_s += 0.1;
    const ScanStats stats = packed ? (model.to_beams(raw, beams), mapper.integrate(beams, pose))
                                   : (model.to_planar_scan(raw, scan), mapper.integrate(scan, pose));
    valid += stats.integrated + stats.outside_map;
  }
  state.counters["points_per_s"] = benchmark::Counter(static_cast<double>(valid), benchmark::Counter::kIsRate);
}
void BM_UrgPointPathPacked(benchmark::State& state) { point_path(state, true); }
void BM_UrgPointPathPlanar(benchmark::State& state) { point_path(state, false); }
BENCHMARK(BM_UrgPointPathPacked);
BENCHMARK(BM_UrgPointPathPlanar);

}  // namespace

BENCHMARK_MAIN();
