// `stridemap live`: a map in real time from a URG (or the emulator) and a
// stream of poses, through the library's LiveMapping loop; `stridemap map`:
// the same map from a scan log and a pose file. Both go through ScanMapper
// and the same writers (docs/live.md).
#include <unistd.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <memory>
#include <optional>
#include <string>

#include "cli_parsing.hpp"
#include "commands.hpp"
#include "map_bag.hpp"
#include "terminal_output.hpp"
#include "output_guard.hpp"
#include "stridemap/core/error.hpp"
#include "stridemap/core/printable_text.hpp"
#include "stridemap/mapfile/map_file.hpp"
#include "stridemap/mapfile/map_outputs.hpp"
#include "stridemap/mapfile/map_resume_check.hpp"
#include "stridemap/io/output_folder.hpp"
#include "stridemap/recordings/pose_stream.hpp"
#include "stridemap/recordings/scan_log.hpp"
#include "stridemap/mapfile/tile_store.hpp"
#include "stridemap/live/live_mapping.hpp"
#include "stridemap/live/log_replay.hpp"
#include "stridemap/live/map_window.hpp"
#include "stridemap/live/map_report.hpp"
#include "report_command.hpp"
#include "urg_device.hpp"
#include "window_placement.hpp"

namespace stridemap::cli {
namespace {

struct MappingArgs {
  std::string poses_path;
  std::string out_dir;
  std::string config_path;
  std::string filters = "none";
  std::string clock = "host";
  std::string map_filter = "fill";
  std::string resume_path;
  double max_pose_gap_s = 1.0;
  bool report = false;
  std::string range;
  std::string window;
  std::string global_map;
  bool overwrite = false;  ///< --overwrite: --out may hold other files, which are kept
};

// --range MIN:MAX: the ends of elevation.png's colour scale [m].
std::optional<std::pair<double, double>> parse_range(const std::string& text) {
  if (text.empty()) return std::nullopt;
  const std::size_t colon = text.find(':');
  char* end = nullptr;
  const auto number = [&](const std::string& part) {
    const double value = std::strtod(part.c_str(), &end);
    if (part.empty() || *end != '\0' || !std::isfinite(value)) {
      throw InputError("--range: '" + text + "' is not MIN:MAX in metres (e.g. -0.05:0.12)");
    }
    return value;
  };
  if (colon == std::string::npos) number("");
  const double low = number(text.substr(0, colon)), high = number(text.substr(colon + 1));
  if (!(low < high)) throw InputError("--range: MIN must be below MAX, got '" + text + "'");
  return std::make_pair(low, high);
}

void add_mapping_options(CLI::App& command, MappingArgs& args) {
  command.add_option("--out", args.out_dir, "Output folder: elevation/certainty PNG and CSV, state.csv, summary.json")
      ->required();
  add_report_flag(command, args.report);
  command.add_option("--range", args.range,
                     "Colour range of elevation.png, MIN:MAX in metres (default: the 2nd to 98th percentile)")
      ->check([](const std::string& text) {
        try {
          parse_range(text);  // at parsing, so that a typo costs no run
        } catch (const InputError& e) {
          return std::string(e.what());
        }
        return std::string();
      });
  command.add_option("--window", args.window,
                     "Where the map's window stays: X,Y (its centre in the map frame, metres, e.g. 1.5,-0.2) or "
                     "fit (map: over everything the log measures, growing the map if needed). Default: it follows "
                     "the robot (docs/cli.md)")
      ->check([](const std::string& text) {
        try {
          parse_window_choice(text);
        } catch (const InputError& e) {
          return std::string(e.what());
        }
        return std::string();
      });
  command.add_option("--config", args.config_path, "Mapper configuration (YAML, docs/config.md)");
  command.add_option("--filters", args.filters,
                     "Scan filters in order: range-clustering, scan-sequence, between-scans, shadow, speckle; paper; urg; none")
      ->capture_default_str();
  command.add_option("--clock", args.clock,
                     "Clock of the pose times: host (Unix time of each scan's step 0, estimated by the driver) or "
                     "sensor (the URG's millisecond clock, in seconds)")
      ->capture_default_str();
  command.add_option("--max-pose-gap-s", args.max_pose_gap_s,
                     "Do not interpolate between poses farther apart than this")
      ->capture_default_str()
      ->check(number_from_to(0.001, 1e9, "s"));
  command.add_option("--map-filter", args.map_filter,
                     "What runs on a copy of the map before it is saved: fill (eq. 11), cas or none")
      ->capture_default_str();
  command.add_option("--global-map", args.global_map,
                     "Keep the cells that leave the window in tiles in this new or empty folder, and reload them "
                     "when the robot comes back (docs/global_map.md); overrides the config's global_map.folder");
  command.add_option("--resume", args.resume_path,
                     "Go on mapping from this map file (a map.smap of an earlier run, made with the same --config); "
                     "the new map goes to --out, the file itself is never changed");
}

LiveClock parse_clock(const std::string& name) {
  if (name == "host") return LiveClock::host;
  if (name == "sensor") return LiveClock::sensor;
  throw InputError("--clock: '" + name + "' is not a clock; use host or sensor");
}

ScanMapperOptions mapper_options(const MappingArgs& args) {
  parse_clock(args.clock);
  parse_map_filter(args.map_filter);
  const WindowChoice window = parse_window_choice(args.window);
  if (window.mode != WindowChoice::Mode::follow && !args.resume_path.empty()) {
    throw InputError("--window: a resumed map keeps the window of its map file (--resume " + args.resume_path +
                     "); leave out --window");
  }
  ScanMapperOptions options;
  if (!args.config_path.empty()) options.config = load_mapper_config(args.config_path);
  if (!args.global_map.empty()) options.config.global_map.folder = args.global_map;
  const std::string& tiles = options.config.global_map.folder;
  if (!tiles.empty() && (io::path_within(tiles, args.out_dir) || io::path_within(args.out_dir, tiles))) {
    // Refused now, not when the outputs are written after the mapping.
    throw InputError("--global-map: '" + tiles + "' and the --out folder '" + args.out_dir +
                     "' lie one inside the other; give the tiles a folder of their own");
  }
  if (window.mode == WindowChoice::Mode::center) {
    fix_window(options, window_centred_at(options.config.mapper.grid, window.center_m));
  }
  options.filters = parse_scan_filter_list(args.filters);
  if (!args.resume_path.empty()) {
    options.resume = std::make_shared<const io::MapFile>(io::load_map_file(args.resume_path));
    options.resume_source = "--resume " + args.resume_path;
    // Before any device is opened or output touched.
    io::check_map_resumable(*options.resume, options.config, options.resume_source);
  }
  return options;
}

// A run whose global map is not all on disk failed, whatever else it did.
void check_tiles_saved(const ScanMapper& mapper) {
  const io::TileStore* tiles = mapper.tile_store();
  if (!tiles) return;
  const io::TileStoreStats& s = tiles->stats();
  note("global map: " + std::to_string(tiles->tiles_on_disk().size()) + " tiles in " + tiles->folder() +
       (s.tiles_set_aside ? "; " + std::to_string(s.tiles_set_aside) + " damaged or missing, set aside and mapped anew"
                          : std::string()));
  if (tiles->failing()) {
    throw RunFailed("global map: " + std::to_string(tiles->unsaved()) + " changed tiles (or the manifest) could not be "
                    "written to " + tiles->folder() + " after " + std::to_string(s.write_failures) +
                    " tries (the warnings above say why); the map in --out holds the window only");
  }
}

void report_shortfall(const ScanMapperStats& stats, const TimeRange& scans, const TimeRange& poses,
                      const std::string& clock) {
  const std::string why = mapping_shortfall(stats, scans, poses, clock);
  if (!why.empty()) throw RunFailed(why);
}

MapRunChoices run_choices(const MappingArgs& args, const ScanMapperOptions& options, bool window_fit_possible) {
  MapRunChoices choices;
  choices.config_path = args.config_path;
  choices.window = args.window;
  choices.resume_path = args.resume_path;
  if (options.resume) choices.resumed_last_scan_time_s = options.resume->metadata.last_scan_time_s;
  choices.window_fit_possible = window_fit_possible;
  return choices;
}

// The scans that reached the mapper but were not used there, for the summary line.
std::string rejected_text(const ScanMapper& mapper) {
  const MapperTotals& t = mapper.mapper().totals();
  return std::to_string(t.scans_rejected_for_time) + " rejected as stale, " +
         std::to_string(t.scans_rejected_for_pose) + " for a bad pose";
}

// ---------------------------------------------------------------- live

struct LiveArgs {
  DeviceArgs device;
  MappingArgs mapping;
  std::string record_path;
  bool overwrite = false;
  bool append = false;
  double save_every_s = 5.0;
  double pose_wait_s = 0.5;
  double status_every_s = 1.0;
};

void run_live(const LiveArgs& args) {
  if (parse_window_choice(args.mapping.window).mode == WindowChoice::Mode::fit) {
    throw InputError("--window fit: live cannot know beforehand where the run will go; give a centre (--window X,Y) "
                     "or let the window follow the robot (no --window)");
  }
  install_stop_signals();
  LiveMappingOptions options;
  options.mapper = mapper_options(args.mapping);
  options.clock = parse_clock(args.mapping.clock);
  options.map_filter = parse_map_filter(args.mapping.map_filter);
  options.max_pose_gap_s = args.mapping.max_pose_gap_s;
  options.save_every_s = args.save_every_s;
  options.pose_wait_s = args.pose_wait_s;
  options.status_every_s = args.status_every_s;
  options.duration_s = args.device.duration_s;
  options.max_scans = args.device.max_scans;
  options.validate();
  const ExistingLog log_choice = existing_log_choice(args.overwrite, args.append);
  const std::vector<NamedPath> inputs{{"--poses", args.mapping.poses_path},
                                      {"--config", args.mapping.config_path},
                                      {"--device", args.device.device},
                                      {"--resume", args.mapping.resume_path}};
  if (!args.record_path.empty()) {
    refuse_output_that_is_an_input("--record", args.record_path, inputs);
    check_log_output("--record", args.record_path, log_choice, "stridemap-urg-log");
  }
  std::vector<NamedPath> out_inputs = inputs;
  out_inputs.push_back({"--record", args.record_path});
  refuse_output_that_is_an_input("--out", args.mapping.out_dir, out_inputs);
  io::check_output_folder(args.mapping.out_dir, "--out", other_files(args.overwrite));
  if (args.mapping.report) report_assets_dir();  // before the run, not after it
  const GlobalMapOptions& global_map = options.mapper.config.global_map;
  if (!global_map.folder.empty()) {
    // A resumed map's cell size is its file's, read only when the mapper is made.
    const std::optional<double> cell_size_m =
        args.mapping.resume_path.empty() ? std::optional<double>(options.mapper.config.mapper.grid.cell_size_m)
                                         : std::nullopt;
    io::check_global_map_folder(global_map, cell_size_m);
  }
  PoseStreamSource poses(args.mapping.poses_path);

  UrgDriverEvent event;
  std::unique_ptr<UrgDriver> driver = start_driver(args.device, event);
  std::fprintf(stderr, "stridemap: connected: %s\n", printable_text(event.message).c_str());
  // Only now, with the inputs open and the sensor streaming, is the log touched.
  std::unique_ptr<io::ScanLogWriter> log;
  if (!args.record_path.empty()) {
    log = std::make_unique<io::ScanLogWriter>(args.record_path, args.device.device, log_choice == ExistingLog::append);
    log->write_sensor(host_seconds(), driver->version(), driver->parameters());
  }
  UrgDriverSource scans(*driver);

  MapRunInfo info;
  info.command = "live";
  info.other_files = other_files(args.overwrite);
  info.elevation_range_m = parse_range(args.mapping.range);
  if (args.mapping.report) {
    info.extra_outputs = [target = args.mapping.out_dir](const std::string& folder) { write_run_report(folder, target); };
  }
  info.scans_from = args.device.device;
  info.poses_from = args.mapping.poses_path;
  info.clock = args.mapping.clock;
  info.map_filter = options.map_filter;
  info.resumed_from = args.mapping.resume_path;
  const bool tty = ::isatty(STDERR_FILENO) != 0;
  std::unique_ptr<LiveMapping> live;
  std::string log_error;
  LiveMappingHooks hooks;
  hooks.save = [&](const ScanMapper& mapper, const LiveRunStats* run) {
    info.pose_lines_skipped = poses.skipped_lines();
    write_map_outputs(mapper, live->sensor(), info, run, args.mapping.out_dir);
  };
  hooks.on_scan = [&](const UrgScan& scan) {
    if (!log || !log_error.empty()) return;
    try {
      log->write_scan(scan);
    } catch (const InputError& e) {
      log_error = e.what();  // mapping goes on; said once, and at the end
      std::fprintf(stderr, "%sstridemap: warning: %s; the scans are no longer recorded\n", tty ? "\n" : "",
                   log_error.c_str());
    }
  };
  const double start = monotonic_seconds();
  hooks.on_event = [&](const LiveEvent& e) {
    switch (e.kind) {
      case LiveEvent::Kind::status: {
        if (verbosity().quiet) break;
        const UrgDriverStats& d = driver->stats();
        const ScanMapper& mapper = live->mapper();
        const double now = monotonic_seconds();
        std::fprintf(stderr,
                     "%slive: %.1f scans/s, %llu scans, %llu lost, %llu faults, %zu mapped, %zu waiting for poses, "
                     "%zu pose lines skipped%s",
                     tty ? "\r" : "", static_cast<double>(d.scans) / std::max(1e-9, now - start),
                     static_cast<unsigned long long>(d.scans), static_cast<unsigned long long>(d.scans_lost),
                     static_cast<unsigned long long>(d.faults), mapper.stats().integrated, mapper.waiting(),
                     poses.skipped_lines(), tty ? "\x1b[K" : "\n");
        break;
      }
      case LiveEvent::Kind::fault:
        if (tty) std::fputc('\n', stderr);
        print_fault(*e.driver_event);
        if (log && log_error.empty()) {
          try {
            log->write_fault(host_seconds(), e.driver_event->fault, e.driver_event->count, e.message);
          } catch (const InputError& error) {
            log_error = error.what();
          }
        }
        break;
      case LiveEvent::Kind::connected:
        if (log && log_error.empty()) {
          try {
            log->write_sensor(host_seconds(), driver->version(), driver->parameters());
          } catch (const InputError& error) {
            log_error = error.what();
          }
        }
        break;
      case LiveEvent::Kind::pose_notice:
        std::fprintf(stderr, "%sstridemap: warning: pose skipped or reopened: %s\n", tty ? "\n" : "", e.message.c_str());
        break;
      case LiveEvent::Kind::save_failed:
        std::fprintf(stderr, "%sstridemap: warning: saving the map failed, retrying while mapping goes on: %s\n",
                     tty ? "\n" : "", e.message.c_str());
        break;
      case LiveEvent::Kind::save_recovered:
      case LiveEvent::Kind::warning:
        std::fprintf(stderr, "%sstridemap: %s%s\n", tty ? "\n" : "",
                     e.kind == LiveEvent::Kind::warning ? "warning: " : "", e.message.c_str());
        break;
    }
  };
  live = std::make_unique<LiveMapping>(options, scans, poses, hooks);
  const LiveMappingResult result = live->run(stop_flag());
  if (tty) std::fputc('\n', stderr);
  if (log && log_error.empty()) {
    try {
      log->flush();
    } catch (const InputError& e) {
      log_error = e.what();
    }
  }
  const ScanMapper& mapper = live->mapper();
  const LiveRunStats& run = result.run;
  std::printf("live: %zu scans mapped of %zu received (%llu lost, %s), %zu pose lines skipped, CPU %.2f %% of one "
              "core, latency mean %.2f ms max %.2f ms; outputs: %s\n",
              scans_mapped(mapper), mapper.stats().scans, static_cast<unsigned long long>(run.driver.scans_lost),
              rejected_text(mapper).c_str(), poses.skipped_lines(), run.duration_s > 0 ? 100.0 * run.cpu_s / run.duration_s : 0.0,
              run.latency_mean_s * 1000.0, run.latency_max_s * 1000.0, args.mapping.out_dir.c_str());
  std::fflush(stdout);
  if (!result.last_save_error.empty()) throw InputError(result.last_save_error + " (the map could not be saved)");
  if (!result.fatal.empty()) throw InputError(args.device.device + ": " + result.fatal + " (the map so far is saved)");
  if (!log_error.empty()) throw InputError(log_error + " (the map is saved; the log stops where writing failed)");
  check_tiles_saved(mapper);
  report_shortfall(mapper.stats(), live->scan_times(), live->pose_times(), args.mapping.clock);
  const std::string nothing = empty_run_failure(mapper, filtered_map_layers(mapper, MapFilter::none),
                                                live->scan_times(), run_choices(args.mapping, options.mapper, false));
  if (!nothing.empty()) throw RunFailed(nothing);
}

// ---------------------------------------------------------------- map

struct MapArgs {
  std::string log_path;
  MappingArgs mapping;
  MapBagArgs bag;
};

void print_skipped(const std::string& what, std::size_t count, const std::vector<std::string>& first) {
  if (count == 0) return;
  std::fprintf(stderr, "stridemap: warning: %zu %s skipped:\n", count, what.c_str());
  for (const std::string& line : first) std::fprintf(stderr, "  %s\n", printable_text(line).c_str());
  if (count > first.size()) std::fprintf(stderr, "  ... and %zu more\n", count - first.size());
}

void run_map(const MapArgs& args) {
  ScanMapperOptions options = mapper_options(args.mapping);
  const LiveClock clock = parse_clock(args.mapping.clock);
  const std::vector<NamedPath> inputs{{"--log", args.log_path},
                                      {"--poses", args.mapping.poses_path},
                                      {"--config", args.mapping.config_path},
                                      {"--resume", args.mapping.resume_path}};
  refuse_output_that_is_an_input("--out", args.mapping.out_dir, inputs);
  io::check_output_folder(args.mapping.out_dir, "--out", other_files(args.mapping.overwrite));
  if (args.mapping.report) report_assets_dir();
  // The log is read as a stream: memory stays flat however long it is, and
  // its damage is told after the mapping. Opening it reads up to its first
  // scan, so a file that is no scan log is refused before the poses are read;
  // --window fit first reads the log once more (streamed too) to fix the window.
  const bool fit = parse_window_choice(args.mapping.window).mode == WindowChoice::Mode::fit;
  std::optional<LogReplay> opened;
  if (!fit) opened.emplace(args.log_path, options, clock);
  io::PoseLineProblems pose_problems;
  PoseTrack track(args.mapping.max_pose_gap_s);
  TimeRange pose_times;
  for (const TimedPose& pose : io::read_pose_file(args.mapping.poses_path, &pose_problems)) {
    track.append(pose);
    pose_times.add(pose.time_s);
  }
  print_skipped("bad pose lines", pose_problems.count, pose_problems.first);
  if (fit) {
    fit_window(options, args.log_path, track, clock);
    opened.emplace(args.log_path, options, clock);
  }
  LogReplay& replay = *opened;
  if (options.resume) note("going on from the map in " + args.mapping.resume_path);
  {
    io::ProgressBar bar = progress_bar("map", "scans");
    replay.run(track, [&bar](std::size_t scans) { bar.update(scans, 0); });
  }
  for (const std::string& notice : replay.take_tile_notices()) {
    std::fprintf(stderr, "stridemap: warning: %s\n", printable_text(notice).c_str());
  }
  const io::ScanLog& log = replay.log();
  print_skipped("damaged scan-log lines", log.skipped_line_numbers.size(), log.skipped);
  if (!log.stop.empty()) {
    std::fprintf(stderr, "stridemap: warning: %s; the log is read up to there\n", printable_text(log.stop).c_str());
  }
  note("read " + std::to_string(replay.scans_read()) + " scans from " + args.log_path + " and " +
       std::to_string(pose_times.count) + " poses from " + args.mapping.poses_path);
  const ScanMapper& mapper = replay.mapper();
  const TimeRange& scan_times = replay.scan_times();
  MapRunInfo info;
  info.command = "map";
  info.other_files = other_files(args.mapping.overwrite);
  info.elevation_range_m = parse_range(args.mapping.range);
  if (args.mapping.report) {
    info.extra_outputs = [target = args.mapping.out_dir](const std::string& folder) { write_run_report(folder, target); };
  }
  info.scans_from = args.log_path;
  info.poses_from = args.mapping.poses_path;
  info.clock = args.mapping.clock;
  info.log_damage = log.damage;
  info.log_lines_skipped = log.skipped_line_numbers.size();
  info.log_stop = log.stop;
  info.pose_lines_skipped = pose_problems.count;
  info.resumed_from = args.mapping.resume_path;
  info.map_filter = parse_map_filter(args.mapping.map_filter);
  const ExportedMap layers = write_map_outputs(mapper, log.parameters, info, nullptr, args.mapping.out_dir);
  const ScanMapperStats& s = mapper.stats();
  std::printf("map: %zu scans mapped of %zu (%zu before the first pose, %zu after the last, %zu in pose gaps, %s), "
              "coverage %.1f %%; outputs: %s\n",
              scans_mapped(mapper), s.scans, s.before_first_pose, s.after_last_pose, s.pose_gap,
              rejected_text(mapper).c_str(), 100.0 * map_coverage(layers), args.mapping.out_dir.c_str());
  std::fflush(stdout);
  check_tiles_saved(mapper);
  report_shortfall(s, scan_times, pose_times, args.mapping.clock);
  const std::string nothing = empty_run_failure(mapper, layers, scan_times, run_choices(args.mapping, options, true));
  if (!nothing.empty()) throw RunFailed(nothing);
}

}  // namespace

void register_live(CLI::App& app) {
  auto args = std::make_shared<LiveArgs>();
  CLI::App* live = app.add_subcommand("live", "Map in real time from a URG-04LX and a pose stream (docs/live.md)");
  add_device_options(*live, args->device);
  live->add_option("--poses", args->mapping.poses_path,
                   "Timestamped poses: a file or a named pipe another process writes (docs/live.md)")
      ->required();
  add_mapping_options(*live, args->mapping);
  live->add_option("--record", args->record_path, "Also write the scans into this scan log");
  add_existing_log_flags(*live, args->overwrite, args->append,
                         "Replace an existing --record log, and stridemap's earlier outputs in --out even when the "
                         "folder holds other files, which are kept (by default both are refused)");
  live->add_option("--save-every-s", args->save_every_s, "Write the map this often (and at exit)")
      ->capture_default_str()
      ->check(number_from_to(0.01, 86400.0, "s"));
  live->add_option("--pose-wait-s", args->pose_wait_s,
                   "A scan whose poses have not arrived after this long is skipped")
      ->capture_default_str()
      ->check(number_from_to(0.0, 3600.0, "s"));
  live->add_option("--status-every-s", args->status_every_s, "Status line period")->capture_default_str()
      ->check(number_from_to(0.01, 86400.0, "s"));
  live->callback([args] { run_live(*args); });

  auto map_args = std::make_shared<MapArgs>();
  CLI::App* map = app.add_subcommand("map", "The map from a scan log and a pose file, as live mapping makes it");
  CLI::Option* log = map->add_option("--log", map_args->log_path, "Scan log (stridemap record, or live --record)");
  map->add_option("--poses", map_args->mapping.poses_path, "Pose file (docs/live.md)");
  add_mapping_options(*map, map_args->mapping);
  add_output_folder_overwrite_flag(*map, map_args->mapping.overwrite);
  add_map_bag_options(*map, map_args->bag);  // --bag: a ROS 1 bag instead of --log/--poses (docs/ros.md)
  map->callback([map_args, log] {
    if (!map_args->bag.bag_path.empty()) {
      if (log->count() > 0 || !map_args->mapping.poses_path.empty()) {
        throw InputError("--bag: give either --bag or --log with --poses, not both");
      }
      map_args->bag.max_pose_gap_s = map_args->mapping.max_pose_gap_s;  // the map command's options serve both
      map_args->bag.overwrite = map_args->mapping.overwrite;
      if (!map_args->mapping.window.empty()) {
        throw InputError("--window: works with --log; the map of a bag (--bag) follows the robot");
      }
      run_map_bag(map_args->bag, map_args->mapping.config_path, map_args->mapping.out_dir);
      return;
    }
    if (map_args->log_path.empty()) throw InputError("--log is required (or --bag, docs/ros.md)");
    if (map_args->mapping.poses_path.empty()) throw InputError("--poses is required with --log");
    run_map(*map_args);
  });
}

}  // namespace stridemap::cli
