#pragma once
// What `stridemap live` and `stridemap map` write: the map layers (the
// shared writer, mapfile/map_outputs.hpp) and summary.json with the scan and
// beam counts, the sensor's parameters and, for live mapping, the run's
// rates, faults, CPU use and latency (docs/live.md).
#include <cstdint>
#include <functional>
#include <utility>
#include <optional>
#include <string>

#include "stridemap/core/map_filter.hpp"
#include "stridemap/io/output_folder.hpp"
#include "stridemap/live/map_run_info.hpp"
#include "stridemap/live/scan_mapper.hpp"
#include "stridemap/sensors/scip_parameters.hpp"
#include "stridemap/sensors/urg_driver.hpp"

namespace stridemap {

/// Live mapping's own figures (not in a replay: they depend on the run).
struct LiveRunStats {
  double duration_s = 0.0;
  double cpu_s = 0.0;            ///< user + system time of the process
  UrgDriverStats driver;
  std::uint64_t latency_samples = 0;
  double latency_mean_s = 0.0;   ///< last byte read -> scan integrated
  double latency_max_s = 0.0;
  double latency_p99_s = 0.0;   ///< from 1 %-wide bins: at most 1 % above the exact one
  std::uint64_t saves = 0;          ///< periodic saves written
  std::uint64_t save_failures = 0;  ///< periodic saves that failed (and were retried)
  std::uint64_t pose_reopens = 0;   ///< the pose file replaced or cut under the reader
};

std::string map_summary_json(const ScanMapper& mapper, const ExportedMap& layers,
                             const scip::ScipParameters& sensor, const MapRunInfo& info, const LiveRunStats* live);

/// First and last of a series of times (scans', poses').
struct TimeRange {
  std::size_t count = 0;
  double first_s = 0.0;
  double last_s = 0.0;
  void add(double time_s) {
    if (count++ == 0) first_s = time_s;
    last_s = time_s;
  }
};

/// Empty when at least half the scans reached the map; else what went
/// wrong, for the user: the scans mapped, the scans' and the poses' time
/// ranges (on `clock`), and what the others were skipped for. A run with no
/// scan at all is not judged.
std::string mapping_shortfall(const ScanMapperStats& stats, const TimeRange& scans, const TimeRange& poses,
                              const std::string& clock);

/// Scans that reached the mapper and were used: not rejected there as stale
/// (a time not later than the last scan mapped) or for a non-finite pose.
std::size_t scans_mapped(const ScanMapper& mapper);

/// Empty when the run mapped something onto the map; else why it did not,
/// naming the cause and the option that fixes it: every scan that reached
/// the mapper rejected as stale (a log older than the --resume map, times
/// going backwards) or for its pose, or scans mapped but no cell known at
/// the end (the mount of --config or its default, or the --window). A run
/// in which no scan reached the mapper is mapping_shortfall's.
std::string empty_run_failure(const ScanMapper& mapper, const ExportedMap& layers, const TimeRange& scans,
                              const MapRunChoices& choices);

/// The map with `filter` applied to a copy (the map being built is not
/// changed, so saving often changes nothing).
ExportedMap filtered_map_layers(const ScanMapper& mapper, MapFilter filter);

/// Writes the layers (info.map_filter applied to a copy) and summary.json as
/// one set (io::OutputFolder): `directory` holds the previous set or the
/// new one, never a mix or a torn file. Returns the layers written. Throws
/// InputError naming the folder (unusable folder, disk full).
ExportedMap write_map_outputs(const ScanMapper& mapper, const scip::ScipParameters& sensor, const MapRunInfo& info,
                                const LiveRunStats* live, const std::string& directory);

}  // namespace stridemap
