// Map file encoding and decoding (mapfile/map_file.hpp), and importing the real
// BreezySLAM recording (recordings/log_import.hpp) when ../shared/data holds it.
#include <benchmark/benchmark.h>

#include <filesystem>
#include <fstream>
#include <iterator>
#include <random>

#include "stridemap/mapfile/map_file.hpp"
#include "stridemap/recordings/log_import.hpp"
#include "test_paths.hpp"

namespace {

using namespace stridemap;

ElevationMap busy_map(int n) {
  ElevationMap map(GridOptions{n, 0.01});
  std::mt19937 random(1);
  std::uniform_real_distribution<float> height(-0.1f, 0.3f);
  const std::size_t cells = static_cast<std::size_t>(n) * static_cast<std::size_t>(n);
  for (std::size_t s = 0; s < cells; s += 2) {
    map.elevation_data()[s] = height(random);
    map.certainty_data()[s] = 3.0f;
    map.state_data()[s] = static_cast<std::uint8_t>(CellState::measured);
  }
  return map;
}

void BM_EncodeMapFile(benchmark::State& state) {
  const ElevationMap map = busy_map(static_cast<int>(state.range(0)));
  for (auto _ : state) benchmark::DoNotOptimize(io::encode_map_file(map, {}));
  state.SetBytesProcessed(static_cast<std::int64_t>(state.iterations()) * state.range(0) * state.range(0) * 19);
}
BENCHMARK(BM_EncodeMapFile)->Arg(100)->Arg(400)->Unit(benchmark::kMicrosecond);

void BM_DecodeMapFile(benchmark::State& state) {
  const std::string bytes = io::encode_map_file(busy_map(static_cast<int>(state.range(0))), {});
  for (auto _ : state) benchmark::DoNotOptimize(io::decode_map_file(bytes, "bench.smap"));
  state.SetBytesProcessed(static_cast<std::int64_t>(state.iterations() * bytes.size()));
}
BENCHMARK(BM_DecodeMapFile)->Arg(100)->Arg(400)->Unit(benchmark::kMicrosecond);

void BM_ImportBreezySlamExp1(benchmark::State& state) {
  const std::filesystem::path path =
      std::filesystem::path(STRIDEMAP_SOURCE_DIR) / ".." / "shared" / "data" / "urg04lx_breezyslam" / "exp1.dat";
  std::ifstream in(path, std::ios::binary);
  if (!in) {
    state.SkipWithError("no ../shared/data/urg04lx_breezyslam/exp1.dat");
    return;
  }
  const std::string text{std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
  for (auto _ : state) benchmark::DoNotOptimize(io::import_breezyslam(text, "exp1.dat"));
  state.SetItemsProcessed(static_cast<std::int64_t>(state.iterations()) * 756);
}
BENCHMARK(BM_ImportBreezySlamExp1)->Unit(benchmark::kMillisecond);

}  // namespace

BENCHMARK_MAIN();
