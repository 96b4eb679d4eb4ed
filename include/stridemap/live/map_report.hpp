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
#include "stridemap/live/scan_mapper.hpp"
#include "stridemap/sensors/scip_parameters.hpp"
#include "stridemap/sensors/urg_driver.hpp"

namespace stridemap {

struct MapRunInfo {
  std::string command;     ///< "live" or "map"
  std::string scans_from;  ///< device or log path
  std::string poses_from;
  std::string clock;       ///< "host" or "sensor"
  std::string log_damage;  ///< map: the first damaged line of the log, if any
  std::size_t log_lines_skipped = 0;   ///< map: damaged log lines skipped
  std::string log_stop;                ///< map: where reading the log stopped early, if it did
  std::size_t pose_lines_skipped = 0;  ///< bad pose lines skipped
  MapFilter map_filter = MapFilter::fill;
  std::string resumed_from;  ///< the map file mapping went on from, if any
  /// Called with the staging folder once the map's files are in it, before
  /// the set is committed, so that more files join the set (the report page).
  std::function<void(const std::string&)> extra_outputs;
  /// Ends of elevation.png's colour scale [m]; empty: the 2nd-98th percentile.
  std::optional<std::pair<double, double>> elevation_range_m;
  /// The option that named the output folder, for its errors.
  std::string out_option = "--out";
  /// OtherFiles::keep (`--overwrite`): the user's files in the folder stay
  /// beside the map's; by default they refuse it.
  io::OtherFiles other_files = io::OtherFiles::refuse;
};

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

/// What the user chose that decides where the points land, for the message
/// of a run that mapped nothing.
struct MapRunChoices {
  std::string config_path;  ///< --config; empty: the defaults (the paper's mount)
  std::string window;       ///< --window as given; empty: the window follows the robot
  std::string resume_path;  ///< --resume
  std::optional<double> resumed_last_scan_time_s;  ///< the resumed map's last scan
  bool window_fit_possible = true;                 ///< map: --window fit; live cannot know the run beforehand
};

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
