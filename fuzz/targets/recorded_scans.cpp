// Recordings for the emulator to replay (recordings/recorded_scans.hpp): a
// stridemap scan log or a BreezySLAM text log, told apart by the first line.
// Whatever the reader accepts, the emulator must be able to serve: a
// replayed scan goes out as SCIP frames that decode to the recorded values
// (an InputError is allowed only from the replay source's own checks, before
// any scan is sent).
#include <algorithm>
#include <memory>
#include <string>
#include <vector>

#include "fuzz_target.hpp"
#include "stridemap/core/error.hpp"
#include "stridemap/recordings/recorded_scans.hpp"
#include "stridemap/sensors/scip_decoder.hpp"
#include "stridemap/sim/urg_emulator.hpp"
#include "stridemap/sim/urg_scan_source.hpp"

STRIDEMAP_FUZZ_TARGET(recorded_scans) {
  using namespace stridemap;
  const std::string name = "fuzz.log";
  io::RecordedScans recorded;
  try {
    recorded = io::parse_recorded_scans(fuzz::as_text(data), name);
  } catch (const InputError& e) {
    fuzz::check(std::string(e.what()).rfind(name, 0) == 0, std::string("an error that does not name the file: ") + e.what());
    return;
  }
  fuzz::check(!recorded.scans.empty(), "a recording accepted without scans");
  fuzz::check(recorded.format == "stridemap" || recorded.format == "breezyslam", "unknown format " + recorded.format);
  for (const auto& scan : recorded.scans) {
    if (recorded.format == "breezyslam") fuzz::check(scan.size() == 683, "a BreezySLAM scan of another length");
  }

  const UrgParameters urg = scip::to_urg_parameters(scip::ScipParameters{});
  std::unique_ptr<RecordedScanSource> source;
  try {
    source = std::make_unique<RecordedScanSource>(recorded.scans, recorded.first_step, recorded.cluster, urg);
  } catch (const InputError&) {
    return;  // e.g. a log recorded with cluster 0: refused before the replay starts
  }
  RecordedScanSource expected = *source;
  UrgEmulatorOptions options;
  options.variant = UrgVariant::ug01;
  UrgEmulator emulator(options, *source);
  const std::size_t scans = std::min<std::size_t>(recorded.scans.size() + 1, 4);
  emulator.receive("MD0044072501000\n", 0);
  emulator.advance(static_cast<std::int64_t>(scans) * emulator.scan_period_ms());

  scip::Decoder decoder;
  for (const EmulatorOutput& out : emulator.output()) decoder.feed(out.bytes);
  scip::Event event;
  std::size_t frames = 0;
  std::vector<std::uint32_t> values;
  while (decoder.next(event)) {
    fuzz::check(event.kind != scip::EventKind::error, "a replayed frame does not decode: " + event.error.message);
    if (event.kind != scip::EventKind::distance) continue;
    expected.scan(frames, 0.0, values);
    fuzz::check(event.distance.values == values, "frame " + std::to_string(frames) + " is not the recorded scan");
    ++frames;
  }
  fuzz::check(frames == scans, std::to_string(frames) + " frames, not " + std::to_string(scans));
}
