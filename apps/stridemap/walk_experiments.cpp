// `stridemap experiment rocky-walk` and `mount-analysis`: the walking robot
// (paper sections 4.2, 5.1, 5.2, 6.2), simulated.
#include <cstdio>
#include <filesystem>
#include <memory>
#include <numbers>
#include <optional>
#include <string>
#include <vector>

#include "commands.hpp"
#include "installed_data.hpp"
#include "terminal_output.hpp"
#include "output_guard.hpp"
#include "stridemap/core/error.hpp"
#include "stridemap/experiments/rocky_walk.hpp"
#include "stridemap/experiments/rocky_walk_report.hpp"
#include "report_command.hpp"
#include "stridemap/config/scene_yaml.hpp"
#include "stridemap/config/walk_path_yaml.hpp"
#include "stridemap/experiments/urg_walk_sensor.hpp"
#include "stridemap/experiments/wall_range_calibration.hpp"
#include "cli_parsing.hpp"
#include "walk_cli_common.hpp"

namespace stridemap::cli {
namespace {

struct RockyWalkArgs {
  bool overwrite = false;
  bool report = false;
  std::string sensor = "urg";
  static constexpr const char* kDefaultScene = "scenes/rocky_mockup.yaml";
  std::string scene_path = kDefaultScene;
  std::string path_file;
  std::string out_dir;
  std::uint64_t seed = 1;
  double pose_error_scale = 1.0;
  std::optional<double> imu_pitch_bias_deg, imu_roll_bias_deg;
  std::optional<double> imu_pitch_noise_deg, imu_roll_noise_deg, camera_yaw_noise_deg;
  std::optional<double> camera_position_noise_m, leg_height_noise_m;
  std::string sweep = "0,0.5,1,2,4";
  std::optional<std::string> reference;           // map-footholds
  std::optional<std::string> calibrate_attitude;  // on
  std::string calibrate_range = "off";  // URG only
  std::string feet = "stand";
  std::optional<double> foothold_map_sigma_m;
  std::optional<double> foothold_gate_sigmas;
  std::optional<std::string> foothold_odometry;  // on (structured-light), off (urg)
  std::string mixed_pixels = "off";
  std::string coupling = "on";
  std::string visibility = "off";
  std::string pipeline = "geometric";
  std::string filters;
  std::optional<std::string> map_filter;
  std::string elevation_rule = "paper";
  std::optional<double> cell_size_m;
  std::optional<int> cells_per_side;
};

void run_rocky_walk_command(const RockyWalkArgs& args) {
  // Everything the user typed is checked before the scene is even read.
  const SimulatedSensor sensor = parse_option<SimulatedSensor>("--sensor", args.sensor);
  const StripePipeline pipeline = parse_option<StripePipeline>("--pipeline", args.pipeline);
  RockyWalkOptions options;
  options.walk.seed = args.seed;
  options.pose_error_scales = parse_number_list("--sweep", args.sweep);
  // Ours for both sensors: h_ref from the fused layer where the stance feet
  // stand, after calibrating the IMU's biases on a flat floor
  // (docs/walking.md); for structured light, whose stripe leaves the feet
  // on unknown cells for seconds, carried by leg odometry between readings
  // (below). The paper's (`map`) drifts by centimetres there.
  const bool urg_sensor = sensor == SimulatedSensor::urg;
  options.walk.pose_errors.reference = parse_option<ReferenceElevationSource>("--reference", args.reference.value_or("map-footholds"));
  options.calibrate_attitude = parse_on_off("--calibrate-attitude", args.calibrate_attitude.value_or("on"));
  if (!urg_sensor) options.calibration = AttitudeCalibrationOptions::wide_stances();
  if (urg_sensor) options.sweep_references.push_back(ReferenceElevationSource::map_fused);
  if (args.feet != "stand" && args.feet != "slide") {
    throw InputError("--feet: '" + args.feet + "' is not one of stand, slide");
  }
  options.walk.gait.feet_stand_in_stance = args.feet == "stand";
  if (args.foothold_map_sigma_m) options.walk.pose_errors.foothold_map_sigma_m = *args.foothold_map_sigma_m;
  if (args.foothold_gate_sigmas) options.walk.pose_errors.foothold_gate_sigmas = *args.foothold_gate_sigmas;
  options.walk.pose_errors.foothold_odometry =
      parse_on_off("--foothold-odometry", args.foothold_odometry.value_or(urg_sensor ? "off" : "on"));
  constexpr double deg = std::numbers::pi / 180.0;
  if (args.imu_pitch_bias_deg) options.walk.pose_errors.imu_pitch_bias_rad = *args.imu_pitch_bias_deg * deg;
  if (args.imu_roll_bias_deg) options.walk.pose_errors.imu_roll_bias_rad = *args.imu_roll_bias_deg * deg;
  // One error at a time, to see which one the map answers to (the sweep's
  // --pose-error-scale multiplies them all).
  PoseErrorOptions& errors = options.walk.pose_errors;
  if (args.imu_pitch_noise_deg) errors.imu_pitch_noise_sigma_rad = *args.imu_pitch_noise_deg * deg;
  if (args.imu_roll_noise_deg) errors.imu_roll_noise_sigma_rad = *args.imu_roll_noise_deg * deg;
  if (args.camera_yaw_noise_deg) errors.camera_yaw_noise_sigma_rad = *args.camera_yaw_noise_deg * deg;
  if (args.camera_position_noise_m) errors.camera_position_noise_sigma_m = *args.camera_position_noise_m;
  if (args.leg_height_noise_m) errors.leg_height_noise_sigma_m = *args.leg_height_noise_m;
  options.walk.pose_errors = options.walk.pose_errors.scaled(checked_non_negative("--pose-error-scale", args.pose_error_scale));
  // The paper's settings per sensor (sections 5.1, 5.3): the URG with 10 mm
  // cells and the fill-in, structured light with 5 mm cells and the CAS
  // filter; 200 cells keep the stripe, 0.2-0.3 m ahead, inside the window.
  const bool urg = sensor == SimulatedSensor::urg;
  options.walk.map_filter = parse_map_filter(args.map_filter.value_or(urg ? "fill" : "cas"));
  options.walk.mapper.update.elevation_rule = parse_elevation_rule(args.elevation_rule);
  options.walk.mapper.grid = {args.cells_per_side.value_or(urg ? 100 : 200), args.cell_size_m.value_or(urg ? 0.01 : 0.005)};
  ElevationMap(options.walk.mapper.grid);  // throws for an unusable grid
  options.validate();
  const bool mixed = parse_on_off("--mixed-pixels", args.mixed_pixels);
  const bool coupling = parse_on_off("--coupling", args.coupling);
  const bool calibrate_range = parse_on_off("--calibrate-range", args.calibrate_range);
  if (!urg && calibrate_range) throw InputError("--calibrate-range applies to the URG only, not to --sensor structured-light");
  const bool visibility = parse_on_off("--visibility", args.visibility);
  if (!urg && visibility) throw InputError("--visibility applies to the URG only, not to --sensor structured-light");
  if (!urg && (mixed || !args.filters.empty())) {
    throw InputError("--mixed-pixels and --filters apply to the URG only, not to --sensor structured-light");
  }
  // With mixed pixels the paper pre-processes every scan (section 5.3).
  const std::string filter_names = args.filters.empty() ? (mixed ? "paper" : "none") : args.filters;
  const std::vector<ScanFilterKind> filters = parse_scan_filter_list(filter_names);

  // Only now, after every option was checked: a bad option is named first.
  const std::string scene_path = resolve_default_data_file("--scene", args.scene_path, RockyWalkArgs::kDefaultScene);
  const Scene scene = load_scene_yaml(scene_path);
  WalkPath path;
  RockyWalkRunInfo info{scene_path, args.path_file};
  if (!args.path_file.empty()) {
    path = load_walk_path_yaml(args.path_file, &scene.terrain);
  } else if (scene.walk_path) {
    path = *scene.walk_path;
    info.path_source = scene_path + ":walk_path";
  } else {
    throw InputError(scene_path + ": the scene has no walk_path section; give a path file with --path");
  }

  WalkSensorFactory factory;
  std::optional<RangeCalibrationFit> range_calibration;
  if (urg) {
    UrgWalkSensorOptions urg_options;
    urg_options.mixed_pixels = mixed;
    urg_options.sim.receiver.enabled = coupling;
    urg_options.filters = filters;
    urg_options.visibility.enabled = visibility;
    // Before the flat-floor attitude calibration, which would otherwise take
    // the short readings at the floor's ranges for a pitch bias.
    if (calibrate_range) {
      range_calibration = calibrate_range_on_wall(urg_options.urg, urg_options.sim, wall_calibration_seed(args.seed));
      urg_options.calibration = range_calibration->calibration;
    }
    factory = [urg_options, seed = args.seed](const Scene& s, const UpdateOptions& update) -> std::unique_ptr<WalkSensor> {
      return std::make_unique<UrgWalkSensor>(s, urg_options, update, seed);
    };
  } else {
    factory = structured_light_walk_sensor_factory(args.seed, pipeline);
  }
  const std::vector<NamedPath> inputs{{"--scene", scene_path}, {"--path", args.path_file}};
  const std::string early_dir = (std::filesystem::path(args.out_dir) / ("rocky-walk-" + args.sensor)).string();
  refuse_output_that_is_an_input("--out", early_dir, inputs);
  io::check_output_folder(early_dir, "--out", other_files(args.overwrite));
  if (args.report) report_assets_dir();  // before the run, not after it
  io::ProgressBar bar = progress_bar("rocky-walk", "scans");
  options.progress = bar.callback();
  RockyWalkResult result =
      naming_grid_setting("--cell-size-m " + number_text(options.walk.mapper.grid.cell_size_m),
                          [&] { return run_rocky_walk(scene, path, factory, options); });
  result.range_calibration = range_calibration;
  if (urg) result.receiver_coupling = mixed && coupling;
  const std::string dir = (std::filesystem::path(args.out_dir) / ("rocky-walk-" + result.sensor)).string();
  refuse_output_that_is_an_input("--out", dir, inputs);
  bar.clear();
  write_output_set(dir, "--out", [&](const std::string& folder) {
    write_rocky_walk_outputs(result, options, info, folder);
    if (args.report) write_run_report(folder, dir);
  }, other_files(args.overwrite));
  note("wrote " + dir);
  std::fputs(rocky_walk_table(result).c_str(), stdout);
  print_outputs_line(dir);
}

}  // namespace

void register_walk_experiments(CLI::App& app) {
  CLI::App* experiment = app.get_subcommand("experiment");

  auto rw = std::make_shared<RockyWalkArgs>();
  CLI::App* rocky = experiment->add_subcommand(
      "rocky-walk", "A walking robot maps the rocky mock-up with an imperfect pose (Figs. 22-24), simulated");
  add_report_flag(*rocky, rw->report);
  rocky->add_option("--sensor", rw->sensor, "Sensor: urg or structured-light")->capture_default_str();
  rocky->add_option("--scene", rw->scene_path, "Scene file (YAML, docs/scenes.md)")->capture_default_str();
  rocky->add_option("--path", rw->path_file, "Path file (YAML, docs/walking.md); default: the scene's walk_path");
  rocky->add_option("--out", rw->out_dir, "Output folder; results go to OUT/rocky-walk-<sensor>/")->required();
  add_output_folder_overwrite_flag(*rocky, rw->overwrite);
  rocky->add_option("--seed", rw->seed, "Seed of the simulation")->capture_default_str()
      ->check(seed_value());
  rocky->add_option("--pose-error-scale", rw->pose_error_scale,
                    "Factor on every pose error of the main walk (docs/walking.md has the defaults)")
      ->capture_default_str()
      ->check(number_from_to(0.0, 1000.0));
  rocky->add_option("--imu-pitch-bias-deg", rw->imu_pitch_bias_deg, "IMU pitch bias [deg] (default -0.3)")
      ->check(number_from_to(-90.0, 90.0, "deg"));
  rocky->add_option("--imu-roll-bias-deg", rw->imu_roll_bias_deg, "IMU roll bias [deg] (default 0.3)")
      ->check(number_from_to(-90.0, 90.0, "deg"));
  rocky->add_option("--imu-pitch-noise-deg", rw->imu_pitch_noise_deg, "IMU pitch noise sigma, per scan [deg] (default 0.2)")
      ->check(number_from_to(0.0, 90.0, "deg"));
  rocky->add_option("--imu-roll-noise-deg", rw->imu_roll_noise_deg, "IMU roll noise sigma, per scan [deg] (default 0.2)")
      ->check(number_from_to(0.0, 90.0, "deg"));
  rocky->add_option("--camera-position-noise-m", rw->camera_position_noise_m,
                    "Camera x and y noise sigma, per scan and axis [m] (default 0.003)")
      ->check(number_from_to(0.0, 1.0, "m"));
  rocky->add_option("--camera-yaw-noise-deg", rw->camera_yaw_noise_deg, "Camera yaw noise sigma, per scan [deg] (default 0.3)")
      ->check(number_from_to(0.0, 90.0, "deg"));
  rocky->add_option("--leg-height-noise-m", rw->leg_height_noise_m,
                    "Leg kinematics noise sigma, per scan, foot and axis [m] (default 0.002)")
      ->check(number_from_to(0.0, 1.0, "m"));
  rocky->add_option("--sweep", rw->sweep, "Pose-error factors of the sweep, comma separated; none for no sweep")
      ->capture_default_str();
  rocky->add_option("--reference", rw->reference,
                    "h_ref from the map (section 5.2: the elevation layer), map-mean (the cells' means of accepted "
                    "readings), map-fused (variance-weighted, Mahalanobis-gated layer, at the feet's nominal places), "
                    "map-footholds (that layer where the stance feet stand, by leg kinematics), legs (trunk z from leg "
                    "kinematics + IMU on footholds fused with that layer) or truth; default map-footholds");
  rocky->add_option("--calibrate-attitude", rw->calibrate_attitude,
                    "on: measure the IMU's pitch and roll biases on a flat floor before each walk and take them off; "
                    "default on");
  rocky->add_option("--calibrate-range", rw->calibrate_range,
                    "on: calibrate the URG's range on a wall (Fig. 6's procedure, simulated) before the walk and map with "
                    "the correction; off: raw ranges (the paper's walk)")
      ->capture_default_str();
  rocky->add_option("--feet", rw->feet,
                    "stand: a stance foot stands still on its foothold and steps in swing; slide: the feet slide with "
                    "the trunk (the simpler model)")
      ->capture_default_str();
  rocky->add_option("--foothold-map-sigma-m", rw->foothold_map_sigma_m,
                    "With --reference legs: the sigma given to the map's height under a landing foot against the leg "
                    "odometry [m]; default 0.003; a large value (1) all but ignores the map")
      ->check(number_from_to(0.0, 1000.0, "m"));
  rocky->add_option("--foothold-gate-sigmas", rw->foothold_gate_sigmas,
                    "With --reference map-footholds: a stance foot whose trunk height is this many sigmas from the "
                    "other feet's is left out; default 2.5; a large value (1e9) keeps every foot")
      ->check(number_from_to(1e-3, 1e12));
  rocky->add_option("--foothold-odometry", rw->foothold_odometry,
                    "With --reference map-footholds: on, leg odometry carries the height between the feet's map "
                    "readings and gates them; off, each scan's readings alone (a scan without one keeps the last); "
                    "default on (structured-light), off (urg)");
  rocky->add_option("--mixed-pixels", rw->mixed_pixels, "on: footprint beam model with mixed pixels at edges")
      ->capture_default_str();
  rocky->add_option("--coupling", rw->coupling,
                    "With --mixed-pixels on: range-intensity coupling through the receiver's gain control "
                    "(docs/mixed_pixels.md), on or off")
      ->capture_default_str();
  rocky->add_option("--visibility", rw->visibility,
                    "on: the visibility clean-up (docs/visibility.md) clears what beams pass below; the walk counts "
                    "the cells it cleared against the truth")
      ->capture_default_str();
  rocky->add_option("--filters", rw->filters, "Scan filters (as for cart-rail); default none, or paper with mixed pixels");
  rocky->add_option("--map-filter", rw->map_filter, "fill (eq. 11), cas or none; default fill (urg), cas (structured-light)");
  rocky->add_option("--pipeline", rw->pipeline,
                    "Structured light: geometric (true stripe + 0.3 px row noise) or image (render and detect)")
      ->capture_default_str();
  rocky->add_option("--elevation-rule", rw->elevation_rule, "paper (eq. 10) or gated")->capture_default_str();
  rocky->add_option("--cell-size-m", rw->cell_size_m, "Map cell size [m]; default 0.01 (urg), 0.005 (structured-light)")
      ->check(number_from_to(kMinCellSizeM, kMaxCellSizeM, "m"));
  rocky->add_option("--cells", rw->cells_per_side, "Cells per side of the local map; default 100 (urg), 200 (structured-light)")
      ->check(grid_cells_option(1));
  rocky->callback([rw] { run_rocky_walk_command(*rw); });

  register_mount_analysis(experiment);
}

}  // namespace stridemap::cli
