// Time per 683-beam scan of each scan filter and of filter chains, on a
// synthetic sequence from a URG-04LX tilted 35 deg down at 0.26 m, driving
// towards a 0.2 x 0.2 x 0.1 m box at 1 cm per scan, with range noise, mixed
// points at depth jumps and a trailing group of mixed points whenever the scan
// plane crosses the box's top edge.
#include <benchmark/benchmark.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>
#include <random>
#include <vector>

#include "stridemap/preprocess/scan_filter_chain.hpp"

namespace {

using stridemap::PlanarScan;

constexpr double pi = 3.14159265358979323846;
constexpr std::size_t urg_beams = 683;
constexpr double sensor_height_m = 0.26;
constexpr double sensor_pitch_rad = 35.0 * pi / 180.0;
constexpr double box_depth_m = 0.2;
constexpr double box_half_width_m = 0.1;
constexpr double box_height_m = 0.1;
constexpr double max_range_m = 4.0;

/// Distance along the beam to the ground or the box, NaN if beyond range.
double cast(double beam_angle_rad, double box_front_m) {
  const double dx = std::cos(beam_angle_rad) * std::cos(sensor_pitch_rad);
  const double dy = std::sin(beam_angle_rad);
  const double dz = -std::cos(beam_angle_rad) * std::sin(sensor_pitch_rad);
  double best = dz < 0.0 ? sensor_height_m / -dz : std::numeric_limits<double>::infinity();
  // Slab test against the box [front, front + depth] x [-w, w] x [0, h].
  double enter = 0.0;
  double leave = best;
  const auto slab = [&](double origin, double direction, double low, double high) {
    if (std::abs(direction) < 1e-12) {
      if (origin < low || origin > high) leave = -1.0;
      return;
    }
    double t0 = (low - origin) / direction;
    double t1 = (high - origin) / direction;
    if (t0 > t1) std::swap(t0, t1);
    enter = std::max(enter, t0);
    leave = std::min(leave, t1);
  };
  slab(0.0, dx, box_front_m, box_front_m + box_depth_m);
  slab(0.0, dy, -box_half_width_m, box_half_width_m);
  slab(sensor_height_m, dz, 0.0, box_height_m);
  if (enter <= leave && leave > 0.0) best = std::min(best, enter);
  return best <= max_range_m ? best : std::numeric_limits<double>::quiet_NaN();
}

std::vector<PlanarScan> make_sequence(std::size_t scans) {
  std::mt19937_64 engine(2024);
  std::normal_distribution<double> noise(0.0, 0.003);
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  std::vector<PlanarScan> sequence(scans);
  for (std::size_t k = 0; k < scans; ++k) {
    PlanarScan& scan = sequence[k];
    scan.resize(urg_beams);
    scan.time_s = 0.1 * static_cast<double>(k);
    const double box_front = 0.60 - 0.01 * static_cast<double>(k);
    for (std::size_t i = 0; i < urg_beams; ++i) {
      scan.angle_rad[i] = (static_cast<double>(i) - 341.0) * 2.0 * pi / 1024.0;
      scan.range_m[i] = cast(scan.angle_rad[i], box_front);
      scan.range_error_m[i] = 0.010;
    }
    // Mixed points: at a depth jump, half of the beams read between the sides.
    for (std::size_t i = 0; i + 1 < urg_beams; ++i) {
      const double a = scan.range_m[i];
      const double b = scan.range_m[i + 1];
      if (std::abs(a - b) > 0.05 && unit(engine) < 0.5) scan.range_m[i] = a + (b - a) * unit(engine);
    }
    // The scan plane meets the box's front face at one height for all beams;
    // it rises 7 mm per scan, and the scan that passes within 3.5 mm of the
    // top edge returns a trailing mixed group.
    const double face_hit_height = sensor_height_m - box_front * std::tan(sensor_pitch_rad);
    if (std::abs(face_hit_height - box_height_m) < 0.0035) {
      for (std::size_t i = 0; i < urg_beams; ++i) {
        const double t = scan.angle_rad[i];
        const double x = box_front / std::cos(sensor_pitch_rad);
        if (std::abs(x * std::tan(t)) <= box_half_width_m) {
          scan.range_m[i] = (x + 0.05 + 0.05 * std::sin(0.25 * static_cast<double>(i))) / std::cos(t);
        }
      }
    }
    for (double& r : scan.range_m) {
      if (!std::isnan(r)) r += noise(engine);
    }
  }
  return sequence;
}

const std::vector<PlanarScan>& sequence() {
  static const std::vector<PlanarScan> scans = make_sequence(40);
  return scans;
}

/// The copy each single-filter benchmark makes per scan (filters work in place).
void BM_CopyScanOnly(benchmark::State& state) {
  const std::vector<PlanarScan>& scans = sequence();
  PlanarScan work = scans[0];
  std::size_t k = 0;
  for (auto _ : state) {
    work = scans[k++ % scans.size()];
    benchmark::DoNotOptimize(work.range_m.data());
    benchmark::ClobberMemory();
  }
}
BENCHMARK(BM_CopyScanOnly);

template <typename Filter, typename Options>
void run_single(benchmark::State& state, const Options& options) {
  const std::vector<PlanarScan>& scans = sequence();
  Filter filter(options);
  PlanarScan work = scans[0];
  std::vector<std::uint8_t> removed;
  std::size_t k = 0;
  std::size_t total_removed = 0;
  for (auto _ : state) {
    work = scans[k++ % scans.size()];
    const stridemap::ScanFilterStats stats = filter.apply(work, removed);
    total_removed += stats.removed;
    benchmark::DoNotOptimize(work.range_m.data());
    benchmark::DoNotOptimize(removed.data());
  }
  state.counters["removed_per_scan"] =
      benchmark::Counter(static_cast<double>(total_removed), benchmark::Counter::kAvgIterations);
}

void BM_RangeClustering(benchmark::State& state) {
  run_single<stridemap::RangeClusteringFilter>(state, stridemap::RangeClusteringOptions{});
}
BENCHMARK(BM_RangeClustering);

void BM_Shadow(benchmark::State& state) {
  run_single<stridemap::ShadowFilter>(state, stridemap::ShadowFilterOptions{});
}
BENCHMARK(BM_Shadow);

void BM_SpeckleDistance(benchmark::State& state) {
  run_single<stridemap::SpeckleFilter>(state, stridemap::SpeckleFilterOptions{});
}
BENCHMARK(BM_SpeckleDistance);

void BM_SpeckleRadiusOutlier(benchmark::State& state) {
  stridemap::SpeckleFilterOptions options;
  options.mode = stridemap::SpeckleMode::radius_outlier;
  run_single<stridemap::SpeckleFilter>(state, options);
}
BENCHMARK(BM_SpeckleRadiusOutlier);

/// One push (copy in, judge the held scan, copy out) per iteration.
void BM_ScanSequence(benchmark::State& state) {
  const std::vector<PlanarScan>& scans = sequence();
  stridemap::ScanSequenceFilter filter;
  PlanarScan out;
  std::vector<std::uint8_t> removed;
  std::size_t k = 0;
  std::size_t total_removed = 0;
  for (auto _ : state) {
    if (filter.push(scans[k++ % scans.size()], out, removed)) total_removed += filter.last_stats().removed;
    benchmark::DoNotOptimize(out.range_m.data());
  }
  state.counters["removed_per_scan"] =
      benchmark::Counter(static_cast<double>(total_removed), benchmark::Counter::kAvgIterations);
}
BENCHMARK(BM_ScanSequence);

void run_chain(benchmark::State& state, const char* names) {
  const std::vector<PlanarScan>& scans = sequence();
  stridemap::ScanFilterChain chain(stridemap::parse_scan_filter_list(names));
  PlanarScan out;
  std::size_t k = 0;
  double total_removed = 0.0;
  for (auto _ : state) {
    if (chain.push(scans[k++ % scans.size()], out)) {
      for (const std::uint8_t r : chain.removed_by_any()) total_removed += r;
    }
    benchmark::DoNotOptimize(out.range_m.data());
  }
  state.counters["removed_per_scan"] = benchmark::Counter(total_removed, benchmark::Counter::kAvgIterations);
}

void BM_ChainPaper(benchmark::State& state) { run_chain(state, "paper"); }
BENCHMARK(BM_ChainPaper);

// The paper's chain with the between-scans test (ours, "urg").
void BM_ChainUrg(benchmark::State& state) { run_chain(state, "urg"); }
BENCHMARK(BM_ChainUrg);

void BM_ChainAllFour(benchmark::State& state) {
  run_chain(state, "range-clustering,scan-sequence,shadow,speckle");
}
BENCHMARK(BM_ChainAllFour);

}  // namespace

BENCHMARK_MAIN();
