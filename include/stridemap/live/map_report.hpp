#pragma once
// What `stridemap live` and `stridemap map` write: the map layers (the
// shared writer, io/map_outputs.hpp) and summary.json with the scan and
// beam counts, the sensor's parameters and, for live mapping, the run's
// rates, faults, CPU use and latency (docs/live.md).
#include <cstdint>
#include <optional>
#include <string>

#include "stridemap/live/scan_mapper.hpp"
#include "stridemap/sensors/scip_parameters.hpp"
#include "stridemap/sensors/urg_driver.hpp"

namespace stridemap {

struct MapRunInfo {
  std::string command;     ///< "live" or "map"
  std::string scans_from;  ///< device or log path
  std::string poses_from;
  std::string clock;       ///< "host" or "sensor"
  std::string log_damage;  ///< map: where reading the log stopped, if it did
};

/// Live mapping's own figures (not in a replay: they depend on the run).
struct LiveRunStats {
  double duration_s = 0.0;
  double cpu_s = 0.0;            ///< user + system time of the process
  UrgDriverStats driver;
  std::uint64_t latency_samples = 0;
  double latency_mean_s = 0.0;   ///< last byte read -> scan integrated
  double latency_max_s = 0.0;
  double latency_p99_s = 0.0;
};

std::string map_summary_json(const ScanMapper& mapper, const io::MapLayers& layers,
                             const scip::ScipParameters& sensor, const MapRunInfo& info, const LiveRunStats* live);

/// Writes the layers (with the fill-in applied to a copy) and summary.json
/// into `directory`. Returns the layers written.
io::MapLayers write_map_outputs(const ScanMapper& mapper, const scip::ScipParameters& sensor, const MapRunInfo& info,
                                const LiveRunStats* live, const std::string& directory);

}  // namespace stridemap
