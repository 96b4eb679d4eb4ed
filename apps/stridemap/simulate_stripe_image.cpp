// `stridemap simulate-stripe-image`: the structured-light camera's image of a
// scene (or of a flat calibration target), simulated, with its ground truth.
#include <cmath>
#include <cstdio>
#include <memory>
#include <numbers>
#include <string>

#include "cli_parsing.hpp"
#include "commands.hpp"
#include "output_guard.hpp"
#include "stridemap/config/scene_yaml.hpp"
#include "stridemap/config/structured_light_config.hpp"
#include "stridemap/core/error.hpp"
#include "stridemap/io/text_file.hpp"
#include "stridemap/render/png_image.hpp"
#include "stridemap/sim/calibration_target.hpp"
#include "stridemap/sim/structured_light_image.hpp"

namespace stridemap::cli {
namespace {

constexpr double kDegPerRad = std::numbers::pi / 180.0;

struct SimulateImageArgs {
  std::string config_path;
  std::string scene_path;
  double wall_distance_m = 0.0;
  std::string out_path;
  std::string truth_path;
  bool overwrite = false;
  double x_m = 0.0, y_m = 0.0, yaw_deg = 0.0, pitch_deg = 0.0, roll_deg = 0.0;
  double lux = 300.0;
  std::uint64_t seed = 1;
};

std::string truth_csv(const StructuredLightFrameTruth& truth) {
  std::string text =
      "# simulated ground truth per image column (u, v: true stripe centre in pixels; point in the map frame [m])\n"
      "u_px,label,v_px,x_m,y_m,z_m,object_index\n";
  char line[200];
  for (const StripeColumnTruth& c : truth.columns) {
    const bool has_point = c.label != StripeColumnLabel::no_surface && c.label != StripeColumnLabel::outside_fan;
    if (has_point) {
      std::snprintf(line, sizeof line, "%.1f,%s,%.4f,%.6f,%.6f,%.6f,%d\n", c.u_px, to_string(c.label), c.v_px,
                    c.point_m.x(), c.point_m.y(), c.point_m.z(), c.object_index);
    } else {
      std::snprintf(line, sizeof line, "%.1f,%s,,,,,\n", c.u_px, to_string(c.label));
    }
    text += line;
  }
  return text;
}

void run(const SimulateImageArgs& args) {
  const bool wall = args.wall_distance_m != 0.0;
  if (wall == !args.scene_path.empty()) {
    throw InputError("simulate-stripe-image: give either --scene FILE or --wall-distance-m D (a calibration target)");
  }
  StructuredLightConfig config = load_structured_light_config(args.config_path);
  TrunkPose pose;
  pose.x_m = args.x_m;
  pose.y_m = args.y_m;
  pose.yaw_rad = args.yaw_deg * kDegPerRad;
  pose.pitch_rad = args.pitch_deg * kDegPerRad;
  pose.roll_rad = args.roll_deg * kDegPerRad;
  Scene scene;
  if (wall) {
    if (!config.has_mount) config.parameters.mount = calibration_bench_mount();
    try {
      scene = calibration_target_scene(config.parameters, pose, args.wall_distance_m);
    } catch (const InputError& e) {
      throw InputError(args.config_path + ": " + e.what());
    }
  } else {
    if (!config.has_mount) {
      throw InputError(args.config_path + ": a scene needs the sensor's mount (mount.pitch_deg, mount.height_m)");
    }
    scene = load_scene_yaml(args.scene_path);
  }
  const std::vector<NamedPath> inputs{{"--config", args.config_path}, {"--scene", args.scene_path}};
  refuse_output_that_is_an_input("--out", args.out_path, inputs);
  refuse_output_that_is_an_input("--truth", args.truth_path, inputs);
  if (!args.truth_path.empty() && (args.truth_path == args.out_path || io::same_file(args.truth_path, args.out_path))) {
    throw InputError("--truth: '" + args.truth_path + "' is also --out; give two files");
  }
  refuse_existing_files({{"--out", args.out_path}, {"--truth", args.truth_path}}, args.overwrite);
  StripeImageOptions options;
  options.ambient.illuminance_lux = args.lux;
  StructuredLightImageRenderer renderer(scene, config.parameters, options, {}, args.seed);
  io::RgbImage image(config.parameters.image_width_px, config.parameters.image_height_px);
  StructuredLightFrameTruth truth;
  const StripeImageStats stats = renderer.render(pose, image.rgb, &truth);
  io::write_png(args.out_path, image);
  if (!args.truth_path.empty()) io::write_text_file(args.truth_path, truth_csv(truth), "stripe truth");
  std::printf("simulated %d x %d image at %.0f lux (gain %.3f DN/lux, %zu saturated pixels): stripe visible in %zu "
              "columns, hidden from the camera in %zu, outside the image in %zu, no surface in %zu\nwrote %s%s%s\n",
              image.width, image.height, args.lux, stats.gain_dn_per_lux, stats.saturated_pixels, truth.visible,
              truth.hidden_from_camera, truth.outside_image, truth.no_surface, args.out_path.c_str(),
              args.truth_path.empty() ? "" : " and ", args.truth_path.c_str());
}

}  // namespace

void register_simulate_stripe_image(CLI::App& app) {
  auto args = std::make_shared<SimulateImageArgs>();
  CLI::App* command = app.add_subcommand(
      "simulate-stripe-image",
      "Simulate the structured-light camera's image of a scene, or of a flat calibration target, with its truth");
  command->add_option("--config", args->config_path, "Structured-light YAML configuration")->required();
  command->add_option("--scene", args->scene_path, "Scene file (YAML, docs/scenes.md)");
  command->add_option("--wall-distance-m", args->wall_distance_m,
                      "Instead of a scene: a flat target across the optical axis of a level sensor, this far from "
                      "the optical centre (z_c) [m]")
      ->check(number_from_to(0.001, 1000.0, "m"));
  command->add_option("--out", args->out_path, "Image to write (PNG)")->required();
  command->add_option("--truth", args->truth_path, "Also write the true stripe per column (CSV)");
  add_file_overwrite_flag(*command, args->overwrite, "--out and --truth");
  command->add_option("--x", args->x_m, "Trunk position x [m]")->capture_default_str()
      ->check(number_from_to(-1e6, 1e6, "m"));
  command->add_option("--y", args->y_m, "Trunk position y [m]")->capture_default_str()
      ->check(number_from_to(-1e6, 1e6, "m"));
  command->add_option("--yaw", args->yaw_deg, "Trunk heading [deg]")->capture_default_str()
      ->check(number_from_to(-360.0, 360.0, "deg"));
  command->add_option("--pitch", args->pitch_deg, "Trunk pitch, positive nose down [deg]")->capture_default_str()
      ->check(number_from_to(-90.0, 90.0, "deg"));
  command->add_option("--roll", args->roll_deg, "Trunk roll [deg]")->capture_default_str()
      ->check(number_from_to(-90.0, 90.0, "deg"));
  command->add_option("--lux", args->lux, "Ambient illuminance [lux]")->capture_default_str()
      ->check(number_from_to(0.0, 1e6, "lux"));
  command->add_option("--seed", args->seed, "Seed of the sensor noise")->capture_default_str()
      ->check(seed_value());
  command->callback([args] { run(*args); });
}

}  // namespace stridemap::cli
