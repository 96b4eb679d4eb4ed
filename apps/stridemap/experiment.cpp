// `stridemap experiment <name>`: the paper's experiments, one command each.
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <memory>
#include <numbers>
#include <string>
#include <vector>

#include "cli_parsing.hpp"
#include "commands.hpp"
#include "installed_data.hpp"
#include "terminal_output.hpp"
#include "output_guard.hpp"
#include "stridemap/core/error.hpp"
#include "stridemap/experiments/cart_rail.hpp"
#include "stridemap/experiments/cart_rail_report.hpp"
#include "report_command.hpp"
#include "stridemap/config/mapper_config.hpp"
#include "stridemap/config/scene_yaml.hpp"
#include "stridemap/config/structured_light_config.hpp"
#include "stridemap/experiments/lighting.hpp"
#include "stridemap/experiments/mixed_pixels.hpp"
#include "stridemap/preprocess/scan_filter_registry.hpp"

namespace stridemap::cli {
namespace {

struct CartRailArgs {
  bool overwrite = false;
  bool report = false;
  std::string sensor = "urg";
  std::string scene_path;
  std::string out_dir;
  std::uint64_t seed = 1;
  double cell_size_m = 0.01;
  int cells_per_side = 0;
  std::string elevation_rule = "paper";
  std::string filters = "none";
  std::string config_path;
  std::string mixed_pixels = "off";
  std::string coupling = "on";
  std::string map_filter = "fill";
  std::string sensor_config_path;
  std::string pipeline = "image";
  double lux = 300.0;
  std::string exposure = "highlight";
  int saturation_halo_dn = io::StripeDetectorOptions{}.saturation_halo_dn;
  bool cell_size_given = false, rule_given = false, filters_given = false, map_filter_given = false;
  bool mixed_pixels_given = false;
};

std::string lux_name(double lux) {
  char text[32];
  std::snprintf(text, sizeof text, "%g lux", lux);
  return text;
}

// "auto", or a fixed gain in DN per lux (a short fixed exposure keeps a
// white surface and the stripe on it below the clip level).
void apply_exposure_arg(const std::string& exposure, CameraSensorOptions& camera) {
  if (exposure == "auto" || exposure == "highlight") {
    camera.auto_exposure = true;
    camera.highlight_limit_dn = exposure == "highlight" ? 220.0 : 0.0;
    return;
  }
  char* end = nullptr;
  const double gain = std::strtod(exposure.c_str(), &end);
  if (exposure.empty() || end != exposure.c_str() + exposure.size() || !std::isfinite(gain) || gain <= 0.0 ||
      gain > 1000.0) {
    throw InputError("--exposure: expected auto, highlight or a fixed gain in DN per lux (a number above 0 and at most 1000), "
                     "got '" + exposure + "'");
  }
  camera.auto_exposure = false;
  camera.fixed_gain_dn_per_lux = gain;
}

// Structured light: Ragno's sensor unless --sensor-config names another;
// 5 mm cells and the CAS filter by default (paper section 5.2, 5.3).
void apply_structured_light_args(const CartRailArgs& args, CartRailOptions& options) {
  options.sensor = CartRailSensor::structured_light;
  if (!args.sensor_config_path.empty()) {
    const StructuredLightConfig config = load_structured_light_config(args.sensor_config_path);
    if (!config.has_mount) {
      throw InputError(args.sensor_config_path + ": the cart-rail run needs the sensor's mount section "
                       "(mount.pitch_deg, mount.height_m)");
    }
    options.structured_light.parameters = config.parameters;
  }
  options.structured_light.pipeline = parse_option<StripePipeline>("--pipeline", args.pipeline);
  options.structured_light.image.ambient.illuminance_lux = args.lux;
  apply_exposure_arg(args.exposure, options.structured_light.image.camera);
  options.structured_light.detector.saturation_halo_dn = args.saturation_halo_dn;
  if (!args.cell_size_given) options.cell_size_m = 0.005;
  if (!args.map_filter_given) options.map_filter = MapFilter::cas;
  if (args.mixed_pixels_given || args.filters_given) {
    throw InputError("--mixed-pixels and --filters apply to the URG only, not to --sensor structured-light");
  }
}

void run_cart_rail_command(const CartRailArgs& args) {
  const SimulatedSensor sensor = parse_option<SimulatedSensor>("--sensor", args.sensor);
  CameraSensorOptions exposure_check;  // refused before the scene is read
  apply_exposure_arg(args.exposure, exposure_check);
  if (sensor == SimulatedSensor::urg &&
      (!args.sensor_config_path.empty() || args.pipeline != name(StripePipeline::image) || args.lux != 300.0 ||
       args.exposure != "highlight")) {
    throw InputError("--sensor-config, --pipeline, --lux and --exposure apply to --sensor structured-light only");
  }
  const Scene scene = load_scene_yaml(args.scene_path);
  const std::string early_dir = (std::filesystem::path(args.out_dir) / ("cart-rail-" + args.sensor)).string();
  refuse_output_that_is_an_input("--out", early_dir, {{"--scene", args.scene_path}, {"--config", args.config_path}});
  io::check_output_folder(early_dir, "--out", other_files(args.overwrite));
  if (args.report) report_assets_dir();  // before the run, not after it
  CartRailOptions options;
  if (!args.config_path.empty()) {
    // The rail keeps its fixed window; the rest of the robot's settings apply.
    const MapperConfig config = load_mapper_config(args.config_path);
    options.mount = config.mount;
    options.update = config.mapper.update;
    options.fill = config.fill;
    options.calibration = config.calibration;
    options.cell_size_m = config.mapper.grid.cell_size_m;
  }
  options.seed = args.seed;
  if (args.cell_size_given || args.config_path.empty()) options.cell_size_m = args.cell_size_m;
  options.cells_per_side = args.cells_per_side;
  if (args.rule_given || args.config_path.empty()) {
    options.update.elevation_rule = parse_elevation_rule(args.elevation_rule);
  }
  options.mixed_pixels = parse_on_off("--mixed-pixels", args.mixed_pixels);
  options.sim.receiver.enabled = parse_on_off("--coupling", args.coupling);
  options.map_filter = parse_map_filter(args.map_filter);
  // With mixed pixels every scan is pre-processed, as in the paper (section
  // 5.3), but with the between-scans test after the paper's pair: on random
  // scenes it removes about twice the mixed-pixel artifacts
  // (docs/experiments.md, "Fidelity on random scenes").
  options.filters = parse_scan_filter_list(args.filters_given || !options.mixed_pixels ? args.filters : "urg");
  std::string run_name(name(sensor));
  if (sensor == SimulatedSensor::structured_light) {
    apply_structured_light_args(args, options);
    if (options.structured_light.pipeline == StripePipeline::geometric) run_name += "-geometric";
  }
  const std::string cell_setting = args.cell_size_given || args.config_path.empty()
                                       ? "--cell-size-m " + number_text(options.cell_size_m)
                                       : args.config_path + ": map.cell_size_m " + number_text(options.cell_size_m);
  io::ProgressBar bar = progress_bar("cart-rail", "scans");
  options.progress = bar.callback();
  const CartRailResult result = naming_grid_setting(cell_setting, [&] { return run_cart_rail(scene, options); });
  bar.clear();
  const CartRailRunInfo info{run_name, args.scene_path};
  const std::string dir = (std::filesystem::path(args.out_dir) / ("cart-rail-" + run_name)).string();
  refuse_output_that_is_an_input("--out", dir, {{"--scene", args.scene_path}, {"--config", args.config_path}});
  write_output_set(dir, "--out", [&](const std::string& folder) {
    write_cart_rail_outputs(result, options, info, folder);
    if (args.report) write_run_report(folder, dir);
  }, other_files(args.overwrite));
  note("wrote " + dir);
  std::fputs(cart_rail_table(result, info).c_str(), stdout);
  print_outputs_line(dir);
}

struct MixedPixelsArgs {
  bool overwrite = false;
  std::string scene_path;
  std::string out_dir;
  std::uint64_t seed = 1;
  double texture_log_sigma = FootprintBeamOptions{}.texture.log_sigma;
  std::size_t cluster_min_points = RangeClusteringOptions{}.min_cluster_points;
  double cluster_max_incidence_deg = RangeClusteringOptions{}.max_incidence_angle_rad * 180.0 / std::numbers::pi;
  bool square_objects = false;
};

void run_mixed_pixels_command(const MixedPixelsArgs& args) {
  Scene scene = load_scene_yaml(args.scene_path);
  // The idealised placement the experiments compare with (docs/experiments.md).
  if (args.square_objects)
    for (BoxObject& box : scene.boxes) box.yaw_rad = 0.0;
  CartRailOptions options;
  options.seed = args.seed;
  options.footprint.texture.log_sigma = args.texture_log_sigma;
  options.filter_options.range_clustering.min_cluster_points = args.cluster_min_points;
  options.filter_options.range_clustering.max_incidence_angle_rad = args.cluster_max_incidence_deg * std::numbers::pi / 180.0;
  const std::string stem = std::filesystem::path(args.scene_path).stem().string();
  const std::string dir = (std::filesystem::path(args.out_dir) / "mixed-pixels" / stem).string();
  refuse_output_that_is_an_input("--out", dir, {{"--scene", args.scene_path}});
  io::check_output_folder(dir, "--out", other_files(args.overwrite));
  io::ProgressBar bar = progress_bar("mixed-pixels", "scans");
  options.progress = bar.callback();
  const MixedPixelsResult result = run_mixed_pixels(scene, options);
  bar.clear();
  write_output_set(dir, "--out",
                   [&](const std::string& folder) { write_mixed_pixels_outputs(result, options, args.scene_path, folder); },
                   other_files(args.overwrite));
  std::fputs(mixed_pixels_table(result).c_str(), stdout);
  print_outputs_line(dir);
}

struct LightingArgs {
  bool overwrite = false;
  static constexpr const char* kDefaultScene = "scenes/cart_rail_boxes.yaml";
  std::string scene_path = kDefaultScene;
  std::string out_dir;
  std::string sensor_config_path;
  std::vector<double> levels_lux;
  std::uint64_t seed = 1;
};

void run_lighting_command(const LightingArgs& args) {
  const std::string scene_path = resolve_default_data_file("--scene", args.scene_path, LightingArgs::kDefaultScene);
  if (!std::filesystem::exists(scene_path)) throw InputError(scene_path + ": the scene file does not exist");
  const Scene scene = load_scene_yaml(scene_path);
  LightingOptions options;
  CartRailArgs sl_args;
  sl_args.sensor_config_path = args.sensor_config_path;
  apply_structured_light_args(sl_args, options.structured_light);
  options.structured_light.seed = args.seed;
  options.urg.seed = args.seed;
  if (!args.levels_lux.empty()) {
    options.levels.clear();
    for (double lux : args.levels_lux) options.levels.push_back({lux_name(lux), lux});
  }
  const std::string dir = (std::filesystem::path(args.out_dir) / "lighting").string();
  refuse_output_that_is_an_input("--out", dir, {{"--scene", scene_path}, {"--sensor-config", args.sensor_config_path}});
  io::check_output_folder(dir, "--out", other_files(args.overwrite));
  io::ProgressBar bar = progress_bar("lighting", "scans");
  options.progress = bar.callback();
  const LightingResult result = run_lighting(scene, options);
  bar.clear();
  write_output_set(dir, "--out",
                   [&](const std::string& folder) { write_lighting_outputs(result, options, scene_path, folder); },
                   other_files(args.overwrite));
  std::fputs(lighting_table(result).c_str(), stdout);
  print_outputs_line(dir);
}

}  // namespace

void register_experiment(CLI::App& app) {
  CLI::App* experiment = app.add_subcommand("experiment", "Reproduce an experiment of the paper (simulated)");
  experiment->require_subcommand(1);

  auto args = std::make_shared<CartRailArgs>();
  CLI::App* cart_rail = experiment->add_subcommand(
      "cart-rail", "Sensor on a cart moved along a rail over a scene (Figs. 16-20, Table 1)");
  add_report_flag(*cart_rail, args->report);
  cart_rail->add_option("--sensor", args->sensor, "Sensor model: urg or structured-light")->capture_default_str();
  cart_rail->add_option("--sensor-config", args->sensor_config_path,
                        "Structured light: sensor configuration (YAML, docs/structured_light.md); default Ragno's");
  cart_rail->add_option("--pipeline", args->pipeline,
                        "Structured light: image (render the camera image, detect the stripe) or geometric (the "
                        "simulator's true stripe)")
      ->capture_default_str();
  cart_rail->add_option("--lux", args->lux, "Structured light: ambient illuminance [lux]")->capture_default_str()
      ->check(number_from_to(0.0, 1e6, "lux"));
  cart_rail->add_option("--exposure", args->exposure,
                        "Structured light: the camera's exposure: highlight (auto exposure metered on the image's mean, "
                        "but the brightest 1 % of the scene kept at or below 220 DN), auto (the mean only) or a fixed "
                        "gain [DN per lux]")
      ->capture_default_str();
  cart_rail->add_option("--saturation-halo-dn", args->saturation_halo_dn,
                        "Structured light: the detector's saturation_halo_dn (least red excess at the edge of a "
                        "clipped core; 0: no halo test)")
      ->capture_default_str()->check(CLI::Range(0, 255));
  cart_rail->add_option("--scene", args->scene_path, "Scene file (YAML, see docs/scenes.md)")->required();
  cart_rail->add_option("--out", args->out_dir, "Output folder; results go to OUT/cart-rail-<sensor>/")->required();
  add_output_folder_overwrite_flag(*cart_rail, args->overwrite);
  cart_rail->add_option("--seed", args->seed, "Seed of the simulation")->capture_default_str()
      ->check(seed_value());
  cart_rail->add_option("--config", args->config_path,
                        "Mapper configuration (YAML, docs/config.md): mount, update rule, fill, calibration, cell size");
  CLI::Option* cell_size = cart_rail->add_option("--cell-size-m", args->cell_size_m,
                                                 "Map cell size [m] (structured light: 0.005 unless given)")
      ->capture_default_str()
      ->check(number_from_to(kMinCellSizeM, kMaxCellSizeM, "m"));
  cart_rail->add_option("--cells", args->cells_per_side, "Cells per map side (0: fit the swept area)")
      ->capture_default_str()
      ->check(grid_cells_option(0));
  CLI::Option* rule = cart_rail->add_option("--elevation-rule", args->elevation_rule,
                        "paper: eq. (10), the highest reading wins; gated: a reading outside the plausibility "
                        "bound needs repeated support (docs/mapping.md)")
      ->capture_default_str();
  CLI::Option* mixed_pixels = cart_rail->add_option("--mixed-pixels", args->mixed_pixels,
                        "on: simulate the beam footprint and phase-shift ranging, so edges give mixed pixels")
      ->capture_default_str();
  cart_rail->add_option("--coupling", args->coupling,
                        "With --mixed-pixels on: range-intensity coupling through the receiver's gain control "
                        "(docs/mixed_pixels.md), on or off")
      ->capture_default_str();
  CLI::Option* map_filter = cart_rail->add_option("--map-filter", args->map_filter,
                                                  "On the finished map: fill (eq. 11), cas, none (structured light: "
                                                  "cas unless given)")
      ->capture_default_str();
  CLI::Option* filters = cart_rail->add_option("--filters", args->filters,
                        "Scan filters in order, comma separated: " + scan_filter_choices() +
                            ". Default: none, or urg with --mixed-pixels on")
      ->capture_default_str();
  auto mp = std::make_shared<MixedPixelsArgs>();
  CLI::App* mixed = experiment->add_subcommand(
      "mixed-pixels", "Mixed pixels from the footprint physics against each filter (Figs. 12-15, 18)");
  mixed->add_option("--scene", mp->scene_path, "Scene file (YAML, see docs/scenes.md)")->required();
  mixed->add_option("--out", mp->out_dir, "Output folder; results go to OUT/mixed-pixels/<scene>/")->required();
  add_output_folder_overwrite_flag(*mixed, mp->overwrite);
  mixed->add_option("--seed", mp->seed, "Seed of the simulation")->capture_default_str()
      ->check(seed_value());
  mixed->add_option("--texture-log-sigma", mp->texture_log_sigma,
                    "Surface texture of the footprint model: std. dev. of the log gain (0: off)")
      ->capture_default_str()
      ->check(number_from_to(0.0, 5.0));
  mixed->add_option("--cluster-min-points", mp->cluster_min_points,
                    "Range clustering: clusters with fewer points are removed")
      ->capture_default_str()
      ->check(whole_from_to(1, 100000));
  mixed->add_option("--cluster-max-incidence-deg", mp->cluster_max_incidence_deg,
                    "Range clustering: the most oblique incidence of one surface [deg]")
      ->capture_default_str()
      ->check(number_from_to(0.0, 90.0, "deg"));
  mixed->add_flag("--square-objects", mp->square_objects,
                  "Turn every box square to the rail (yaw 0), the idealised placement");
  mixed->callback([mp] { run_mixed_pixels_command(*mp); });

  auto la = std::make_shared<LightingArgs>();
  CLI::App* lighting = experiment->add_subcommand(
      "lighting", "Structured-light stripe detection and map error from dim lab to daylight, URG beside it (Fig. 21)");
  lighting->add_option("--out", la->out_dir, "Output folder; results go to OUT/lighting/")->required();
  add_output_folder_overwrite_flag(*lighting, la->overwrite);
  lighting->add_option("--scene", la->scene_path, "Scene file (YAML, see docs/scenes.md)")->capture_default_str();
  lighting->add_option("--sensor-config", la->sensor_config_path,
                       "Structured-light configuration (YAML); default Ragno's");
  lighting->add_option("--levels", la->levels_lux,
                       "Ambient illuminances [lux], comma separated; default 50,300,1000,3000,10000,30000,100000")
      ->delimiter(',')
      ->check(number_from_to(0.0, 1e6, "lux"));
  lighting->add_option("--seed", la->seed, "Seed of the simulation")->capture_default_str()
      ->check(seed_value());
  lighting->callback([la] { run_lighting_command(*la); });

  cart_rail->callback([args, cell_size, rule, filters, mixed_pixels, map_filter] {
    args->cell_size_given = cell_size->count() > 0;
    args->map_filter_given = map_filter->count() > 0;
    args->mixed_pixels_given = mixed_pixels->count() > 0;
    args->filters_given = filters->count() > 0;
    args->rule_given = rule->count() > 0;
    run_cart_rail_command(*args);
  });
}

}  // namespace stridemap::cli
