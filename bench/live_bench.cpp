// The live mapping path per scan, as `stridemap live` runs it once the bytes
// are in: decode one MD frame (2,134 bytes, a simulated cart-rail scan of
// the shipped scene), turn it into a raw scan, look its pose up between two
// timestamped poses and integrate it into the map. The frames and poses are
// made beforehand; the map window follows the cart as on the robot.
#include <benchmark/benchmark.h>

#include <string>
#include <vector>

#include "stridemap/config/scene_yaml.hpp"
#include "stridemap/live/scan_mapper.hpp"
#include "stridemap/sensors/scip_decoder.hpp"
#include "stridemap/sensors/scip_reply_encoder.hpp"
#include "stridemap/sensors/scip_scan.hpp"
#include "stridemap/sim/urg_scan_source.hpp"
#include "test_paths.hpp"

namespace {

using namespace stridemap;

struct Recorded {
  std::vector<std::string> frames;
  std::vector<TimedPose> poses;
};

Recorded simulate(std::size_t scans) {
  const Scene scene = load_scene_yaml(std::string(STRIDEMAP_SOURCE_DIR) + "/scenes/cart_rail_boxes.yaml");
  const UrgParameters urg;
  const CartRailMotion motion(*scene.cart_rail, urg.scan_period_s);
  SimulatedScanSource source(std::make_unique<UrgSimulator>(scene, urg, UrgSimOptions{}, 1), motion, SensorMount{}, 1);
  const scip::Command echo = scip::parse_command("MD0044072501000");
  Recorded r;
  std::vector<std::uint32_t> values;
  for (std::size_t k = 0; k < scans; ++k) {
    const double t = 0.1 * static_cast<double>(k);
    source.scan(k, t, values);
    std::string& frame = r.frames.emplace_back();
    scip::append_distance_reply(echo, static_cast<std::uint32_t>(100 * k), values, frame);
    r.poses.push_back({t, motion.pose_at(t)});
  }
  return r;
}

void BM_DecodeAndMapOneScan(benchmark::State& state) {
  const Recorded recorded = simulate(120);
  ScanMapperOptions options;
  options.filters = state.range(0) ? parse_scan_filter_list("paper") : std::vector<ScanFilterKind>{};
  ScanMapper mapper(options, UrgParameters{});
  PoseTrack poses;
  scip::Decoder decoder;
  scip::Event event;
  scip::TimestampUnwrapper unwrap;
  UrgRawScan raw;
  std::size_t k = 0;
  double time_offset = 0.0;
  for (auto _ : state) {
    const std::size_t i = k % recorded.frames.size();
    if (i == 0 && k > 0) time_offset += 0.1 * static_cast<double>(recorded.frames.size());  // the cart rides again
    poses.append({recorded.poses[i].time_s + time_offset + 0.05, recorded.poses[i].pose});
    decoder.feed(recorded.frames[i]);
    decoder.next(event);
    scip::to_urg_raw_scan(event, recorded.poses[i].time_s + time_offset, raw);
    unwrap.unwrap(event.distance.timestamp_ms);
    mapper.add(raw);
    mapper.process(poses, false);
    ++k;
  }
  benchmark::DoNotOptimize(mapper.stats().integrated);
  state.SetItemsProcessed(static_cast<std::int64_t>(state.iterations()));
  state.SetLabel(state.range(0) ? "filters: paper" : "no filters");
}
BENCHMARK(BM_DecodeAndMapOneScan)->Arg(0)->Arg(1)->Unit(benchmark::kMicrosecond);

}  // namespace

BENCHMARK_MAIN();
