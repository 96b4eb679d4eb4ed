// Cost of simulating mixed pixels: one URG-04LX scan (682 beams) with the
// footprint beam model against the single-ray model, on the shipped
// cart/rail boxes scene (flat floor, two boxes, a can) and on a rocky
// procedural height field, along the cart's rail. Arguments of the
// footprint runs: rings of sub-rays (19 sub-rays at 2 rings) and smear
// instants; the defaults are 2 and 3 (57 rays per beam).
#include <cstdint>
#include <memory>
#include <vector>

#include <benchmark/benchmark.h>

#include "stridemap/config/scene_yaml.hpp"
#include "stridemap/sim/cart_rail.hpp"
#include "stridemap/sim/footprint_beam_model.hpp"
#include "stridemap/sim/urg_simulator.hpp"
#include "test_paths.hpp"

namespace stridemap {
namespace {

Scene boxes_scene() { return load_scene_yaml(std::string(STRIDEMAP_SOURCE_DIR) + "/scenes/cart_rail_boxes.yaml"); }

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

void run_scans(benchmark::State& state, const Scene& scene, std::unique_ptr<BeamModel> model) {
  UrgSimulator sim(scene, UrgParameters{}, UrgSimOptions{}, 1, std::move(model));
  CartRailPath rail;
  rail.end_x_m = 1.2;
  const std::vector<TrunkPose> poses = cart_rail_poses(rail);
  UrgRawScan scan;
  std::vector<BeamLabel> labels;
  std::size_t k = 0;
  std::int64_t mixed = 0;
  for (auto _ : state) {
    sim.scan(poses[k], SensorMount{}, 0.1 * static_cast<double>(k), scan, &labels);
    benchmark::DoNotOptimize(scan.values_mm.data());
    for (const BeamLabel label : labels) mixed += label == BeamLabel::mixed;
    k = (k + 1) % poses.size();
  }
  state.SetItemsProcessed(static_cast<std::int64_t>(state.iterations()) * static_cast<std::int64_t>(scan.values_mm.size()));
  state.counters["mixed_per_scan"] = benchmark::Counter(static_cast<double>(mixed), benchmark::Counter::kAvgIterations);
}

std::unique_ptr<BeamModel> footprint_model(const benchmark::State& state) {
  FootprintBeamOptions options;
  options.footprint_rings = static_cast<int>(state.range(0));
  options.smear_instants = static_cast<int>(state.range(1));
  return std::make_unique<FootprintBeamModel>(options);
}

void BM_SingleRayScanBoxes(benchmark::State& state) {
  run_scans(state, boxes_scene(), std::make_unique<SingleRayBeamModel>());
}
BENCHMARK(BM_SingleRayScanBoxes)->Unit(benchmark::kMicrosecond);

void BM_FootprintScanBoxes(benchmark::State& state) { run_scans(state, boxes_scene(), footprint_model(state)); }
BENCHMARK(BM_FootprintScanBoxes)
    ->ArgNames({"rings", "instants"})
    ->Args({2, 3})
    ->Args({1, 3})
    ->Args({2, 1})
    ->Args({3, 4})
    ->Unit(benchmark::kMicrosecond);

void BM_SingleRayScanRocky(benchmark::State& state) {
  run_scans(state, rocky_scene(), std::make_unique<SingleRayBeamModel>());
}
BENCHMARK(BM_SingleRayScanRocky)->Unit(benchmark::kMicrosecond);

void BM_FootprintScanRocky(benchmark::State& state) { run_scans(state, rocky_scene(), footprint_model(state)); }
BENCHMARK(BM_FootprintScanRocky)->ArgNames({"rings", "instants"})->Args({2, 3})->Unit(benchmark::kMicrosecond);

}  // namespace
}  // namespace stridemap

BENCHMARK_MAIN();
