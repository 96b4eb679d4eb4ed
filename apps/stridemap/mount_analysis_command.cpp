// `stridemap experiment mount-analysis`: sensor mounts compared on random
// step fields (Figs. 5 and 7), simulated.
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <memory>
#include <numbers>
#include <optional>
#include <string>
#include <vector>

#include "cli_parsing.hpp"
#include "output_guard.hpp"
#include "terminal_output.hpp"
#include "stridemap/experiments/mount_analysis.hpp"
#include "stridemap/experiments/mount_analysis_report.hpp"
#include "report_command.hpp"
#include "stridemap/experiments/structured_light_walk_sensor.hpp"
#include "stridemap/experiments/urg_walk_sensor.hpp"
#include "walk_cli_common.hpp"

namespace stridemap::cli {
namespace {

struct MountAnalysisArgs {
  bool overwrite = false;
  bool report = false;
  std::string sensor = "urg";
  std::string out_dir;
  std::uint64_t seed = 1;
  int fields = 2;
  std::optional<std::string> heights_cm;
  std::optional<std::string> pitches_deg;
};

/// "a:b:step" (a, a + step, ... up to b) or "a,b,c"; every value >= 0.
std::vector<double> parse_grid(const std::string& option, const std::string& text) {
  const auto colon = std::count(text.begin(), text.end(), ':');
  if (colon == 0) return parse_number_list(option, text);
  if (colon != 2) throw InputError(option + ": expected start:stop:step or a comma-separated list, got '" + text + "'");
  std::vector<std::string> parts(3);
  std::size_t k = 0;
  for (char c : text) (c == ':' ? parts[++k] : parts[k]) += c == ':' ? std::string() : std::string(1, c);
  const double start = parse_number_list(option, parts[0]).at(0);
  const double stop = parse_number_list(option, parts[1]).at(0);
  const double step = parse_number_list(option, parts[2]).at(0);
  if (!(step > 0.0)) throw InputError(option + ": the step must be positive, got '" + parts[2] + "'");
  std::vector<double> values;
  for (double v = start; v <= stop + 1e-9 * step && values.size() <= 10000; v = start + step * static_cast<double>(values.size())) {
    values.push_back(v);
  }
  return values;  // empty when stop < start: run_mount_analysis reports the empty grid
}

void run_mount_analysis_command(const MountAnalysisArgs& args) {
  if (args.report) report_assets_dir();  // before the run, not after it
  const SimulatedSensor sensor = parse_option<SimulatedSensor>("--sensor", args.sensor);
  const bool urg = sensor == SimulatedSensor::urg;
  MountAnalysisOptions options;
  options.seed = args.seed;
  options.fields = args.fields;
  if (!urg) {
    // Ragno, the paper's structured-light robot, is smaller than Messor:
    // 5 mm cells (section 5.1), a narrower strip of feet and a shorter
    // stride ahead (docs/experiments.md).
    options.cell_size_m = 0.005;
    options.corridor_half_width_m = 0.15;
    options.score.min_stripe_width_m = 0.3;
    options.score.min_look_ahead_m = 0.15;
  }
  const std::string heights = args.heights_cm.value_or(urg ? "12:36:4" : "10:30:4");
  const std::string pitches = args.pitches_deg.value_or(urg ? "10:60:5" : "0:40:5");
  for (double cm : parse_grid("--heights-cm", heights)) options.sweep_heights_m.push_back(cm / 100.0);
  for (double deg : parse_grid("--pitches-deg", pitches)) options.sweep_pitches_rad.push_back(deg * std::numbers::pi / 180.0);
  options.validate();

  io::ProgressBar bar = progress_bar("mount-analysis", "mounts");
  options.progress = bar.callback();
  MountAnalysisResult result;
  if (sensor == SimulatedSensor::urg) {
    const UrgWalkSensorOptions base;
    const MountSensorFactory factory = [base, seed = args.seed](const Scene& scene, const NamedMount& mount,
                                                                 const UpdateOptions& update) -> std::unique_ptr<WalkSensor> {
      UrgWalkSensorOptions o = base;
      o.mount = mount.mount;
      return std::make_unique<UrgWalkSensor>(scene, o, update, seed);
    };
    const MountRangeShare share = [urg = base.urg](const NamedMount& mount) -> std::optional<double> {
      return urg_share_in_range_interval(mount.mount, urg);
    };
    result = run_mount_analysis(paper_urg_mounts(), factory, share, options);
  } else {
    result = run_mount_analysis(paper_structured_light_mounts(), structured_light_mount_sensor_factory(args.seed),
                                nullptr, options);
  }
  const std::string dir = (std::filesystem::path(args.out_dir) / ("mount-analysis-" + result.sensor)).string();
  bar.clear();
  write_output_set(dir, "--out", [&](const std::string& folder) {
    write_mount_analysis_outputs(result, options, folder);
    if (args.report) write_run_report(folder, dir);
  }, other_files(args.overwrite));
  note("wrote " + dir);
  std::fputs(mount_analysis_table(result).c_str(), stdout);
  print_outputs_line(dir);
}

}  // namespace

WalkSensorFactory structured_light_walk_sensor_factory(std::uint64_t seed, StripePipeline pipeline) {
  StructuredLightWalkSensorOptions base;
  base.pipeline = pipeline;
  return [base, seed](const Scene& scene, const UpdateOptions& update) -> std::unique_ptr<WalkSensor> {
    return std::make_unique<StructuredLightWalkSensor>(scene, base, update, seed);
  };
}

MountSensorFactory structured_light_mount_sensor_factory(std::uint64_t seed) {
  return [seed](const Scene& scene, const NamedMount& mount, const UpdateOptions& update) -> std::unique_ptr<WalkSensor> {
    StructuredLightWalkSensorOptions o;
    o.parameters.mount = mount.mount;
    if (mount.sheet_angle_rad) o.parameters.sheet_angle_rad = *mount.sheet_angle_rad;
    return std::make_unique<StructuredLightWalkSensor>(scene, o, update, seed);
  };
}

void register_mount_analysis(CLI::App* experiment) {
  auto args = std::make_shared<MountAnalysisArgs>();
  CLI::App* cmd = experiment->add_subcommand(
      "mount-analysis", "Sensor mounts compared on random step fields: occlusions, uncertainty, stripe (Figs. 5, 7), simulated");
  add_report_flag(*cmd, args->report);
  cmd->add_option("--sensor", args->sensor, "Sensor: urg or structured-light")->capture_default_str();
  cmd->add_option("--out", args->out_dir, "Output folder; results go to OUT/mount-analysis-<sensor>/")->required();
  add_output_folder_overwrite_flag(*cmd, args->overwrite);
  cmd->add_option("--seed", args->seed, "Seed of the step fields and the simulation")->capture_default_str()
      ->check(seed_value());
  cmd->add_option("--fields", args->fields, "Random step fields walked per mount")->capture_default_str()
      ->check(whole_from_to(1, 10000));
  cmd->add_option("--heights-cm", args->heights_cm,
                  "Sweep heights: start:stop:step or a list [cm]; default 12:36:4 (urg), 10:30:4 (structured-light)");
  cmd->add_option("--pitches-deg", args->pitches_deg,
                  "Sweep pitches: start:stop:step or a list [deg]; default 10:60:5 (urg), 0:40:5 (structured-light)");
  cmd->callback([args] { run_mount_analysis_command(*args); });
}

}  // namespace stridemap::cli
