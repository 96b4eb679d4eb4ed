// The visibility clean-up's cost per scan against the map update it follows
// (docs/performance.md, docs/visibility.md): the walking, turning URG-sized
// scans of foothold_bench through MappingPipeline::add_planar, with the
// clean-up and the foothold layers each off and on, so that the
// budget (both together within 30 % of the update) can be read off.
#include <cmath>
#include <random>

#include <benchmark/benchmark.h>

#include "stridemap/pipeline/mapping_pipeline.hpp"

namespace {

using namespace stridemap;

// 682 beams over 240 deg of a floor with a low step (every 50th beam's first
// ten reach 80 % of the floor's range); beams that point up get no return.
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

void walk(benchmark::State& state, bool visibility, bool foothold, double turn_rad_per_scan) {
  PipelineOptions options;
  options.mapper.window_ahead_m = 0.3;
  options.visibility.enabled = visibility;
  options.foothold.enabled = foothold;
  // Computed after every scan, not when read (never here): the budget is per scan.
  options.foothold.update_every_scan = true;
  MappingPipeline pipeline(options);
  PlanarScan scan = urg_like_scan(options.mount);
  std::mt19937_64 rng(1);
  std::normal_distribution<double> tilt(0.0, 0.02);
  TrunkPose pose;
  const auto step = [&] {
    pose.x_m += 0.003;
    pose.yaw_rad += turn_rad_per_scan;
    pose.pitch_rad = tilt(rng);
    pose.roll_rad = tilt(rng);
    scan.time_s += 0.1;
    benchmark::DoNotOptimize(pipeline.add_planar(scan, pose));
  };
  for (int k = 0; k < 50; ++k) step();
  const std::size_t before = pipeline.stats().cells_contradicted;
  for (auto _ : state) step();
  state.counters["scans_per_s"] = benchmark::Counter(static_cast<double>(state.iterations()), benchmark::Counter::kIsRate);
  if (const VisibilityClearing* v = pipeline.integrator().visibility()) {
    state.counters["cells_crossed_last_scan"] = static_cast<double>(v->stats().cells_crossed);
    state.counters["beams_traced_last_scan"] = static_cast<double>(v->stats().beams_traced);
    state.counters["contradicted_per_scan"] =
        static_cast<double>(pipeline.stats().cells_contradicted - before) / static_cast<double>(state.iterations());
  }
}

void BM_UpdateOnly(benchmark::State& state) { walk(state, false, false, 0.002); }
BENCHMARK(BM_UpdateOnly);
void BM_UpdateWithVisibility(benchmark::State& state) { walk(state, true, false, 0.002); }
BENCHMARK(BM_UpdateWithVisibility);
void BM_UpdateWithFoothold(benchmark::State& state) { walk(state, false, true, 0.002); }
BENCHMARK(BM_UpdateWithFoothold);
void BM_UpdateWithFootholdAndVisibility(benchmark::State& state) { walk(state, true, true, 0.002); }
BENCHMARK(BM_UpdateWithFootholdAndVisibility);

// Walking straight ahead.
void BM_UpdateOnlyStraight(benchmark::State& state) { walk(state, false, false, 0.0); }
BENCHMARK(BM_UpdateOnlyStraight);
void BM_UpdateWithVisibilityStraight(benchmark::State& state) { walk(state, true, false, 0.0); }
BENCHMARK(BM_UpdateWithVisibilityStraight);

}  // namespace

BENCHMARK_MAIN();
