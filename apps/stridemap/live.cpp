// `stridemap live`: a map in real time from a URG (or the emulator) and a
// stream of poses, through the library's LiveMapping loop, which records the
// scans (ScanRecorder) and saves the map (MapSaver) as `map` does
// (map_command.cpp, docs/live.md). This file parses, builds and prints.
#include <cstdio>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "cli_parsing.hpp"
#include "commands.hpp"
#include "live_console.hpp"
#include "mapping_options.hpp"
#include "output_guard.hpp"
#include "report_command.hpp"
#include "urg_device.hpp"
#include "stridemap/core/error.hpp"
#include "stridemap/core/printable_text.hpp"
#include "stridemap/io/output_folder.hpp"
#include "stridemap/live/live_mapping.hpp"
#include "stridemap/live/map_saver.hpp"
#include "stridemap/live/map_window.hpp"
#include "stridemap/live/scan_recorder.hpp"
#include "stridemap/mapfile/tile_store.hpp"

namespace stridemap::cli {
namespace {

struct LiveArgs {
  DeviceArgs device;
  MappingArgs mapping;  ///< its overwrite is --overwrite, for --record and --out
  std::string record_path;
  bool append = false;
  double save_every_s = 5.0;
  double pose_wait_s = 0.5;
  double status_every_s = 1.0;
};

LiveMappingOptions live_options(const LiveArgs& args) {
  if (parse_window_choice(args.mapping.window).mode == WindowChoice::Mode::fit) {
    throw InputError("--window fit: live cannot know beforehand where the run will go; give a centre (--window X,Y) "
                     "or let the window follow the robot (no --window)");
  }
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
  return options;
}

// Every output checked before the sensor is opened, so that a mistake costs no run.
void check_outputs(const LiveArgs& args, ExistingLog log_choice, const LiveMappingOptions& options) {
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
  io::check_output_folder(args.mapping.out_dir, "--out", other_files(args.mapping.overwrite));
  if (args.mapping.report) report_assets_dir();
  const GlobalMapOptions& global_map = options.mapper.config.global_map;
  if (!global_map.folder.empty()) {
    // A resumed map's cell size is its file's, read only when the mapper is made.
    const std::optional<double> cell_size_m =
        args.mapping.resume_path.empty() ? std::optional<double>(options.mapper.config.mapper.grid.cell_size_m)
                                         : std::nullopt;
    io::check_global_map_folder(global_map, cell_size_m);
  }
}

void run_live(const LiveArgs& args) {
  install_stop_signals();
  const LiveMappingOptions options = live_options(args);
  const ExistingLog log_choice = existing_log_choice(args.mapping.overwrite, args.append);
  check_outputs(args, log_choice, options);
  PoseStreamSource poses(args.mapping.poses_path);
  UrgDriverEvent event;
  std::unique_ptr<UrgDriver> driver = start_driver(args.device, event);
  std::fprintf(stderr, "stridemap: connected: %s\n", printable_text(event.message).c_str());
  UrgDriverSource scans(*driver);
  // Only now, with the inputs open and the sensor streaming, is the log touched.
  ScanRecorder recorder = args.record_path.empty() ? ScanRecorder()
                                                   : ScanRecorder(args.record_path, args.device.device,
                                                                  log_choice == ExistingLog::append, scans);
  MapSaver saver(run_info(args.mapping, "live", args.device.device), args.mapping.out_dir);
  const LiveConsole console(*driver, poses);
  std::unique_ptr<LiveMapping> live;
  LiveMappingHooks hooks;
  hooks.on_scan = [&](const UrgScan& scan) {
    // Mapping goes on; said once here, and again at the end.
    if (!recorder.scan(scan)) console.warn(recorder.error() + "; the scans are no longer recorded");
  };
  hooks.on_event = [&](const LiveEvent& e) {
    console.show(e, live->mapper());
    recorder.event(e, scans);
  };
  live = std::make_unique<LiveMapping>(options, scans, poses, saver, hooks);
  const LiveMappingResult result = live->run(stop_flag());
  console.finish();
  recorder.flush();
  const ScanMapper& mapper = live->mapper();
  const LiveRunStats& run = result.run;
  std::printf("live: %zu scans mapped of %zu received (%llu lost, %s), %zu pose lines skipped, CPU %.2f %% of one "
              "core, latency mean %.2f ms max %.2f ms; outputs: %s\n",
              scans_mapped(mapper), mapper.stats().scans, static_cast<unsigned long long>(run.driver.scans_lost),
              rejected_text(mapper).c_str(), poses.skipped_lines(), run.duration_s > 0 ? 100.0 * run.cpu_s / run.duration_s : 0.0,
              run.latency_mean_s * 1000.0, run.latency_max_s * 1000.0, printable_text(args.mapping.out_dir).c_str());
  std::fflush(stdout);
  if (!result.last_save_error.empty()) throw InputError(result.last_save_error + " (the map could not be saved)");
  if (!result.fatal.empty()) throw InputError(args.device.device + ": " + result.fatal + " (the map so far is saved)");
  if (!recorder.error().empty()) {
    throw InputError(recorder.error() + " (the map is saved; the log stops where writing failed)");
  }
  check_finished_run(mapper, filtered_map_layers(mapper, MapFilter::none), live->scan_times(), live->pose_times(),
                     args.mapping, map_run_choices(args.mapping, options.mapper, false));
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
  add_existing_log_flags(*live, args->mapping.overwrite, args->append,
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
}

}  // namespace stridemap::cli
