// The foothold layers' cost per scan against the map update they follow
// (docs/performance.md, docs/foothold.md): the same walking, turning URG
// scans as core_bench's BM_IntegrateScan, without the foothold layers, with
// them read after every scan and read after every 10th, and a
// recomputation of the whole window for scale.
#include <algorithm>
#include <cmath>
#include <random>

#include <benchmark/benchmark.h>

#include "stridemap/core/foothold.hpp"
#include "stridemap/core/terrain_mapper.hpp"

namespace {

using namespace stridemap;

// A URG-04LX-sized scan (682 beams over 240 deg) of a floor with a low step,
// as core_bench's: beams that point up get no return (NaN).
PlanarScan urg_like_scan(const SensorMount& mount) {
  PlanarScan scan;
  scan.resize(682);
  for (std::size_t i = 0; i < scan.size(); ++i) {
    const double t = (static_cast<double>(i) + 44.0 - 384.0) * 2.0 * M_PI / 1024.0;
    const double down = std::cos(t) * std::sin(mount.pitch_rad);
    scan.angle_rad[i] = t;
    scan.range_m[i] = down > 0.1 ? mount.height_m / down * (i % 50 < 10 ? 0.8 : 1.0) : NAN;
    scan.range_error_m[i] = 0.01;
  }
  return scan;
}

// read_every: 0 for no foothold layers; k to note every scan's changed rows
// and bring the layers up to date after every k-th scan (1: eagerly, as
// update_every_scan; 10: a 1 Hz planner reading a 10 Hz URG's map).
void walk(benchmark::State& state, int read_every, double turn_rad_per_scan) {
  MapperOptions options;
  options.window_ahead_m = 0.3;
  const SensorMount mount;
  TerrainMapper mapper(options, mount);
  FootholdLayers foothold(mapper.map(), FootholdOptions{});
  foothold.recompute_all(mapper.map());
  PlanarScan scan = urg_like_scan(mount);
  std::mt19937_64 rng(1);
  std::normal_distribution<double> tilt(0.0, 0.02);
  TrunkPose pose;
  std::size_t scans = 0, geometry_cells = 0, edge_cells = 0, score_cells = 0;
  const auto step = [&] {
    pose.x_m += 0.003;  // a slow walk: the window moves every few scans
    pose.yaw_rad += turn_rad_per_scan;
    pose.pitch_rad = tilt(rng);
    pose.roll_rad = tilt(rng);
    scan.time_s += 0.1;
    benchmark::DoNotOptimize(mapper.integrate(scan, pose));
    if (read_every > 0) {
      foothold.note(mapper.map(), mapper.changed_rows());
      if (++scans % static_cast<std::size_t>(read_every) == 0) {
        foothold.refresh(mapper.map());
        geometry_cells += foothold.last_geometry_cells();
        edge_cells += foothold.last_edge_cells();
        score_cells += foothold.last_score_cells();
      }
    }
    mapper.clear_changed_cells();
  };
  // Warm up: a map with history, as in a walk.
  for (int k = 0; k < 50; ++k) step();
  scans = geometry_cells = edge_cells = score_cells = 0;
  for (auto _ : state) step();
  state.counters["scans_per_s"] = benchmark::Counter(static_cast<double>(state.iterations()), benchmark::Counter::kIsRate);
  if (read_every > 0) {
    const double reads = std::max(1.0, static_cast<double>(scans / static_cast<std::size_t>(read_every)));
    state.counters["geometry_cells_per_read"] = static_cast<double>(geometry_cells) / reads;
    state.counters["edge_cells_per_read"] = static_cast<double>(edge_cells) / reads;
    state.counters["score_cells_per_read"] = static_cast<double>(score_cells) / reads;
  }
}

// Turning as core_bench's BM_IntegrateScan: the heading sweeps round, so the
// scan line lies diagonally across the window most of the time.
void BM_ScanMapUpdateOnly(benchmark::State& state) { walk(state, 0, 0.002); }
BENCHMARK(BM_ScanMapUpdateOnly);

// The layers read (brought up to date) after every scan.
void BM_ScanMapUpdateWithFoothold(benchmark::State& state) { walk(state, 1, 0.002); }
BENCHMARK(BM_ScanMapUpdateWithFoothold);

// Read after every 10th scan: the per-scan cost amortised.
void BM_ScanMapUpdateWithFootholdRead10(benchmark::State& state) { walk(state, 10, 0.002); }
BENCHMARK(BM_ScanMapUpdateWithFootholdRead10);

// Walking straight ahead: the scan line stays across the heading.
void BM_ScanMapUpdateOnlyStraight(benchmark::State& state) { walk(state, 0, 0.0); }
BENCHMARK(BM_ScanMapUpdateOnlyStraight);

void BM_ScanMapUpdateWithFootholdStraight(benchmark::State& state) { walk(state, 1, 0.0); }
BENCHMARK(BM_ScanMapUpdateWithFootholdStraight);

void BM_ScanMapUpdateWithFootholdRead10Straight(benchmark::State& state) { walk(state, 10, 0.0); }
BENCHMARK(BM_ScanMapUpdateWithFootholdRead10Straight);

// Every cell of the paper's 100 x 100 window, mostly known: what an update
// would cost without the changed box.
void BM_FootholdRecomputeWindow(benchmark::State& state) {
  ElevationMap map(GridOptions{static_cast<int>(state.range(0)), 0.01});
  std::mt19937_64 rng(2);
  std::uniform_real_distribution<float> z(0.0f, 0.05f);
  for (int i = 0; i < map.cells_per_side(); ++i) {
    for (int j = 0; j < map.cells_per_side(); ++j) {
      const std::size_t s = map.slot(map.cell_at_local(i, j));
      if ((i + 3 * j) % 7 == 0) continue;
      map.elevation_data()[s] = z(rng);
      map.certainty_data()[s] = 6.0f;
      map.state_data()[s] = 1;
    }
  }
  FootholdLayers foothold(map, FootholdOptions{});
  for (auto _ : state) {
    foothold.recompute_all(map);
    benchmark::ClobberMemory();
  }
}
BENCHMARK(BM_FootholdRecomputeWindow)->Arg(100);

}  // namespace

BENCHMARK_MAIN();
