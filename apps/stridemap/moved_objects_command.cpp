// `stridemap experiment moved-objects`: boxes that leave the scene (taken
// away, or a foot passing through) mapped with the visibility clean-up off
// and on, simulated (docs/visibility.md).
#include <cstdio>
#include <filesystem>
#include <memory>
#include <string>

#include "cli_parsing.hpp"
#include "commands.hpp"
#include "installed_data.hpp"
#include "output_guard.hpp"
#include "terminal_output.hpp"
#include "stridemap/config/mapper_config.hpp"
#include "stridemap/config/scene_yaml.hpp"
#include "stridemap/experiments/moved_objects.hpp"

namespace stridemap::cli {
namespace {

struct MovedObjectsArgs {
  bool overwrite = false;
  static constexpr const char* kDefaultScene = "scenes/moved_objects.yaml";
  std::string scene_path = kDefaultScene;
  std::string config_path;
  std::uint64_t seed = 1;
  std::string out_dir;
};

void run_moved_objects_command(const MovedObjectsArgs& args) {
  MovedObjectsOptions options;
  options.seed = args.seed;
  // The clean-up's settings from a config's visibility section (its
  // `enabled` is not used: the experiment runs both ways).
  if (!args.config_path.empty()) options.visibility = load_mapper_config(args.config_path).visibility;
  const std::string scene_path = resolve_default_data_file("--scene", args.scene_path, MovedObjectsArgs::kDefaultScene);
  const Scene scene = load_scene_yaml(scene_path);
  const std::string dir = (std::filesystem::path(args.out_dir) / "moved-objects").string();
  refuse_output_that_is_an_input("--out", dir, {{"--scene", scene_path}, {"--config", args.config_path}});
  io::check_output_folder(dir, "--out", other_files(args.overwrite));
  io::ProgressBar bar = progress_bar("moved-objects", "scans");
  options.progress = bar.callback();
  const MovedObjectsResult result = run_moved_objects(scene, options);
  bar.clear();
  write_output_set(dir, "--out", [&](const std::string& folder) {
    write_moved_objects_outputs(result, options, scene_path, folder);
  }, other_files(args.overwrite));
  std::fputs(moved_objects_table(result).c_str(), stdout);
  print_outputs_line(dir);
}

}  // namespace

void register_moved_objects_experiment(CLI::App& app) {
  CLI::App* experiment = app.get_subcommand("experiment");
  auto ma = std::make_shared<MovedObjectsArgs>();
  CLI::App* moved = experiment->add_subcommand(
      "moved-objects", "Objects taken away or passing through, mapped with the visibility clean-up off and on: "
                       "scans until cleared, simulated (docs/visibility.md)");
  moved->add_option("--scene", ma->scene_path, "Scene with a cart_rail and boxes that leave (present_until_s)")
      ->capture_default_str();
  moved->add_option("--config", ma->config_path, "Mapper config whose visibility section sets the clean-up");
  moved->add_option("--seed", ma->seed, "Seed of the simulation")->capture_default_str()->check(seed_value());
  moved->add_option("--out", ma->out_dir, "Output folder; results go to OUT/moved-objects/")->required();
  add_output_folder_overwrite_flag(*moved, ma->overwrite);
  moved->callback([ma] { run_moved_objects_command(*ma); });
}

}  // namespace stridemap::cli
