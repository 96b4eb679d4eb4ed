// `stridemap experiment <name>`: the paper's experiments, one command each.
#include <cstdio>
#include <filesystem>
#include <memory>
#include <string>

#include "cli_parsing.hpp"
#include "commands.hpp"
#include "stridemap/core/error.hpp"
#include "stridemap/experiments/cart_rail.hpp"
#include "stridemap/experiments/cart_rail_report.hpp"
#include "stridemap/experiments/mixed_pixels.hpp"
#include "stridemap/io/mapper_config.hpp"
#include "stridemap/io/scene_yaml.hpp"

namespace stridemap::cli {
namespace {

struct CartRailArgs {
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
  std::string map_filter = "fill";
  bool cell_size_given = false, rule_given = false, filters_given = false;
};

void run_cart_rail_command(const CartRailArgs& args) {
  if (args.sensor != "urg") {
    throw InputError("--sensor: '" + args.sensor + "' is not available for cart-rail; supported: urg");
  }
  const Scene scene = load_scene_yaml(args.scene_path);
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
  options.map_filter = parse_map_filter(args.map_filter);
  // With mixed pixels the paper pre-processes every scan (section 5.3).
  options.filters = parse_scan_filter_list(args.filters_given || !options.mixed_pixels ? args.filters : "paper");
  const CartRailResult result = run_cart_rail(scene, options);
  const CartRailRunInfo info{args.sensor, args.scene_path};
  const std::string dir = (std::filesystem::path(args.out_dir) / ("cart-rail-" + args.sensor)).string();
  write_cart_rail_outputs(result, options, info, dir);
  std::fputs(cart_rail_table(result, info).c_str(), stdout);
  std::printf("outputs: %s\n", dir.c_str());
}

struct MixedPixelsArgs {
  std::string scene_path;
  std::string out_dir;
  std::uint64_t seed = 1;
};

void run_mixed_pixels_command(const MixedPixelsArgs& args) {
  const Scene scene = load_scene_yaml(args.scene_path);
  CartRailOptions options;
  options.seed = args.seed;
  const MixedPixelsResult result = run_mixed_pixels(scene, options);
  const std::string stem = std::filesystem::path(args.scene_path).stem().string();
  const std::string dir = (std::filesystem::path(args.out_dir) / "mixed-pixels" / stem).string();
  write_mixed_pixels_outputs(result, options, args.scene_path, dir);
  std::fputs(mixed_pixels_table(result).c_str(), stdout);
  std::printf("outputs: %s\n", dir.c_str());
}

}  // namespace

void register_experiment(CLI::App& app) {
  CLI::App* experiment = app.add_subcommand("experiment", "Reproduce an experiment of the paper (simulated)");
  experiment->require_subcommand(1);

  auto args = std::make_shared<CartRailArgs>();
  CLI::App* cart_rail = experiment->add_subcommand(
      "cart-rail", "Sensor on a cart moved along a rail over a scene (Figs. 16-20, Table 1)");
  cart_rail->add_option("--sensor", args->sensor, "Sensor model: urg")->capture_default_str();
  cart_rail->add_option("--scene", args->scene_path, "Scene file (YAML, see docs/scenes.md)")->required();
  cart_rail->add_option("--out", args->out_dir, "Output folder; results go to OUT/cart-rail-<sensor>/")->required();
  cart_rail->add_option("--seed", args->seed, "Seed of the simulation")->capture_default_str();
  cart_rail->add_option("--config", args->config_path,
                        "Mapper configuration (YAML, docs/config.md): mount, update rule, fill, calibration, cell size");
  CLI::Option* cell_size = cart_rail->add_option("--cell-size-m", args->cell_size_m, "Map cell size [m]")
      ->capture_default_str();
  cart_rail->add_option("--cells", args->cells_per_side, "Cells per map side (0: fit the swept area)")
      ->capture_default_str();
  CLI::Option* rule = cart_rail->add_option("--elevation-rule", args->elevation_rule,
                        "paper: eq. (10), the highest reading wins; gated: a reading outside the plausibility "
                        "bound needs repeated support (docs/mapping.md)")
      ->capture_default_str();
  cart_rail->add_option("--mixed-pixels", args->mixed_pixels,
                        "on: simulate the beam footprint and phase-shift ranging, so edges give mixed pixels")
      ->capture_default_str();
  cart_rail->add_option("--map-filter", args->map_filter, "On the finished map: fill (eq. 11), cas, none")
      ->capture_default_str();
  CLI::Option* filters = cart_rail->add_option("--filters", args->filters,
                        "Scan filters in order, comma separated: range-clustering, scan-sequence, shadow, "
                        "speckle; paper = range-clustering,scan-sequence; none. Default: none, or paper "
                        "with --mixed-pixels on")
      ->capture_default_str();
  auto mp = std::make_shared<MixedPixelsArgs>();
  CLI::App* mixed = experiment->add_subcommand(
      "mixed-pixels", "Mixed pixels from the footprint physics against each filter (Figs. 12-15, 18)");
  mixed->add_option("--scene", mp->scene_path, "Scene file (YAML, see docs/scenes.md)")->required();
  mixed->add_option("--out", mp->out_dir, "Output folder; results go to OUT/mixed-pixels/<scene>/")->required();
  mixed->add_option("--seed", mp->seed, "Seed of the simulation")->capture_default_str();
  mixed->callback([mp] { run_mixed_pixels_command(*mp); });

  cart_rail->callback([args, cell_size, rule, filters] {
    args->cell_size_given = cell_size->count() > 0;
    args->filters_given = filters->count() > 0;
    args->rule_given = rule->count() > 0;
    run_cart_rail_command(*args);
  });
}

}  // namespace stridemap::cli
