// Per-frame cost of the structured-light image path: the geometric
// simulator, the rendered VGA camera image, the stripe detector, and the
// whole frame (render, detect, map) on the cart-rail scene.
#include <benchmark/benchmark.h>

#include <string>
#include <vector>

#include "stridemap/config/scene_yaml.hpp"
#include "stridemap/core/terrain_mapper.hpp"
#include "stridemap/sensors/structured_light_mapping.hpp"
#include "stridemap/sim/structured_light_image.hpp"
#include "stridemap/vision/stripe_detector.hpp"
#include "test_paths.hpp"

namespace {

using namespace stridemap;

Scene rail_scene() { return load_scene_yaml(std::string(STRIDEMAP_SOURCE_DIR) + "/scenes/cart_rail_narrow.yaml"); }

TrunkPose on_the_box() {
  TrunkPose pose;
  pose.x_m = 0.3;  // the stripe crosses the large box
  return pose;
}

void BM_GeometricStripeFrame(benchmark::State& state) {
  StructuredLightSimulator simulator(rail_scene(), StructuredLightParameters{});
  StructuredLightFrameTruth frame;
  for (auto _ : state) {
    simulator.simulate(on_the_box(), frame);
    benchmark::DoNotOptimize(frame.visible);
  }
  state.SetItemsProcessed(state.iterations() * 640);
}
BENCHMARK(BM_GeometricStripeFrame);

void BM_RenderStripeImageVga(benchmark::State& state) {
  StructuredLightImageRenderer renderer(rail_scene(), StructuredLightParameters{});
  std::vector<std::uint8_t> rgb;
  for (auto _ : state) {
    const StripeImageStats stats = renderer.render(on_the_box(), rgb);
    benchmark::DoNotOptimize(stats.laser_pixels);
  }
  state.SetItemsProcessed(state.iterations() * 640 * 480);
}
BENCHMARK(BM_RenderStripeImageVga)->Unit(benchmark::kMillisecond);

// Detection on a rendered frame; range(0) is the ambient light [lux]:
// 300 (lab, stripe in every column) and 30000 (daylight, no stripe).
void BM_DetectStripeVga(benchmark::State& state) {
  StripeImageOptions options;
  options.ambient.illuminance_lux = static_cast<double>(state.range(0));
  StructuredLightImageRenderer renderer(rail_scene(), StructuredLightParameters{}, options);
  io::RgbImage image(640, 480);
  renderer.render(on_the_box(), image.rgb);
  io::StripeDetector detector;
  io::StripeDetection detection;
  detector.detect(image, detection);  // buffers grown before timing
  for (auto _ : state) {
    detector.detect(image, detection);
    benchmark::DoNotOptimize(detection.found);
  }
  state.counters["columns_found"] = static_cast<double>(detection.found);
  state.SetItemsProcessed(state.iterations() * 640 * 480);
}
BENCHMARK(BM_DetectStripeVga)->Arg(300)->Arg(30000)->Unit(benchmark::kMicrosecond);

// One frame of the cart-rail image path: render, detect, eq. (1)-(8), map.
void BM_ImagePipelineFrame(benchmark::State& state) {
  const StructuredLightParameters parameters;
  StructuredLightImageRenderer renderer(rail_scene(), parameters);
  io::StripeDetector detector;
  io::RgbImage image(640, 480);
  io::StripeDetection detection;
  std::vector<StripePixel> pixels;
  std::vector<MapPoint> points;
  MapperOptions options;
  options.grid = {320, 0.005};
  options.follow_robot = false;
  TerrainMapper mapper(options, parameters.mount);
  TrunkPose pose = on_the_box();
  for (auto _ : state) {
    pose.x_m += 0.0001;
    renderer.render(pose, image.rgb);
    detector.detect(image, detection);
    detection.pixels(pixels);
    stripe_to_map_points(renderer.model(), pixels, pose, mapper.motion_to(pose), options.update, points);
    benchmark::DoNotOptimize(mapper.integrate_points(points, pose).integrated);
  }
}
BENCHMARK(BM_ImagePipelineFrame)->Unit(benchmark::kMillisecond);

}  // namespace

BENCHMARK_MAIN();
