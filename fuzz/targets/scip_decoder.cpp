// The SCIP 2.0 stream decoder on arbitrary bytes, fed whole and in chunks
// chosen by the input: the events must not depend on the chunking nor
// overlap, and every distance reply must go through the URG model, every
// scan filter and the mapper without anything but InputError.
#include <algorithm>
#include <string>
#include <vector>

#include "fuzz_target.hpp"
#include "stridemap/core/error.hpp"
#include "stridemap/core/terrain_mapper.hpp"
#include "stridemap/preprocess/scan_filter_chain.hpp"
#include "stridemap/sensors/scip_decoder.hpp"
#include "stridemap/sensors/scip_scan.hpp"
#include "stridemap/sensors/urg04lx.hpp"

namespace {

using namespace stridemap;
using namespace stridemap::scip;

// The members of an event that its kind makes meaningful, as text.
std::string describe(const Event& e) {
  std::string s = std::to_string(static_cast<int>(e.kind)) + "@" + std::to_string(e.stream_offset) + "+" +
                  std::to_string(e.byte_count);
  if (e.kind == EventKind::error) {
    return s + " " + std::string(error_kind_name(e.error.kind)) + ": " + e.error.message;
  }
  s += " echo=" + e.reply.echo.text + " status=" + e.reply.status;
  if (e.kind == EventKind::distance) {
    s += " t=" + std::to_string(e.distance.timestamp_ms) + " n=" + std::to_string(e.distance.values.size());
    for (std::uint32_t v : e.distance.values) s += "," + std::to_string(v);
  }
  if (e.kind == EventKind::info) {
    for (const InfoField& f : e.info) s += " " + f.key + ":" + f.value;
  }
  if (e.kind == EventKind::time) s += " time=" + std::to_string(e.time_ms);
  return s;
}

std::vector<std::string> decode_in_chunks(std::string_view bytes, std::uint32_t seed, const DecoderOptions& options,
                                          std::vector<Event>* distance_events) {
  Decoder decoder(options);
  std::vector<std::string> events;
  Event event;
  std::size_t pos = 0;
  std::size_t covered = 0;  // events must not overlap (blank lines between frames belong to none)
  while (pos < bytes.size()) {
    // Seed 0: everything at once. Otherwise mostly small chunks (where
    // framing bugs hide), sometimes large ones.
    std::size_t chunk = bytes.size();
    if (seed != 0) {
      seed = seed * 1664525u + 1013904223u;
      chunk = (seed >> 28) < 12 ? 1 + (seed >> 16) % 7 : 1 + (seed >> 8) % 700;
    }
    decoder.feed(bytes.substr(pos, chunk));
    pos += std::min(chunk, bytes.size() - pos);
    while (decoder.next(event)) {
      fuzz::check(event.stream_offset >= covered, "event at offset " + std::to_string(event.stream_offset) +
                                                      " overlaps the previous one, which ended at " +
                                                      std::to_string(covered));
      fuzz::check(event.byte_count > 0, "event covering no bytes: " + describe(event));
      covered = event.stream_offset + event.byte_count;
      fuzz::check(covered <= decoder.stream_offset(), "event beyond the bytes consumed");
      events.push_back(describe(event));
      if (distance_events && event.kind == EventKind::distance) distance_events->push_back(event);
    }
    fuzz::check(decoder.pending_bytes() == 0, "next() returned false with bytes still queued");
  }
  return events;
}

}  // namespace

STRIDEMAP_FUZZ_TARGET(scip_decoder) {
  if (data.size() < 2) return;
  const std::uint32_t seed = 1u + (data[0] | (data[1] << 8));
  const std::string_view bytes = fuzz::as_text(data.subspan(2));
  DecoderOptions options;
  // Small limits now and then, so that the cut-off paths run on short inputs.
  if (seed & 1) options = {40, 300};

  std::vector<Event> distance;
  const std::vector<std::string> whole = decode_in_chunks(bytes, 0, options, &distance);
  const std::vector<std::string> chunked = decode_in_chunks(bytes, seed, options, nullptr);
  fuzz::check(whole.size() == chunked.size(), "chunking changed the number of events: " + std::to_string(whole.size()) +
                                                  " vs " + std::to_string(chunked.size()));
  for (std::size_t i = 0; i < whole.size(); ++i) {
    fuzz::check(whole[i] == chunked[i], "chunking changed event " + std::to_string(i) + ":\n  " + whole[i] + "\n  " +
                                            chunked[i]);
  }

  // Decoded scans into the sensor model and a small mapper.
  const UrgModel urg;
  MapperOptions mapper_options;
  mapper_options.grid.cells_per_side = 20;
  TerrainMapper mapper(mapper_options, SensorMount{});
  UrgRawScan raw;
  PlanarScan scan, filtered;
  TimestampUnwrapper clock;
  ScanFilterChain chain(parse_scan_filter_list("range-clustering,scan-sequence,shadow,speckle"));
  for (const Event& event : distance) {
    try {
      const double time_s = static_cast<double>(clock.unwrap(event.distance.timestamp_ms)) * 1e-3;
      to_urg_raw_scan(event, time_s, raw);
      urg.to_planar_scan(raw, scan);
      if (!chain.push(scan, filtered)) continue;
      const ScanStats stats = mapper.integrate(filtered, TrunkPose{});
      fuzz::check(stats.integrated + stats.invalid_range + stats.invalid_beam + stats.outside_map == stats.beams ||
                      stats.time_rejected,
                  "a beam of a decoded scan was neither used nor counted");
    } catch (const InputError&) {
      // E.g. a scan of another length (another cluster count) ends the
      // filters' stream: start a new one, as a driver would.
      chain.reset();
    }
  }
}
