// Per-frame cost of the structured-light path: one stripe per VGA frame (a
// row position in each of the 640 columns) turned into map points with
// eq. (8)'s bound, and those points integrated into a 5 mm map.
#include <benchmark/benchmark.h>

#include <cmath>
#include <vector>

#include "stridemap/core/terrain_mapper.hpp"
#include "stridemap/sensors/structured_light_mapping.hpp"

namespace {

using namespace stridemap;

std::vector<StripePixel> vga_stripe() {
  std::vector<StripePixel> pixels;
  // Ragno's flat-ground row with a gentle wave, so that rows differ.
  for (int u = 0; u < 640; ++u) pixels.push_back({u + 0.5, 470.0 + 4.0 * std::sin(0.05 * u)});
  return pixels;
}

void BM_StripeToMapPoints(benchmark::State& state) {
  const StructuredLightModel model;
  const std::vector<StripePixel> pixels = vga_stripe();
  std::vector<MapPoint> points;
  TrunkPose pose;
  pose.pitch_rad = 0.02;
  pose.roll_rad = -0.01;
  const ScanMotion motion{0.005, 0.01};
  const UpdateOptions options;
  for (auto _ : state) {
    const StripeConversionStats stats = stripe_to_map_points(model, pixels, pose, motion, options, points);
    benchmark::DoNotOptimize(stats.converted);
    benchmark::DoNotOptimize(points.data());
  }
  state.SetItemsProcessed(state.iterations() * static_cast<long long>(pixels.size()));
}
BENCHMARK(BM_StripeToMapPoints);

void BM_StripeFrameIntoMap(benchmark::State& state) {
  const StructuredLightModel model;
  const std::vector<StripePixel> pixels = vga_stripe();
  std::vector<MapPoint> points;
  MapperOptions options;
  options.grid.cell_size_m = 0.005;
  options.window_ahead_m = 0.2;
  TerrainMapper mapper(options, model.parameters().mount);
  TrunkPose pose;
  for (auto _ : state) {
    pose.x_m += 0.001;
    stripe_to_map_points(model, pixels, pose, mapper.motion_to(pose), options.update, points);
    const ScanStats stats = mapper.integrate_points(points, pose);
    benchmark::DoNotOptimize(stats.integrated);
  }
  state.SetItemsProcessed(state.iterations() * static_cast<long long>(pixels.size()));
}
BENCHMARK(BM_StripeFrameIntoMap);

}  // namespace

BENCHMARK_MAIN();
