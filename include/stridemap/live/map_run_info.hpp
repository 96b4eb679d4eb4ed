#pragma once
// The run information of `stridemap live` and `stridemap map`, made in one
// place from the settings both commands share, so that the map file,
// summary.json and the messages of the two commands say the same things.
#include <cstddef>
#include <functional>
#include <optional>
#include <string>
#include <utility>

#include "stridemap/core/map_filter.hpp"
#include "stridemap/io/output_folder.hpp"
#include "stridemap/live/scan_mapper.hpp"

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

/// What the user chose that decides where the points land, for the message
/// of a run that mapped nothing.
struct MapRunChoices {
  std::string config_path;  ///< --config; empty: the defaults (the paper's mount)
  std::string window;       ///< --window as given; empty: the window follows the robot
  std::string resume_path;  ///< --resume
  std::optional<double> resumed_last_scan_time_s;  ///< the resumed map's last scan
  bool window_fit_possible = true;                 ///< map: --window fit; live cannot know the run beforehand
};

/// The mapping settings of `live` and `map` as given on the command line
/// (docs/cli.md), before they are checked.
struct MapRunSettings {
  std::string poses_path;
  std::string out_dir;
  std::string config_path;
  std::string filters = "none";
  std::string clock = "host";
  std::string map_filter = "fill";
  std::string resume_path;
  double max_pose_gap_s = 1.0;
  std::string range;  ///< MIN:MAX of elevation.png's colour scale, or empty
  std::string window;
  std::string global_map;
  bool overwrite = false;  ///< --overwrite: --out may hold other files, which are kept
};

/// --range MIN:MAX: the ends of elevation.png's colour scale [m]; nothing
/// for empty text. Throws InputError naming --range.
std::optional<std::pair<double, double>> parse_elevation_range(const std::string& text);

/// The run information of `command` ("live" or "map") mapping the scans of
/// `scans_from` with `settings`; what only the run finds out (damaged log
/// lines, skipped pose lines) is added as it does. Throws InputError for a
/// --range or --map-filter that does not parse.
MapRunInfo map_run_info(const std::string& command, const std::string& scans_from, const MapRunSettings& settings);

/// The choices named by empty_run_failure. `window_fit_possible`: --window
/// fit is an option of the command (map; live cannot know the run beforehand).
MapRunChoices map_run_choices(const MapRunSettings& settings, const ScanMapperOptions& options,
                              bool window_fit_possible);

}  // namespace stridemap
