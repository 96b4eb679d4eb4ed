// Speed of the simulator: one URG-04LX scan (682 beams) of the shipped
// cart/rail scene and of a rocky procedural terrain, and the ground truth of
// a whole 100 x 100 map.
#include <cstddef>
#include <vector>

#include <benchmark/benchmark.h>

#include "stridemap/config/scene_yaml.hpp"
#include "stridemap/sim/cart_rail.hpp"
#include "stridemap/sim/urg_simulator.hpp"
#include "test_paths.hpp"

namespace stridemap {
namespace {

Scene shipped_scene() { return load_scene_yaml(std::string(STRIDEMAP_SOURCE_DIR) + "/scenes/cart_rail_boxes.yaml"); }

Scene rocky_scene() {
  ProceduralTerrainOptions options;
  options.min_x_m = -0.5;
  options.min_y_m = -1.0;
  options.max_x_m = 2.5;
  options.max_y_m = 1.0;
  options.resolution_m = 0.005;
  options.amplitude_m = 0.05;
  options.wavelength_m = 0.25;
  Scene scene;
  scene.terrain = make_procedural_height_field(options, 7);
  return scene;
}

void run_rail_scans(benchmark::State& state, const Scene& scene) {
  UrgSimulator sim(scene, UrgParameters{}, UrgSimOptions{}, 1);
  CartRailPath rail;
  rail.end_x_m = 1.2;
  const std::vector<TrunkPose> poses = cart_rail_poses(scene.cart_rail.value_or(rail));
  UrgRawScan scan;
  std::vector<BeamLabel> labels;
  std::size_t k = 0;
  for (auto _ : state) {
    sim.scan(poses[k], SensorMount{}, 0.1 * static_cast<double>(k), scan, &labels);
    benchmark::DoNotOptimize(scan.values_mm.data());
    k = (k + 1) % poses.size();
  }
  state.SetItemsProcessed(static_cast<std::int64_t>(state.iterations()) * static_cast<std::int64_t>(scan.values_mm.size()));
  state.counters["beams_per_scan"] = static_cast<double>(scan.values_mm.size());
}

void BM_UrgScanCartRailBoxes(benchmark::State& state) { run_rail_scans(state, shipped_scene()); }
BENCHMARK(BM_UrgScanCartRailBoxes)->Unit(benchmark::kMicrosecond);

void BM_UrgScanRockyTerrain(benchmark::State& state) { run_rail_scans(state, rocky_scene()); }
BENCHMARK(BM_UrgScanRockyTerrain)->Unit(benchmark::kMicrosecond);

void BM_GroundTruthOfAMap(benchmark::State& state) {
  const Scene scene = state.range(0) == 0 ? shipped_scene() : rocky_scene();
  const double cell_m = 0.01;
  for (auto _ : state) {
    double sum = 0.0;
    for (int j = 0; j < 100; ++j) {
      for (int i = 0; i < 100; ++i) {
        const double x = 0.5 + i * cell_m, y = -0.5 + j * cell_m;
        sum += scene.max_height_in_rect(x, y, x + cell_m, y + cell_m);
      }
    }
    benchmark::DoNotOptimize(sum);
  }
  state.SetItemsProcessed(static_cast<std::int64_t>(state.iterations()) * 10000);
}
BENCHMARK(BM_GroundTruthOfAMap)->Arg(0)->Arg(1)->Unit(benchmark::kMicrosecond);

}  // namespace
}  // namespace stridemap

BENCHMARK_MAIN();
