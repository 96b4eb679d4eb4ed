// `stridemap experiment foothold`: the foothold layers of maps the walking
// robot built, scored against the truth's (docs/foothold.md), simulated.
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
#include "stridemap/core/error.hpp"
#include "stridemap/experiments/foothold.hpp"

namespace stridemap::cli {
namespace {

struct FootholdArgs {
  bool overwrite = false;
  static constexpr const char* kDefaultScene = "scenes/rocky_mockup.yaml";
  std::string scene_path = kDefaultScene;
  std::string config_path;
  std::size_t mockup_seeds = 5;
  std::size_t random_scenes = 10;
  std::uint64_t seed = 1;
  std::string out_dir;
};

void run_foothold_command(const FootholdArgs& args) {
  FootholdExperimentOptions options;
  options.mockup_seeds = args.mockup_seeds;
  options.random_scenes = args.random_scenes;
  options.seed = args.seed;
  // Only the foothold section is taken from a config: the walk is the
  // paper's local map on the simulated robot, as in rocky-walk.
  if (!args.config_path.empty()) options.foothold = load_mapper_config(args.config_path).foothold;
  options.validate();
  if (args.mockup_seeds + args.random_scenes == 0) {
    throw InputError("--mockup-seeds and --random-scenes are both 0: nothing to walk");
  }
  const std::string scene_path = resolve_default_data_file("--scene", args.scene_path, FootholdArgs::kDefaultScene);
  const Scene scene = load_scene_yaml(scene_path);
  if (!scene.walk_path) throw InputError(scene_path + ": the scene has no walk_path section");
  const std::string dir = (std::filesystem::path(args.out_dir) / "foothold").string();
  refuse_output_that_is_an_input("--out", dir, {{"--scene", scene_path}, {"--config", args.config_path}});
  io::check_output_folder(dir, "--out", other_files(args.overwrite));
  io::ProgressBar bar = progress_bar("foothold", "walks");
  options.progress = bar.callback();
  const FootholdExperimentResult result =
      run_foothold_experiment(scene, *scene.walk_path, std::filesystem::path(scene_path).filename().string(), options);
  bar.clear();
  write_output_set(
      dir, "--out", [&](const std::string& folder) { write_foothold_outputs(result, options, folder); },
      other_files(args.overwrite));
  std::fputs(foothold_table(result).c_str(), stdout);
  print_outputs_line(dir);
}

}  // namespace

void register_foothold_experiment(CLI::App& app) {
  CLI::App* experiment = app.get_subcommand("experiment");
  auto fa = std::make_shared<FootholdArgs>();
  CLI::App* foothold = experiment->add_subcommand(
      "foothold", "Foothold layers of the walking robot's maps against the truth's: precision/recall of safe, "
                  "simulated (docs/foothold.md)");
  foothold->add_option("--scene", fa->scene_path, "The scene walked with several seeds (YAML with a walk_path)")
      ->capture_default_str();
  foothold->add_option("--config", fa->config_path, "Mapper config whose foothold section sets the layers (docs/config.md)");
  foothold->add_option("--mockup-seeds", fa->mockup_seeds, "Walks over --scene, seeds SEED, SEED+1, ...")
      ->capture_default_str()->check(whole_from_to(0, 10000));
  foothold->add_option("--random-scenes", fa->random_scenes, "Walks over random rocky scenes (scene seed SEED*1000+k)")
      ->capture_default_str()->check(whole_from_to(0, 10000));
  foothold->add_option("--seed", fa->seed, "First seed")->capture_default_str()->check(seed_value());
  foothold->add_option("--out", fa->out_dir, "Output folder; results go to OUT/foothold/")->required();
  add_output_folder_overwrite_flag(*foothold, fa->overwrite);
  foothold->callback([fa] { run_foothold_command(*fa); });
}

}  // namespace stridemap::cli
