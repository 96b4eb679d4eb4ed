// `stridemap detect-stripe IMAGE.png --config FILE`: the laser stripe in a
// camera image (real or simulated), as points (CSV) and an overlay image.
#include <cstdio>
#include <filesystem>
#include <memory>
#include <string>

#include "cli_parsing.hpp"
#include "commands.hpp"
#include "output_guard.hpp"
#include "stridemap/core/printable_text.hpp"
#include "stridemap/config/structured_light_config.hpp"
#include "stridemap/core/error.hpp"
#include "stridemap/core/sensor_transform.hpp"
#include "stridemap/io/text_file.hpp"
#include "stridemap/render/png_image.hpp"
#include "stridemap/sensors/structured_light_report.hpp"
#include "stridemap/vision/stripe_detector.hpp"

namespace stridemap::cli {
namespace {

struct DetectStripeArgs {
  std::string image_path;
  std::string config_path;
  std::string out_dir;  ///< empty: beside the image
  double min_confidence = 0.0;
  bool overwrite = false;
  io::StripeDetectorOptions detector;
};

std::string points_csv(const io::StripeDetection& detection, const StructuredLightModel& model, bool with_mount,
                       double min_confidence) {
  std::string text = "# stripe per image column: u, v in pixels from the top-left corner (pixel centres at +0.5);\n"
                     "# camera frame C of eq. (1) (x_c left, y_c down, z_c ahead) in metres";
  text += with_mount ? ";\n# forward, left, up: level trunk in its neutral posture, from the ground under the camera\n"
                     : "\n";
  text += "u_px,found,v_px,confidence,x_c_m,y_c_m,z_c_m";
  text += with_mount ? ",forward_m,left_m,up_m\n" : "\n";
  char line[256];
  for (const io::StripeColumnDetection& c : detection.columns) {
    Eigen::Vector3d point;
    const bool found = c.found && c.confidence >= min_confidence &&
                       model.back_project(c.u_px, c.v_px, point) == StripePointStatus::valid;
    if (!found) {
      std::snprintf(line, sizeof line, "%.1f,0,,,,,%s\n", c.u_px, with_mount ? ",,," : "");
      text += line;
      continue;
    }
    std::snprintf(line, sizeof line, "%.1f,1,%.3f,%.3f,%.6f,%.6f,%.6f", c.u_px, c.v_px, c.confidence, point.x(),
                  point.y(), point.z());
    text += line;
    if (with_mount) {
      const Eigen::Vector3d trunk =
          sensor_point_to_map(camera_to_sensor_frame(point), TrunkPose{}, model.parameters().mount);
      std::snprintf(line, sizeof line, ",%.6f,%.6f,%.6f", trunk.x(), trunk.y(), trunk.z());
      text += line;
    }
    text += "\n";
  }
  return text;
}

void run(const DetectStripeArgs& args) {
  const StructuredLightConfig config = load_structured_light_config(args.config_path);
  const StructuredLightModel model(config.parameters);
  if (config.has_mount) {
    try {
      ground_stripe_report(model);
    } catch (const InputError& e) {
      throw InputError(args.config_path + ": " + e.what() +
                       " (leave out the mount section to get camera-frame points only, e.g. for calibration images)");
    }
  }
  const io::RgbImage image =
      io::read_stripe_image(args.image_path, config.parameters.image_width_px, config.parameters.image_height_px);
  io::StripeDetector detector(args.detector);
  io::StripeDetection detection;
  detector.detect(image, detection);

  const std::filesystem::path image_path(args.image_path);
  const std::filesystem::path dir = args.out_dir.empty() ? image_path.parent_path() : std::filesystem::path(args.out_dir);
  const std::string stem = image_path.stem().string();
  const std::string csv = (dir / (stem + ".stripe.csv")).string();
  const std::string overlay = (dir / (stem + ".overlay.png")).string();
  const std::vector<NamedPath> inputs{{"the image", args.image_path}, {"--config", args.config_path}};
  refuse_output_that_is_an_input("the stripe CSV", csv, inputs);
  refuse_output_that_is_an_input("the overlay", overlay, inputs);
  refuse_existing_files({{"the stripe CSV", csv}, {"the overlay", overlay}}, args.overwrite);
  if (!dir.empty()) {
    std::error_code error;
    std::filesystem::create_directories(dir, error);
    if (error) throw InputError(dir.string() + ": cannot create the output folder: " + error.message());
  }
  io::write_text_file(csv, points_csv(detection, model, config.has_mount, args.min_confidence), "stripe points");
  io::write_png(overlay, io::stripe_overlay(image, detection));

  std::printf("%s: stripe found in %zu of %d columns (%zu candidate pixels, %zu after clean-up", printable_text(args.image_path).c_str(),
              detection.found, detection.width, detection.candidate_pixels, detection.cleaned_pixels);
  if (detection.rejected_tall_runs > 0) std::printf(", %zu columns with a too tall red region", detection.rejected_tall_runs);
  std::printf(")\nwrote %s and %s\n", printable_text(csv).c_str(), printable_text(overlay).c_str());
}

}  // namespace

void register_detect_stripe(CLI::App& app) {
  auto args = std::make_shared<DetectStripeArgs>();
  CLI::App* command = app.add_subcommand(
      "detect-stripe",
      "Find the laser stripe in a colour camera image (colour threshold, morphological clean-up, sub-pixel row per "
      "column) and write IMAGE.stripe.csv and IMAGE.overlay.png");
  command->add_option("image", args->image_path, "Camera image (8- or 16-bit colour PNG)")->required();
  command->add_option("--config", args->config_path, "Structured-light YAML configuration (docs/structured_light.md)")
      ->required();
  command->add_option("--out", args->out_dir, "Output folder (default: the image's folder)");
  add_file_overwrite_flag(*command, args->overwrite, "IMAGE.stripe.csv and IMAGE.overlay.png");
  command->add_option("--min-confidence", args->min_confidence, "Columns below this confidence count as no stripe")
      ->capture_default_str()
      ->check(number_from_to(0.0, 1.0));
  command->add_option("--min-red-excess", args->detector.min_red_excess_dn, "Least R - max(G, B) of a stripe pixel [DN]")
      ->capture_default_str()
      ->check(whole_from_to(0, 65535));
  command->add_option("--min-red", args->detector.min_red_dn, "Least red value of a stripe pixel [DN]")
      ->capture_default_str()
      ->check(whole_from_to(0, 65535));
  command->add_option("--min-component", args->detector.min_component_px,
                      "Connected regions smaller than this are dropped [px]")
      ->capture_default_str()
      ->check(whole_from_to(0, 100000000));
  command->add_option("--max-stripe-height", args->detector.max_stripe_height_px,
                      "A red run taller than this in a column is not a stripe [px]")
      ->capture_default_str()
      ->check(whole_from_to(1, 100000));
  command->callback([args] { run(*args); });
}

}  // namespace stridemap::cli
