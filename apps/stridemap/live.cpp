// `stridemap live`: a map in real time from a URG (or the emulator) and a
// stream of poses; `stridemap map`: the same map from a scan log and a pose
// file. Both go through ScanMapper and the same writers (docs/live.md).
#include <unistd.h>

#include <algorithm>
#include <cstdio>
#include <deque>
#include <memory>
#include <string>
#include <vector>

#include "cli_parsing.hpp"
#include "commands.hpp"
#include "stridemap/core/error.hpp"
#include "stridemap/core/printable_text.hpp"
#include "stridemap/io/map_outputs.hpp"
#include "stridemap/io/pose_stream.hpp"
#include "stridemap/io/scan_log.hpp"
#include "stridemap/live/map_report.hpp"
#include "urg_device.hpp"

namespace stridemap::cli {
namespace {

struct MappingArgs {
  std::string poses_path;
  std::string out_dir;
  std::string config_path;
  std::string filters = "none";
  std::string clock = "host";
  double max_pose_gap_s = 1.0;
};

void add_mapping_options(CLI::App& command, MappingArgs& args) {
  command.add_option("--out", args.out_dir, "Output folder: elevation/certainty PNG and CSV, state.csv, summary.json")
      ->required();
  command.add_option("--config", args.config_path, "Mapper configuration (YAML, docs/config.md)");
  command.add_option("--filters", args.filters,
                     "Scan filters in order: range-clustering, scan-sequence, shadow, speckle; paper; none")
      ->capture_default_str();
  command.add_option("--clock", args.clock,
                     "Clock of the pose times: host (Unix time of each scan's step 0, estimated by the driver) or "
                     "sensor (the URG's millisecond clock, in seconds)")
      ->capture_default_str();
  command.add_option("--max-pose-gap-s", args.max_pose_gap_s,
                     "Do not interpolate between poses farther apart than this")
      ->capture_default_str()
      ->check(number_from_to(0.001, 1e9, "s"));
}

ScanMapperOptions mapper_options(const MappingArgs& args) {
  if (args.clock != "host" && args.clock != "sensor") {
    throw InputError("--clock: '" + args.clock + "' is not a clock; use host or sensor");
  }
  ScanMapperOptions options;
  if (!args.config_path.empty()) options.config = load_mapper_config(args.config_path);
  options.filters = parse_scan_filter_list(args.filters);
  return options;
}

double scan_time(const UrgScan& scan, const std::string& clock) {
  return clock == "sensor" ? sensor_time_seconds(scan.sensor_time_ms) : scan.host_time_s;
}

// ---------------------------------------------------------------- live

struct LiveArgs {
  DeviceArgs device;
  MappingArgs mapping;
  std::string record_path;
  double save_every_s = 5.0;
  double pose_wait_s = 0.5;
  double status_every_s = 1.0;
};

class LatencyMeter {
 public:
  void add(double seconds) {
    samples_.push_back(seconds);
    sum_ += seconds;
    max_ = std::max(max_, seconds);
  }
  void fill(LiveRunStats& out) {
    out.latency_samples = samples_.size();
    if (samples_.empty()) return;
    out.latency_mean_s = sum_ / static_cast<double>(samples_.size());
    out.latency_max_s = max_;
    std::vector<double> sorted = samples_;
    const std::size_t k = std::min(sorted.size() - 1, static_cast<std::size_t>(0.99 * static_cast<double>(sorted.size())));
    std::nth_element(sorted.begin(), sorted.begin() + static_cast<std::ptrdiff_t>(k), sorted.end());
    out.latency_p99_s = sorted[k];
  }

 private:
  std::vector<double> samples_;
  double sum_ = 0.0, max_ = 0.0;
};

void run_live(const LiveArgs& args) {
  install_stop_signals();
  if (!(args.save_every_s > 0.0)) throw InputError("--save-every-s must be positive");
  if (!(args.pose_wait_s >= 0.0)) throw InputError("--pose-wait-s must be >= 0");
  const ScanMapperOptions options = mapper_options(args.mapping);
  io::PoseStreamReader poses(args.mapping.poses_path);
  PoseTrack track(args.mapping.max_pose_gap_s);
  std::unique_ptr<io::ScanLogWriter> log;
  if (!args.record_path.empty()) log = std::make_unique<io::ScanLogWriter>(args.record_path, args.device.device);

  const double cpu_start = process_cpu_seconds();
  UrgDriverEvent event;
  std::unique_ptr<UrgDriver> driver = start_driver(args.device, event);
  std::fprintf(stderr, "stridemap: connected: %s\n", printable_text(event.message).c_str());
  if (log) log->write_sensor(host_seconds(), driver->version(), driver->parameters());
  const scip::ScipParameters sensor = driver->parameters();
  ScanMapper mapper(options, driver->urg_parameters());
  const MapRunInfo info{"live", args.device.device, args.mapping.poses_path, args.mapping.clock, {}};

  LatencyMeter latency;
  std::deque<double> receive_times;  // of the scans queued in the mapper, oldest first
  const double start = monotonic_seconds();
  double next_save = start + args.save_every_s;
  double next_status = start + args.status_every_s;
  const bool tty = ::isatty(STDERR_FILENO) != 0;
  const auto run_stats = [&] {
    LiveRunStats run;
    run.duration_s = monotonic_seconds() - start;
    run.cpu_s = process_cpu_seconds() - cpu_start;
    run.driver = driver->stats();
    latency.fill(run);
    return run;
  };
  // Scans leave the mapper's queue in order; the ones integrated count for latency.
  const auto account = [&](std::size_t integrated_before) {
    const std::size_t left = mapper.waiting();
    const std::size_t integrated = mapper.stats().integrated - integrated_before;
    const std::size_t consumed = receive_times.size() - left;
    const double now = host_seconds();
    for (std::size_t i = 0; i < consumed; ++i) {
      if (i < integrated) latency.add(now - receive_times.front());  // process() integrates before expire() skips
      receive_times.pop_front();
    }
  };
  const auto print_status = [&](double now) {
    const UrgDriverStats& d = driver->stats();
    const io::MapLayers layers = io::export_map_layers(mapper.mapper().map());
    std::fprintf(stderr,
                 "%slive: %.1f scans/s, %llu scans, %llu lost, %llu faults, %zu mapped, %zu waiting for poses, "
                 "coverage %.1f %%%s",
                 tty ? "\r" : "", static_cast<double>(d.scans) / std::max(1e-9, now - start),
                 static_cast<unsigned long long>(d.scans), static_cast<unsigned long long>(d.scans_lost),
                 static_cast<unsigned long long>(d.faults), mapper.stats().integrated, mapper.waiting(),
                 100.0 * io::map_coverage(layers), tty ? "\x1b[K" : "\n");
  };
  // A bad pose line or another sensor ends live mapping with an error, but
  // only after the map so far is saved.
  std::string fatal;
  constexpr std::size_t kMaxPoses = 200000;  // over half an hour at 100 Hz
  bool warned_clock = false;
  while (!stop_requested() && fatal.empty()) {
    try {
      const double now = monotonic_seconds();
      if (args.device.duration_s > 0.0 && now - start >= args.device.duration_s) break;
      // Counted as handed out, not as the driver queues them.
      if (args.device.max_scans > 0 && mapper.stats().scans >= args.device.max_scans && mapper.waiting() == 0) break;
      if (now >= next_save) {
        write_map_outputs(mapper, sensor, info, nullptr, args.mapping.out_dir);
        next_save = now + args.save_every_s;
      }
      if (now >= next_status) {
        print_status(now);
        next_status = now + args.status_every_s;
      }
      poses.poll(track);
      const std::size_t integrated_before = mapper.stats().integrated;
      if (driver->next(event, 0.05)) {
        switch (event.kind) {
          case UrgDriverEvent::Kind::scan: {
            if (log) log->write_scan(event.scan);
            UrgRawScan raw = event.scan.raw;
            raw.time_s = scan_time(event.scan, args.mapping.clock);
            mapper.add(raw, now);
            receive_times.push_back(event.scan.host_receive_time_s);
            poses.poll(track);
            break;
          }
          case UrgDriverEvent::Kind::fault:
            if (tty) std::fputc('\n', stderr);
            print_fault(event);
            if (log) log->write_fault(host_seconds(), event.fault, event.count, event.message);
            break;
          case UrgDriverEvent::Kind::connected:
            if (log) log->write_sensor(host_seconds(), driver->version(), driver->parameters());
            if (!(driver->parameters() == sensor)) {
              throw InputError(args.device.device + ": another sensor answered after the reconnection (" +
                               driver->parameters().model + "); restart live mapping for it");
            }
            break;
        }
      }
      mapper.process(track, false);
      mapper.expire(now - args.pose_wait_s);
      account(integrated_before);
      if (track.size() > kMaxPoses) {
        // Poses far ahead of every scan: the clocks do not match. Keep memory bounded and say so once.
        if (!warned_clock) {
          std::fprintf(stderr, "stridemap: warning: %zu poses and no scan within their times; do the poses use "
                               "the clock given with --clock (%s)?\n",
                       track.size(), args.mapping.clock.c_str());
          warned_clock = true;
        }
        track.drop_before(track.last_time_s() - 60.0);
      }
    } catch (const InputError& e) {
      fatal = e.what();
    }
  }
  if (tty) std::fputc('\n', stderr);
  driver->stop();
  // The end: poses are complete now, as they are for a replay of the same data.
  if (fatal.empty()) {
    try {
      poses.poll(track);
    } catch (const InputError& e) {
      fatal = e.what();
    }
  }
  const std::size_t integrated_before = mapper.stats().integrated;
  mapper.process(track, true);
  account(integrated_before);
  mapper.finish();
  if (log) log->flush();
  const LiveRunStats run = run_stats();
  const io::MapLayers layers = write_map_outputs(mapper, sensor, info, &run, args.mapping.out_dir);
  std::printf("live: %zu scans mapped of %zu received (%llu lost), coverage %.1f %%, CPU %.2f %% of one core, "
              "latency mean %.2f ms max %.2f ms; outputs: %s\n",
              mapper.stats().integrated, mapper.stats().scans, static_cast<unsigned long long>(run.driver.scans_lost),
              100.0 * io::map_coverage(layers), run.duration_s > 0 ? 100.0 * run.cpu_s / run.duration_s : 0.0,
              run.latency_mean_s * 1000.0, run.latency_max_s * 1000.0, args.mapping.out_dir.c_str());
  if (!fatal.empty()) throw InputError(fatal + " (the map so far is saved)");
}

// ---------------------------------------------------------------- map

struct MapArgs {
  std::string log_path;
  MappingArgs mapping;
};

void run_map(const MapArgs& args) {
  const ScanMapperOptions options = mapper_options(args.mapping);
  const io::ScanLog log = io::read_scan_log(args.log_path);
  if (!log.damage.empty()) {
    std::fprintf(stderr, "stridemap: warning: %s; mapping the %zu scans before it\n", printable_text(log.damage).c_str(),
                 log.scans.size());
  }
  PoseTrack track(args.mapping.max_pose_gap_s);
  for (const TimedPose& pose : io::read_pose_file(args.mapping.poses_path)) track.append(pose);
  ScanMapper mapper(options, scip::to_urg_parameters(log.parameters));
  for (const UrgScan& scan : log.scans) {
    UrgRawScan raw = scan.raw;
    raw.time_s = scan_time(scan, args.mapping.clock);
    mapper.add(raw);
    mapper.process(track, true);
  }
  mapper.finish();
  const MapRunInfo info{"map", args.log_path, args.mapping.poses_path, args.mapping.clock, log.damage};
  const io::MapLayers layers = write_map_outputs(mapper, log.parameters, info, nullptr, args.mapping.out_dir);
  const ScanMapperStats& s = mapper.stats();
  std::printf("map: %zu scans mapped of %zu (%zu before the first pose, %zu after the last, %zu in pose gaps), "
              "coverage %.1f %%; outputs: %s\n",
              s.integrated, s.scans, s.before_first_pose, s.after_last_pose, s.pose_gap,
              100.0 * io::map_coverage(layers), args.mapping.out_dir.c_str());
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
  map->add_option("--log", map_args->log_path, "Scan log (stridemap record, or live --record)")->required();
  map->add_option("--poses", map_args->mapping.poses_path, "Pose file (docs/live.md)")->required();
  add_mapping_options(*map, map_args->mapping);
  map->callback([map_args] { run_map(*map_args); });
}

}  // namespace stridemap::cli
