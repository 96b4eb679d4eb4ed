// A whole simulated walk over the rocky mock-up, mapping included: the
// gait, the pose estimate, the sensor simulation, the mapper, and (for the
// scored variants) the mosaic, the fill-in and the ground truth. Reported
// as scans (frames) per second of CPU time (one thread).
#include <memory>
#include <string>

#include <benchmark/benchmark.h>

#include "stridemap/config/scene_yaml.hpp"
#include "stridemap/experiments/structured_light_walk_sensor.hpp"
#include "stridemap/experiments/urg_walk_sensor.hpp"
#include "stridemap/experiments/walk.hpp"
#include "test_paths.hpp"

namespace stridemap {
namespace {

const Scene& mockup() {
  static const Scene scene = load_scene_yaml(std::string(STRIDEMAP_SOURCE_DIR) + "/scenes/rocky_mockup.yaml");
  return scene;
}

void run(benchmark::State& state, bool structured_light, bool scored) {
  const Scene& scene = mockup();
  WalkOptions options;
  options.build_mosaic = scored;
  if (structured_light) options.mapper.grid = {200, 0.005};
  std::size_t scans = 0;
  for (auto _ : state) {
    std::unique_ptr<WalkSensor> sensor;
    if (structured_light) {
      sensor = std::make_unique<StructuredLightWalkSensor>(scene, StructuredLightWalkSensorOptions{},
                                                           options.mapper.update, 1);
    } else {
      sensor = std::make_unique<UrgWalkSensor>(scene, UrgWalkSensorOptions{}, options.mapper.update, 1);
    }
    const WalkResult result = run_walk(scene, *scene.walk_path, *sensor, options);
    benchmark::DoNotOptimize(result.mapper_totals.integrated);
    scans += result.scans;
  }
  state.SetItemsProcessed(static_cast<std::int64_t>(scans));
  state.counters["scans_per_walk"] = static_cast<double>(scans) / static_cast<double>(state.iterations());
}

// Simulation and mapping only: what a robot-in-the-loop run costs.
void BM_WalkUrg(benchmark::State& state) { run(state, false, false); }
BENCHMARK(BM_WalkUrg)->Unit(benchmark::kMillisecond);

// The rocky-walk experiment's main walk: also the mosaic, fill-in and truth.
void BM_WalkUrgScored(benchmark::State& state) { run(state, false, true); }
BENCHMARK(BM_WalkUrgScored)->Unit(benchmark::kMillisecond);

void BM_WalkStructuredLight(benchmark::State& state) { run(state, true, false); }
BENCHMARK(BM_WalkStructuredLight)->Unit(benchmark::kMillisecond);

}  // namespace
}  // namespace stridemap

BENCHMARK_MAIN();
