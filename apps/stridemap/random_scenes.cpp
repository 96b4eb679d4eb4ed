// `stridemap scene random` (a random scene as a YAML file) and
// `stridemap experiment fidelity` (the cart-rail figures over many random
// scenes, as distributions): claims are measured on scenes nobody tuned for.
#include <cerrno>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <memory>
#include <string>

#include <fcntl.h>
#include <unistd.h>

#include "cli_parsing.hpp"
#include "commands.hpp"
#include "output_guard.hpp"
#include "terminal_output.hpp"
#include "stridemap/config/scene_yaml.hpp"
#include "stridemap/core/error.hpp"
#include "stridemap/experiments/fidelity.hpp"
#include "stridemap/preprocess/scan_filter_registry.hpp"

namespace stridemap::cli {
namespace {

struct RandomSceneArgs {
  std::uint64_t seed = 1;
  std::string kind = "boxes";
  std::string out_path;
};

// Creates `path` only if nothing is there (O_EXCL: no race with another
// writer either) and removes it again if the text cannot be written whole,
// so an existing file is never touched and no half file is left.
void write_new_file(const std::string& path, const std::string& text) {
  const int fd = ::open(path.c_str(), O_WRONLY | O_CREAT | O_EXCL | O_CLOEXEC, 0644);
  if (fd < 0) {
    if (errno == EEXIST) throw InputError("--out: " + path + " exists already; it is not overwritten (choose another name)");
    throw InputError("--out: cannot create " + path + ": " + std::strerror(errno));
  }
  std::size_t written = 0;
  int error = 0;
  while (written < text.size()) {
    const ssize_t n = ::write(fd, text.data() + written, text.size() - written);
    if (n < 0 && errno == EINTR) continue;
    if (n <= 0) {
      error = n < 0 ? errno : EIO;
      break;
    }
    written += static_cast<std::size_t>(n);
  }
  if (error == 0 && ::fsync(fd) != 0 && errno != EINVAL) error = errno;
  if (::close(fd) != 0 && error == 0) error = errno;
  if (error != 0) {
    ::unlink(path.c_str());
    throw InputError("--out: cannot write " + path + ": " + std::strerror(error));
  }
}

void run_random_scene(const RandomSceneArgs& args) {
  const RandomSceneKind kind = parse_option<RandomSceneKind>("--kind", args.kind);
  const std::string text = random_scene_yaml(kind, args.seed);
  // What is written must load: the generator's own check.
  (void)parse_scene_yaml(text, "random scene (kind " + args.kind + ", seed " + std::to_string(args.seed) + ")");
  write_new_file(args.out_path, text);
  note("wrote " + args.out_path);
}

struct FidelityArgs {
  bool overwrite = false;
  std::size_t scenes = 30;
  std::uint64_t seed = 1;
  std::string kind = "boxes";
  std::string structured_light = "image";
  std::string filters = "urg";
  std::string coupling = "on";
  std::string bystanders = "auto";
  double min_lux = 50.0, max_lux = 1000.0;
  int saturation_halo_dn = io::StripeDetectorOptions{}.saturation_halo_dn;
  std::size_t cluster_max_bridged = RangeClusteringOptions{}.max_bridged_invalid_beams;
  std::string out_dir;
};

void run_fidelity_command(const FidelityArgs& args) {
  FidelityOptions options;
  options.scenes = args.scenes;
  options.seed = args.seed;
  options.kind = parse_option<RandomSceneKind>("--kind", args.kind);
  try {
    options.filters = parse_scan_filter_list(args.filters);
    (void)ScanFilterChain(options.filters);  // an order the chain refuses fails here, before any run
  } catch (const InputError& e) {
    throw InputError(std::string("--filters: ") + e.what());
  }
  if (options.filters.empty()) throw InputError("--filters: none leaves nothing to measure; give at least one filter");
  if (options.kind == RandomSceneKind::rocky) {
    throw InputError("--kind: rocky scenes have no cart rail to measure on; use boxes or steps");
  }
  options.urg.sim.receiver.enabled = parse_on_off("--coupling", args.coupling);
  options.urg.filter_options.range_clustering.max_bridged_invalid_beams = args.cluster_max_bridged;
  if (args.structured_light == "off") {
    options.structured_light = false;
  } else {
    options.structured_light_rail.structured_light.pipeline =
        parse_option<StripePipeline>("--structured-light", args.structured_light);
  }
  // The URG-only figures were measured on the line's objects alone; the
  // bystanders are there for the stripe detector.
  options.bystanders = args.bystanders == "auto" ? options.structured_light : parse_on_off("--bystanders", args.bystanders);
  if (options.bystanders && options.kind != RandomSceneKind::boxes) {
    if (args.bystanders == "on") throw InputError("--bystanders: only boxes scenes have them; use --kind boxes or off");
    options.bystanders = false;
  }
  if (!(args.min_lux <= args.max_lux)) {
    throw InputError("--min-lux: must not exceed --max-lux (" + std::to_string(args.max_lux) + "), got " +
                     std::to_string(args.min_lux));
  }
  options.min_lux = args.min_lux;
  options.max_lux = args.max_lux;
  options.structured_light_rail.structured_light.detector.saturation_halo_dn = args.saturation_halo_dn;
  options.structured_light_rail.structured_light.detector.validate();
  const std::string dir = (std::filesystem::path(args.out_dir) / "fidelity").string();
  io::check_output_folder(dir, "--out", other_files(args.overwrite));
  io::ProgressBar bar = progress_bar("fidelity", "runs");
  options.progress = bar.callback();
  const FidelityResult result = run_fidelity(options);
  bar.clear();
  write_output_set(
      dir, "--out", [&](const std::string& folder) { write_fidelity_outputs(result, options, folder); },
      other_files(args.overwrite));
  std::fputs(fidelity_table(result).c_str(), stdout);
  print_outputs_line(dir);
}

}  // namespace

void register_random_scenes(CLI::App& app) {
  CLI::App* scene = app.add_subcommand("scene", "Scenes for the simulator (docs/scenes.md)");
  scene->require_subcommand(1);
  auto rs = std::make_shared<RandomSceneArgs>();
  CLI::App* random = scene->add_subcommand(
      "random", "Write a random scene (sizes off the grid, turned boxes, reflectances 0.1-0.9) as YAML");
  random->add_option("--seed", rs->seed, "Same seed and kind, same scene")->capture_default_str()->check(seed_value());
  random->add_option("--kind", rs->kind, "boxes (on a cart rail), rocky (ground, rocks, a walk path) or steps "
                                         "(a block field on a cart rail)")
      ->capture_default_str();
  random->add_option("--out", rs->out_path, "The scene file to create (an existing file is never overwritten)")
      ->required();
  random->callback([rs] { run_random_scene(*rs); });

  CLI::App* experiment = app.get_subcommand("experiment");
  auto fa = std::make_shared<FidelityArgs>();
  CLI::App* fidelity = experiment->add_subcommand(
      "fidelity", "Cart-rail figures on random scenes: median, 90th percentile and worst");
  fidelity->add_option("--scenes", fa->scenes, "How many random scenes")->capture_default_str()
      ->check(whole_from_to(1, 100000));
  fidelity->add_option("--seed", fa->seed, "Scene k is random scene seed*1000+k")->capture_default_str()
      ->check(seed_value());
  fidelity->add_option("--kind", fa->kind, "Scene kind: boxes or steps")->capture_default_str();
  fidelity->add_option("--structured-light", fa->structured_light,
                       "Structured-light runs: image (render and detect), geometric (the true stripe) or off")
      ->capture_default_str();
  fidelity->add_option("--filters", fa->filters,
                       "Scan filters of the URG's filtered run, comma separated: " + scan_filter_choices())
      ->capture_default_str();
  fidelity->add_option("--cluster-max-bridged", fa->cluster_max_bridged,
                       "Range clustering: a cluster runs on over at most this many invalid beams (0: the "
                       "published rule)")
      ->capture_default_str()->check(whole_from_to(0, 16));
  fidelity->add_option("--coupling", fa->coupling,
                       "Range-intensity coupling through the receiver's gain control (docs/mixed_pixels.md): on or off")
      ->capture_default_str();
  fidelity->add_option("--bystanders", fa->bystanders,
                       "Tall white and black boxes beside the line (boxes scenes): on, off, or auto (on with "
                       "structured light)")
      ->capture_default_str();
  fidelity->add_option("--min-lux", fa->min_lux, "Structured light: least ambient light of a scene [lux]")
      ->capture_default_str()->check(CLI::Range(1.0, 1e6));
  fidelity->add_option("--max-lux", fa->max_lux,
                       "Structured light: most ambient light of a scene [lux]; each scene's is drawn from its seed, "
                       "log-uniform")
      ->capture_default_str()->check(CLI::Range(1.0, 1e6));
  fidelity->add_option("--saturation-halo-dn", fa->saturation_halo_dn,
                       "Structured light: the detector's saturation_halo_dn (least red excess beside a clipped "
                       "core; 0: no halo test)")
      ->capture_default_str()->check(CLI::Range(0, 255));
  fidelity->add_option("--out", fa->out_dir, "Output folder; results go to OUT/fidelity/")->required();
  add_output_folder_overwrite_flag(*fidelity, fa->overwrite);
  fidelity->callback([fa] { run_fidelity_command(*fa); });
}

}  // namespace stridemap::cli
