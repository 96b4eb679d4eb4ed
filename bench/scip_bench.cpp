// SCIP codec speed: decoding MD data frames of 682 3-character values (a full
// URG-04LX scan, 2,134 bytes on the wire) fed in one block or in the small
// chunks a serial port delivers, and encoding the same frames (emulator side).
#include <benchmark/benchmark.h>

#include <cstdint>
#include <string>
#include <vector>

#include "stridemap/sensors/scip_decoder.hpp"
#include "stridemap/sensors/scip_reply_encoder.hpp"

namespace {

using namespace stridemap::scip;

constexpr std::size_t kValues = 682;
constexpr std::size_t kFrames = 64;

// Plausible ranges with error codes mixed in, different for every frame.
std::vector<std::uint32_t> scan_values(std::uint32_t seed) {
  std::vector<std::uint32_t> values(kValues);
  for (std::size_t i = 0; i < kValues; ++i) {
    const std::uint32_t v = (seed * 2654435761u + static_cast<std::uint32_t>(i) * 40503u) % 6000u;
    values[i] = v < 300 ? v % 20 : v;
  }
  return values;
}

std::string md_stream() {
  std::string bytes;
  const Command echo = parse_command("MD0044072501000");
  for (std::uint32_t frame = 0; frame < kFrames; ++frame) {
    append_distance_reply(echo, frame * 100, scan_values(frame), bytes);
  }
  return bytes;
}

void decode_stream(benchmark::State& state, std::size_t chunk_bytes) {
  const std::string bytes = md_stream();
  Decoder decoder;
  Event event;
  std::size_t frames = 0;
  for (auto _ : state) {
    for (std::size_t pos = 0; pos < bytes.size(); pos += chunk_bytes) {
      decoder.feed(std::string_view(bytes).substr(pos, chunk_bytes));
      while (decoder.next(event)) {
        frames += event.kind == EventKind::distance ? 1 : 0;
        benchmark::DoNotOptimize(event.distance.values.data());
      }
    }
  }
  if (frames != kFrames * state.iterations()) state.SkipWithError("frames lost");
  state.SetBytesProcessed(static_cast<std::int64_t>(bytes.size() * state.iterations()));
  state.SetItemsProcessed(static_cast<std::int64_t>(frames));
  state.counters["frames_per_s"] = benchmark::Counter(static_cast<double>(frames), benchmark::Counter::kIsRate);
}

void BM_DecodeMdFramesWhole(benchmark::State& state) { decode_stream(state, md_stream().size()); }
BENCHMARK(BM_DecodeMdFramesWhole);

// A USB CDC-ACM read returns up to 64 bytes at a time.
void BM_DecodeMdFramesChunked(benchmark::State& state) { decode_stream(state, static_cast<std::size_t>(state.range(0))); }
BENCHMARK(BM_DecodeMdFramesChunked)->Arg(1)->Arg(64)->Arg(4096);

void BM_EncodeMdFrame(benchmark::State& state) {
  const Command echo = parse_command("MD0044072501000");
  const auto values = scan_values(1);
  std::string out;
  for (auto _ : state) {
    out.clear();
    append_distance_reply(echo, 12345, values, out);
    benchmark::DoNotOptimize(out.data());
  }
  state.SetBytesProcessed(static_cast<std::int64_t>(out.size() * state.iterations()));
  state.SetItemsProcessed(state.iterations());
}
BENCHMARK(BM_EncodeMdFrame);

}  // namespace

BENCHMARK_MAIN();
