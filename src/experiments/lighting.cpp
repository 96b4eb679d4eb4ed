#include "stridemap/experiments/lighting.hpp"

#include <cmath>
#include <cstdio>
#include <filesystem>
#include <memory>
#include <system_error>
#include <utility>

#include <nlohmann/json.hpp>

#include "stripe_tally_json.hpp"

#include "stridemap/core/error.hpp"
#include "stridemap/core/sensor_transform.hpp"
#include "stridemap/io/text_file.hpp"
#include "stridemap/mapfile/map_file.hpp"
#include "stridemap/render/line_plot.hpp"
#include "stridemap/render/png_image.hpp"
#include "stridemap/sim/cart_rail.hpp"
#include "stridemap/sim/scene_ray_caster.hpp"
#include "stridemap/vision/stripe_detector.hpp"

namespace stridemap {
namespace {

std::string lux_text(double lux) {
  char text[32];
  std::snprintf(text, sizeof text, "%.0f", lux);
  return text;
}

}  // namespace

std::vector<LightingLevel> default_lighting_levels() {
  return {{"dim lab", 50.0},          {"lab", 300.0},        {"bright lab", 1000.0}, {"beside a window", 3000.0},
          {"overcast daylight", 1e4}, {"daylight", 3e4},     {"sunlight", 1e5}};
}

UrgRangeError urg_range_error(const Scene& scene, const CartRailOptions& options) {
  const std::vector<TrunkPose> poses = cart_rail_poses(scene.cart_rail.value_or(options.default_rail));
  std::unique_ptr<BeamModel> model;
  if (options.mixed_pixels) {
    model = std::make_unique<FootprintBeamModel>(options.footprint);
  } else {
    model = std::make_unique<SingleRayBeamModel>();
  }
  UrgSimulator simulator(scene, options.urg, options.sim, options.seed, std::move(model));
  const SceneRayCaster caster(scene);
  UrgRawScan raw;
  UrgRangeError error;
  double sum_sq = 0.0;
  for (std::size_t k = 0; k < poses.size(); ++k) {
    simulator.scan(poses[k], options.mount, static_cast<double>(k) * options.urg.scan_period_s, raw);
    const Eigen::Matrix3d rotation = sensor_to_map_rotation(poses[k], options.mount);
    const Eigen::Vector3d origin = sensor_origin_in_map(poses[k], options.mount);
    for (std::size_t i = 0; i < raw.values_mm.size(); ++i) {
      if (raw.values_mm[i] < 20) continue;  // error codes
      const double t = options.urg.step_angle_rad(raw.first_step + static_cast<int>(i));
      const Eigen::Vector3d direction = std::cos(t) * rotation.col(0) + std::sin(t) * rotation.col(1);
      const auto hit = caster.cast(origin, direction, options.swept_max_range_m);
      if (!hit) continue;
      const double e = raw.values_mm[i] / 1000.0 - hit->range_m;
      sum_sq += e * e;
      error.max_m = std::max(error.max_m, std::abs(e));
      ++error.beams;
    }
  }
  error.rms_m = error.beams ? std::sqrt(sum_sq / static_cast<double>(error.beams)) : 0.0;
  return error;
}

LightingResult run_lighting(const Scene& scene, const LightingOptions& options) {
  if (options.levels.empty()) throw InputError("lighting: no light levels given");
  for (const LightingLevel& level : options.levels) {
    if (!(std::isfinite(level.illuminance_lux) && level.illuminance_lux > 0.0)) {
      throw InputError("lighting: level '" + level.name + "': the illuminance must be a positive number of lux, got " +
                       std::to_string(level.illuminance_lux));
    }
  }
  LightingResult result;
  const CartRailPath rail = scene.cart_rail.value_or(options.structured_light.default_rail);
  TrunkPose example_pose;
  example_pose.x_m = std::isfinite(options.example_x_m) ? options.example_x_m : 0.5 * (rail.start_x_m + rail.end_x_m);
  example_pose.y_m = rail.y_m;
  example_pose.yaw_rad = rail.yaw_rad;
  const std::size_t runs = options.levels.size() + 1;  // the levels, then the URG's run
  for (const LightingLevel& level : options.levels) {
    CartRailOptions o = options.structured_light;
    o.progress = progress_of_part(options.progress, result.rows.size(), runs);
    o.sensor = CartRailSensor::structured_light;
    o.structured_light.pipeline = StripePipeline::image;
    o.structured_light.image.ambient.illuminance_lux = level.illuminance_lux;
    const CartRailResult run = run_cart_rail(scene, o);
    LightingRow row;
    row.level = level;
    row.stripe = run.stripe;
    row.score = run.score;
    row.objects = run.objects;
    StructuredLightImageRenderer renderer(scene, o.structured_light.parameters, o.structured_light.image,
                                          o.structured_light.geometry, o.seed);
    row.example = io::RgbImage(o.structured_light.parameters.image_width_px, o.structured_light.parameters.image_height_px);
    renderer.render(example_pose, row.example.rgb);
    io::StripeDetection detection;
    io::StripeDetector(o.structured_light.detector).detect(row.example, detection);
    row.example_overlay = io::stripe_overlay(row.example, detection);
    result.rows.push_back(std::move(row));
  }
  CartRailOptions urg = options.urg;
  urg.sensor = CartRailSensor::urg;
  urg.progress = progress_of_part(options.progress, runs - 1, runs);
  result.urg = run_cart_rail(scene, urg);
  result.urg_range = urg_range_error(scene, urg);
  return result;
}

std::string lighting_table(const LightingResult& r) {
  std::string out = "lighting (simulated): structured light, image path, against the simulator's truth\n";
  out += "level               lux   detected [%]  false (of detections)  row RMS [px]  map RMS [mm]  coverage [%]"
         "  URG range RMS [mm]  URG map RMS [mm]\n";
  char line[320];
  for (const LightingRow& row : r.rows) {
    char map_rms[32] = "-";
    if (row.score.known_cells > 0) std::snprintf(map_rms, sizeof map_rms, "%.1f", row.score.rms_error_m * 1000);
    std::snprintf(line, sizeof line, "%-18s %6.0f %13.1f %10zu (%6.2f %%) %13.2f %13s %13.1f %19.1f %17.1f\n",
                  row.level.name.c_str(), row.level.illuminance_lux, 100.0 * row.stripe.detection_rate(),
                  row.stripe.false_detections, 100.0 * row.stripe.false_rate(), row.stripe.row_error_rms_px,
                  map_rms, row.score.coverage * 100, r.urg_range.rms_m * 1000, r.urg.score.rms_error_m * 1000);
    out += line;
  }
  out += "URG-04LX: its model has no ambient-light input, so its columns are the same at every level by construction\n";
  return out;
}

void write_lighting_outputs(const LightingResult& r, const LightingOptions& options, const std::string& scene_path,
                            const std::string& directory) {
  const std::filesystem::path dir(directory);
  std::error_code ec;
  std::filesystem::create_directories(dir, ec);
  if (ec) throw InputError(dir.string() + ": cannot create the output folder: " + ec.message());

  std::string csv = "# simulated; structured light through the image path (render, detect, map), URG-04LX from its model\n"
                    "level,lux,truth_visible_columns,detected_columns,correct_columns,false_detections,"
                    "detection_rate,false_rate,row_error_rms_px,map_rms_error_m,map_coverage,urg_range_rms_m,"
                    "urg_map_rms_error_m\n";
  io::PlotSeries detected{"stripe detected [%]", {}, {}, {0, 110, 200}};
  io::PlotSeries false_rate{"false detections [%]", {}, {}, {220, 60, 30}};
  io::PlotSeries map_error{"structured light", {}, {}, {0, 110, 200}};
  io::PlotSeries urg_error{"URG-04LX (model)", {}, {}, {40, 150, 60}};
  nlohmann::json levels = nlohmann::json::array();
  char line[400];
  for (const LightingRow& row : r.rows) {
    const StripeTally& t = row.stripe;
    std::snprintf(line, sizeof line, "%s,%.0f,%zu,%zu,%zu,%zu,%.6f,%.6f,%.4f,%.6f,%.4f,%.6f,%.6f\n",
                  row.level.name.c_str(), row.level.illuminance_lux, t.truth_visible, t.detected, t.correct,
                  t.false_detections, t.detection_rate(), t.false_rate(), t.row_error_rms_px, row.score.rms_error_m,
                  row.score.coverage, r.urg_range.rms_m, r.urg.score.rms_error_m);
    csv += line;
    const double lux = row.level.illuminance_lux;
    detected.x.push_back(lux);
    detected.y.push_back(100.0 * t.detection_rate());
    false_rate.x.push_back(lux);
    false_rate.y.push_back(100.0 * t.false_rate());
    map_error.x.push_back(lux);
    map_error.y.push_back(row.score.known_cells > 0 ? row.score.rms_error_m * 1000 : NAN);
    urg_error.x.push_back(lux);
    urg_error.y.push_back(r.urg.score.rms_error_m * 1000);
    const std::string stem = "image_" + lux_text(lux) + "lx";
    io::write_png((dir / (stem + ".png")).string(), row.example);
    io::write_png((dir / (stem + "_overlay.png")).string(), row.example_overlay);
    nlohmann::json level = {{"name", row.level.name},
                            {"lux", lux},
                            {"map_rms_error_m", row.score.rms_error_m},
                            {"map_coverage", row.score.coverage},
                            {"map_artifact_cells", row.score.artifact_cells},
                            {"example_image", stem + ".png"}};
    detail::add_stripe_tally(level, t);
    levels.push_back(std::move(level));
  }
  io::write_text_file((dir / "lighting.csv").string(), csv, "lighting table");

  io::LinePlotOptions rates;
  rates.title = "Stripe detection against ambient light (simulated)";
  rates.x_label = "ambient illuminance [lux]";
  rates.y_label = "[%]";
  rates.log_x = true;
  rates.y_min = 0.0;
  rates.y_max = 100.0;
  io::LinePlotOptions errors = rates;
  errors.title = "Map RMS error against ambient light (simulated)";
  errors.y_label = "[mm]";
  errors.y_max.reset();
  io::write_png((dir / "lighting.png").string(),
                io::stack_vertically({io::render_line_plot({detected, false_rate}, rates),
                                      io::render_line_plot({map_error, urg_error}, errors)}));

  const nlohmann::json summary = {
      {"experiment", "lighting"},
      {"tool_version", io::tool_version()},
      {"source", "simulation"},
      {"scene", scene_path},
      {"seed", options.structured_light.seed},
      {"levels", levels},
      {"urg",
       {{"range_rms_m", r.urg_range.rms_m},
        {"range_max_m", r.urg_range.max_m},
        {"range_beams", r.urg_range.beams},
        {"map_rms_error_m", r.urg.score.rms_error_m},
        {"map_coverage", r.urg.score.coverage},
        {"model_assumes", "no dependence on ambient light: range noise, systematic error and dropouts depend on "
                          "range and echo amplitude only (paper Fig. 21c; Kneip et al. 2009)"}}}};
  io::write_text_file((dir / "summary.json").string(), summary.dump(2) + "\n", "summary");
  // The printed table, for the report page to show as it is.
  io::write_text_file((dir / "table.txt").string(), lighting_table(r), "table");
}

}  // namespace stridemap
