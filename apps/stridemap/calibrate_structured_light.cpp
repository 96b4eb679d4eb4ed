// `stridemap calibrate-structured-light`: b and beta from images of a flat
// target at known distances (paper section 3.2; the camera's intrinsics come
// from the configuration).
#include <cstdio>
#include <memory>
#include <numbers>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "cli_parsing.hpp"
#include "commands.hpp"
#include "output_guard.hpp"
#include "stridemap/core/printable_text.hpp"
#include "stridemap/config/structured_light_config.hpp"
#include "stridemap/core/error.hpp"
#include "stridemap/io/text_file.hpp"
#include "stridemap/sensors/structured_light_calibration.hpp"
#include "stridemap/vision/stripe_detector.hpp"

namespace stridemap::cli {
namespace {


struct CalibrateArgs {
  std::string config_path;
  std::vector<std::string> targets;  ///< "DISTANCE_M=IMAGE.png"
  bool fit_offset = false;
  double min_confidence = 0.5;
  std::string json_path;
  bool overwrite = false;
};

CalibrationTargetImage load_target(const std::string& spec, const StructuredLightParameters& camera,
                                   io::StripeDetector& detector, double min_confidence) {
  const std::size_t equals = spec.find('=');
  if (equals == std::string::npos || equals == 0 || equals + 1 == spec.size()) {
    throw InputError("--target '" + spec + "': expected DISTANCE_M=IMAGE.png, e.g. 0.15=target_150mm.png");
  }
  CalibrationTargetImage target;
  target.name = spec.substr(equals + 1);
  const std::string distance = spec.substr(0, equals);
  std::size_t used = 0;
  try {
    target.distance_m = std::stod(distance, &used);
  } catch (const std::exception&) {
    used = 0;
  }
  if (used != distance.size()) throw InputError("--target '" + spec + "': '" + distance + "' is not a distance in metres");
  const io::RgbImage image = io::read_stripe_image(target.name, camera.image_width_px, camera.image_height_px);
  io::StripeDetection detection;
  detector.detect(image, detection);
  detection.pixels(target.stripe, min_confidence);
  if (target.stripe.empty()) {
    throw InputError(target.name + ": no stripe found with confidence >= " + std::to_string(min_confidence) +
                     " (is the target lit by the sheet and in view?)");
  }
  return target;
}

void run(const CalibrateArgs& args) {
  std::vector<NamedPath> inputs{{"--config", args.config_path}};
  for (const std::string& spec : args.targets) {
    if (const auto equals = spec.find('='); equals != std::string::npos) inputs.push_back({"--target", spec.substr(equals + 1)});
  }
  refuse_output_that_is_an_input("--json", args.json_path, inputs);
  refuse_existing_files({{"--json", args.json_path}}, args.overwrite);
  const StructuredLightConfig config = load_structured_light_config(args.config_path);
  io::StripeDetector detector;
  std::vector<CalibrationTargetImage> targets;
  for (const std::string& spec : args.targets) {
    targets.push_back(load_target(spec, config.parameters, detector, args.min_confidence));
  }
  StructuredLightCalibrationOptions options;
  options.fit_distance_offset = args.fit_offset;
  const StructuredLightCalibration fit = calibrate_baseline_and_sheet_angle(config.parameters, targets, options);

  std::printf("Structured-light calibration, stage 2 (intrinsics from %s: tau_c = %.3f deg, %d x %d px)\n",
              args.config_path.c_str(), config.parameters.half_fov_vertical_rad * kDegPerRad,
              config.parameters.image_width_px, config.parameters.image_height_px);
  std::printf("  distance [mm]  points  outliers  row [px]  fitted [px]  residual [px]  scatter [px]  image\n");
  for (const CalibrationTargetFit& t : fit.targets) {
    std::printf("  %13.1f  %6zu  %8zu  %8.3f  %11.3f  %+13.3f  %12.3f  %s\n", t.distance_m * 1000, t.points,
                t.outliers, t.observed_row_px, t.fitted_row_px, t.residual_px, t.scatter_px, t.name.c_str());
  }
  std::printf("b    = %.3f mm +- %.3f mm (1 sigma)\n", fit.baseline_m * 1000, fit.baseline_sigma_m * 1000);
  std::printf("beta = %.4f deg +- %.4f deg (1 sigma); correlation with b %.3f\n", fit.sheet_angle_rad * kDegPerRad,
              fit.sheet_angle_sigma_rad * kDegPerRad, fit.baseline_sheet_angle_correlation);
  if (args.fit_offset) {
    std::printf("distance offset = %.3f mm +- %.3f mm\n", fit.distance_offset_m * 1000,
                fit.distance_offset_sigma_m * 1000);
  }
  std::printf("residuals: RMS %.3f px over %zu targets, s = %.3f px with %d degrees of freedom, %d iterations\n",
              fit.rms_residual_px, fit.targets.size(), fit.residual_sigma_px, fit.degrees_of_freedom, fit.iterations);
  std::printf("configuration: baseline_m: %.5f, sheet_angle_deg: %.4f; errors: baseline_m: %.5f, "
              "sheet_angle_deg: %.4f (3 sigma)\n",
              fit.baseline_m, fit.sheet_angle_rad * kDegPerRad, 3 * fit.baseline_sigma_m, 3 * fit.sheet_angle_sigma_rad * kDegPerRad);

  if (!args.json_path.empty()) {
    nlohmann::json targets_json = nlohmann::json::array();
    for (const CalibrationTargetFit& t : fit.targets) {
      targets_json.push_back({{"image", t.name},
                              {"distance_m", t.distance_m},
                              {"points", t.points},
                              {"outliers", t.outliers},
                              {"row_px", t.observed_row_px},
                              {"fitted_row_px", t.fitted_row_px},
                              {"residual_px", t.residual_px},
                              {"scatter_px", t.scatter_px}});
    }
    std::vector<std::vector<double>> covariance;
    for (Eigen::Index i = 0; i < fit.covariance.rows(); ++i) {
      covariance.emplace_back();
      for (Eigen::Index j = 0; j < fit.covariance.cols(); ++j) covariance.back().push_back(fit.covariance(i, j));
    }
    const nlohmann::json out = {{"baseline_m", fit.baseline_m},
                                {"baseline_sigma_m", fit.baseline_sigma_m},
                                {"sheet_angle_deg", fit.sheet_angle_rad * kDegPerRad},
                                {"sheet_angle_sigma_deg", fit.sheet_angle_sigma_rad * kDegPerRad},
                                {"distance_offset_m", fit.distance_offset_m},
                                {"distance_offset_sigma_m", fit.distance_offset_sigma_m},
                                {"covariance_b_beta_rad", covariance},
                                {"rms_residual_px", fit.rms_residual_px},
                                {"residual_sigma_px", fit.residual_sigma_px},
                                {"degrees_of_freedom", fit.degrees_of_freedom},
                                {"targets", targets_json}};
    io::write_text_file(args.json_path, out.dump(2) + "\n", "calibration");
    std::printf("wrote %s\n", printable_text(args.json_path).c_str());
  }
}

}  // namespace

void register_calibrate_structured_light(CLI::App& app) {
  auto args = std::make_shared<CalibrateArgs>();
  CLI::App* command = app.add_subcommand(
      "calibrate-structured-light",
      "Fit b and beta (eq. 1) to images of a flat target across the optical axis at known distances");
  command->add_option("--config", args->config_path,
                      "Structured-light YAML configuration: the camera's intrinsics (and a starting b, beta)")
      ->required();
  command->add_option("--target", args->targets,
                      "DISTANCE_M=IMAGE.png: a target image and its distance from the optical centre along the "
                      "optical axis; repeat for each distance (at least 3)")
      ->required();
  command->add_flag("--fit-distance-offset", args->fit_offset,
                    "Also fit an offset added to every distance (a ruler not zeroed at the optical centre)");
  command->add_option("--min-confidence", args->min_confidence, "Stripe columns below this confidence are not used")
      ->capture_default_str()
      ->check(number_from_to(0.0, 1.0));
  command->add_option("--json", args->json_path, "Also write the result as JSON");
  add_file_overwrite_flag(*command, args->overwrite, "--json");
  command->callback([args] { run(*args); });
}

}  // namespace stridemap::cli
