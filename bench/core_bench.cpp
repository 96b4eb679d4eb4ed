// Map update and fill-in throughput on one core (docs/performance.md).
#include <cmath>
#include <optional>
#include <random>

#include <benchmark/benchmark.h>

#include "stridemap/core/cas_filter.hpp"
#include "stridemap/core/terrain_mapper.hpp"
#include "stridemap/core/weighted_median_fill.hpp"

namespace {

using namespace stridemap;

// A URG-04LX-sized scan (682 beams over 240 deg) of a floor with a low step,
// as the paper's mount sees it; beams that point up get no return (NaN).
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

void integrate_scans(benchmark::State& state, const SensorMount& mount, std::optional<double> trunk_z_m) {
  MapperOptions options;
  options.window_ahead_m = 0.3;
  TerrainMapper mapper(options, mount);
  PlanarScan scan = urg_like_scan(mount);
  std::mt19937_64 rng(1);
  std::normal_distribution<double> tilt(0.0, 0.02);
  TrunkPose pose;
  pose.z_m = trunk_z_m;
  std::size_t valid = 0;
  for (double r : scan.range_m) valid += std::isfinite(r) ? 1 : 0;
  for (auto _ : state) {
    pose.x_m += 0.003;  // a slow walk: the window moves every few scans
    pose.yaw_rad += 0.002;
    pose.pitch_rad = tilt(rng);
    pose.roll_rad = tilt(rng);
    scan.time_s += 0.1;  // the mapper rejects a scan that is not newer than the last
    benchmark::DoNotOptimize(mapper.integrate(scan, pose));
  }
  state.counters["points_per_s"] =
      benchmark::Counter(static_cast<double>(valid * state.iterations()), benchmark::Counter::kIsRate);
  state.counters["scans_per_s"] = benchmark::Counter(static_cast<double>(state.iterations()), benchmark::Counter::kIsRate);
}

void BM_IntegrateScan(benchmark::State& state) { integrate_scans(state, SensorMount{}, std::nullopt); }
BENCHMARK(BM_IntegrateScan);

// The full mount (roll and yaw) and a pose with z: the composed rotation and
// the lever-arm partials, once per scan; the per-point work is the same.
void BM_IntegrateScanFullMount(benchmark::State& state) {
  SensorMount mount;
  mount.roll_rad = 0.087;
  mount.yaw_rad = 0.17;
  mount.forward_offset_m = 0.1;
  integrate_scans(state, mount, 0.05);
}
BENCHMARK(BM_IntegrateScanFullMount);

void BM_IntegratePoints(benchmark::State& state) {
  MapperOptions options;
  options.follow_robot = false;
  TerrainMapper mapper(options, SensorMount{});
  std::vector<MapPoint> points(4096);
  std::mt19937_64 rng(2);
  std::uniform_real_distribution<double> xy(-0.5, 0.5);
  for (MapPoint& p : points) p = {xy(rng), xy(rng), 0.01 * xy(rng), 0.01};
  for (auto _ : state) benchmark::DoNotOptimize(mapper.integrate_points(points, TrunkPose{}));
  state.counters["points_per_s"] =
      benchmark::Counter(static_cast<double>(points.size() * state.iterations()), benchmark::Counter::kIsRate);
}
BENCHMARK(BM_IntegratePoints);

// 70 % of cells measured on a gentle slope with noise, the rest unknown in
// scattered holes; now and then a lone spike of low certainty (CAS's prey).
ElevationMap scattered_map(int n) {
  ElevationMap map({n, 0.01});
  std::mt19937_64 rng(3);
  std::uniform_real_distribution<double> u(0.0, 1.0);
  for (int i = 0; i < n; ++i) {
    for (int j = 0; j < n; ++j) {
      if (u(rng) < 0.3) continue;
      const std::size_t s = map.slot(map.cell_at_local(i, j));
      const bool spike = u(rng) < 0.02;
      map.elevation_data()[s] = static_cast<float>(0.001 * i + 0.005 * u(rng) + (spike ? 0.1 : 0.0));
      map.certainty_data()[s] = spike ? 3.0f : static_cast<float>(3 * (1 + static_cast<int>(u(rng) * 5)));
      map.state_data()[s] = static_cast<std::uint8_t>(CellState::measured);
    }
  }
  return map;
}

void BM_WeightedMedianFill(benchmark::State& state) {
  const int n = static_cast<int>(state.range(0));
  const ElevationMap original = scattered_map(n);
  ElevationMap map = original;
  WeightedMedianFill fill;
  for (auto _ : state) {
    state.PauseTiming();
    map = original;  // the fill changes the map; each round starts from the same one
    state.ResumeTiming();
    benchmark::DoNotOptimize(fill.apply(map));
  }
  state.counters["cells_per_s"] =
      benchmark::Counter(static_cast<double>(n) * n * static_cast<double>(state.iterations()), benchmark::Counter::kIsRate);
}
BENCHMARK(BM_WeightedMedianFill)->Arg(100)->Arg(200);

// The CAS filter (removal, then the fill-in) on the same maps.
void BM_CasFilter(benchmark::State& state) {
  const int n = static_cast<int>(state.range(0));
  const ElevationMap original = scattered_map(n);
  ElevationMap map = original;
  CasFilter cas;
  for (auto _ : state) {
    state.PauseTiming();
    map = original;
    state.ResumeTiming();
    benchmark::DoNotOptimize(cas.apply(map));
  }
}
BENCHMARK(BM_CasFilter)->Arg(100);

void BM_MoveWindowOneCell(benchmark::State& state) {
  ElevationMap map({100, 0.01});
  std::int64_t k = 0;
  for (auto _ : state) {
    ++k;
    benchmark::DoNotOptimize(map.move_corner_to({map.min_cell().x + 1, map.min_cell().y + (k % 2)}));
  }
}
BENCHMARK(BM_MoveWindowOneCell);

// Moves by `range(0)` cells along one axis (x: whole rows of the storage,
// y: a column in every row); "s_per_cell" is the time per entering cell.
void move_window(benchmark::State& state, bool along_x) {
  ElevationMap map({100, 0.01});
  const std::int64_t step = state.range(0);
  std::size_t cells = 0;
  for (auto _ : state) {
    const CellIndex c = map.min_cell();
    cells += map.move_corner_to({c.x + (along_x ? step : 0), c.y + (along_x ? 0 : step)});
  }
  state.counters["s_per_cell"] =
      benchmark::Counter(static_cast<double>(cells), benchmark::Counter::kIsRate | benchmark::Counter::kInvert);
}
void BM_MoveWindowX(benchmark::State& state) { move_window(state, true); }
void BM_MoveWindowY(benchmark::State& state) { move_window(state, false); }
BENCHMARK(BM_MoveWindowX)->Arg(1)->Arg(10)->Arg(99);
BENCHMARK(BM_MoveWindowY)->Arg(1)->Arg(10)->Arg(99);

void BM_ClearMap(benchmark::State& state) {
  ElevationMap map({100, 0.01});
  for (auto _ : state) {
    map.clear();
    benchmark::DoNotOptimize(map.elevation_data());
  }
}
BENCHMARK(BM_ClearMap);

}  // namespace

BENCHMARK_MAIN();
