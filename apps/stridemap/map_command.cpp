// `stridemap map`: the map from a scan log and a pose file, as live mapping
// makes it: the same ScanMapper, run information and writers (docs/live.md).
#include <cstdio>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "cli_parsing.hpp"
#include "commands.hpp"
#include "map_bag.hpp"
#include "mapping_options.hpp"
#include "output_guard.hpp"
#include "terminal_output.hpp"
#include "window_placement.hpp"
#include "stridemap/core/error.hpp"
#include "stridemap/core/printable_text.hpp"
#include "stridemap/io/output_folder.hpp"
#include "stridemap/live/log_replay.hpp"
#include "stridemap/live/map_saver.hpp"
#include "stridemap/live/map_window.hpp"
#include "stridemap/mapfile/map_outputs.hpp"
#include "stridemap/recordings/pose_stream.hpp"
#include "stridemap/recordings/scan_log.hpp"
#include "report_command.hpp"

namespace stridemap::cli {
namespace {

struct MapArgs {
  std::string log_path;
  MappingArgs mapping;
  MapBagArgs bag;
};

void print_skipped(const std::string& what, std::size_t count, const std::vector<std::string>& first) {
  if (count == 0) return;
  std::fprintf(stderr, "stridemap: warning: %zu %s skipped:\n", count, printable_text(what).c_str());
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
  // The poses too are read as the scans need them: a long run holds the
  // poses just ahead of its scans, not the file.
  io::PoseFileCursor poses(args.mapping.poses_path);
  if (fit) {
    fit_window(options, args.log_path, args.mapping.poses_path, args.mapping.max_pose_gap_s, clock);
    opened.emplace(args.log_path, options, clock);
  }
  LogReplay& replay = *opened;
  if (options.resume) note("going on from the map in " + args.mapping.resume_path);
  {
    PoseTrack track(args.mapping.max_pose_gap_s);
    replay.read_poses_with([&poses](double time_s, PoseTrack& t) { poses.read_to(time_s, t); });
    io::ProgressBar bar = progress_bar("map", "scans");
    replay.run(track, [&bar](std::size_t scans) { bar.update(scans, 0); });
  }
  poses.read_rest();  // for the counts and the time range the checks below tell
  print_skipped("bad pose lines", poses.problems().count, poses.problems().first);
  const TimeRange pose_times{poses.poses(), poses.first_time_s(), poses.last_time_s()};
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
  MapSaver saver(run_info(args.mapping, "map", args.log_path), args.mapping.out_dir);
  saver.info().log_damage = log.damage;
  saver.info().log_lines_skipped = log.skipped_line_numbers.size();
  saver.info().log_stop = log.stop;
  saver.info().pose_lines_skipped = poses.problems().count;
  const ExportedMap layers = saver.save(mapper, log.parameters);
  const ScanMapperStats& s = mapper.stats();
  std::printf("map: %zu scans mapped of %zu (%zu before the first pose, %zu after the last, %zu in pose gaps, %s), "
              "coverage %.1f %%; outputs: %s\n",
              scans_mapped(mapper), s.scans, s.before_first_pose, s.after_last_pose, s.pose_gap,
              rejected_text(mapper).c_str(), 100.0 * map_coverage(layers), printable_text(args.mapping.out_dir).c_str());
  std::fflush(stdout);
  check_finished_run(mapper, layers, replay.scan_times(), pose_times, args.mapping,
                     map_run_choices(args.mapping, options, true));
}

}  // namespace

void register_map(CLI::App& app) {
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
