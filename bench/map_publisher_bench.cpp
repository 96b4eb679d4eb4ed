// What handing the map to a reader thread costs (core/map_publisher.hpp):
// the copy into a snapshot buffer per scan, and a reader taking the latest
// snapshot (docs/performance.md, docs/reliability.md).
#include <atomic>
#include <thread>

#include <benchmark/benchmark.h>

#include "stridemap/core/map_publisher.hpp"
#include "stridemap/core/terrain_mapper.hpp"

namespace {

using namespace stridemap;

MapperOptions grid_of(int cells) {
  MapperOptions options;
  options.grid.cells_per_side = cells;
  return options;
}

void BM_PublishSnapshot(benchmark::State& state) {
  const MapperOptions options = grid_of(static_cast<int>(state.range(0)));
  TerrainMapper mapper(options, SensorMount{});
  MapPublisher publisher(options.grid);
  for (auto _ : state) benchmark::DoNotOptimize(publisher.publish(mapper));
  const double cells = static_cast<double>(options.grid.cells_per_side) * options.grid.cells_per_side;
  state.counters["bytes_per_s"] =
      benchmark::Counter(cells * 14.0 * static_cast<double>(state.iterations()), benchmark::Counter::kIsRate);
}
BENCHMARK(BM_PublishSnapshot)->Arg(100)->Arg(200);

// The same while a reader thread keeps taking and dropping snapshots, so
// the lock is contended.
void BM_PublishSnapshotWithBusyReader(benchmark::State& state) {
  const MapperOptions options = grid_of(100);
  TerrainMapper mapper(options, SensorMount{});
  MapPublisher publisher(options.grid);
  publisher.publish(mapper);
  std::atomic<bool> done{false};
  std::thread reader([&] {
    while (!done.load(std::memory_order_relaxed)) benchmark::DoNotOptimize(publisher.latest()->sequence);
  });
  for (auto _ : state) benchmark::DoNotOptimize(publisher.publish(mapper));
  done = true;
  reader.join();
}
BENCHMARK(BM_PublishSnapshotWithBusyReader)->UseRealTime();

void BM_TakeLatestSnapshot(benchmark::State& state) {
  const MapperOptions options = grid_of(100);
  TerrainMapper mapper(options, SensorMount{});
  MapPublisher publisher(options.grid);
  publisher.publish(mapper);
  for (auto _ : state) {
    const PublishedMapHandle snapshot = publisher.latest();
    benchmark::DoNotOptimize(snapshot.get());
  }
}
BENCHMARK(BM_TakeLatestSnapshot);

}  // namespace

BENCHMARK_MAIN();
