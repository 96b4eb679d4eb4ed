// `stridemap sensor-report`: what a structured-light configuration measures
// (paper section 3.3) and, on request, its spatial uncertainty maps
// (section 3.2, Fig. 3) as CSV and PNG.
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <memory>
#include <numbers>
#include <string>
#include <system_error>

#include "cli_parsing.hpp"
#include "commands.hpp"
#include "output_guard.hpp"
#include "stridemap/core/printable_text.hpp"
#include "stridemap/config/structured_light_config.hpp"
#include "stridemap/core/error.hpp"
#include "stridemap/mapfile/grid_csv.hpp"
#include "stridemap/render/grid_render.hpp"
#include "stridemap/render/png_image.hpp"
#include "stridemap/sensors/structured_light_report.hpp"
#include "stridemap/sensors/structured_light_uncertainty.hpp"

namespace stridemap::cli {
namespace {

constexpr double kMm = 1000.0;

struct SensorReportOptions {
  bool overwrite = false;
  std::string config_path;
  std::string uncertainty_dir;  ///< empty: no maps
  UncertaintyMapOptions maps;
};

void print_parameters(const std::string& source, const StructuredLightParameters& p) {
  std::printf("Structured-light sensor: %s\n", printable_text(source).c_str());
  std::printf("  b = %.1f mm, beta = %.2f deg, tau_c = %.2f deg, gamma_c = %.2f deg, image %d x %d px\n",
              p.baseline_m * kMm, p.sheet_angle_rad * kDegPerRad, p.half_fov_vertical_rad * kDegPerRad,
              p.half_fov_horizontal_rad * kDegPerRad, p.image_width_px, p.image_height_px);
  std::printf("  focal length by eq. (2): %.1f px from tau_c, %.1f px from gamma_c\n",
              focal_length_from_half_fov_px(p.image_height_px, p.half_fov_vertical_rad),
              focal_length_from_half_fov_px(p.image_width_px, p.half_fov_horizontal_rad));
  std::printf("  error bounds: Delta b = %.2f mm, Delta beta = %.3f deg, Delta tau_c = %.3f deg, "
              "Delta v = %.2f px, Delta u = %.2f px\n\n",
              p.baseline_error_m * kMm, p.sheet_angle_error_rad * kDegPerRad, p.half_fov_vertical_error_rad * kDegPerRad,
              p.row_error_px, p.column_error_px);
}

void print_row_view(const char* label, const SheetRowView& row) {
  std::printf("  %-22s v = %6.1f px: z_c = %7.1f mm, y_c = %7.1f mm, field %6.1f mm wide, dz_c/dv = %.3f mm/px\n",
              label, row.row_px, row.depth_m * kMm, row.vertical_m * kMm, row.lateral_field_m * kMm,
              row.depth_per_row_m_per_px * kMm);
}

void print_sheet(const StructuredLightModel& model) {
  const SheetInView view = sheet_in_view(model);
  std::printf("Laser sheet in the camera frame (eq. 1):\n");
  std::printf("  crosses the optical axis at z_c = %.1f mm (row %.1f)\n", view.axis_crossing_depth_m * kMm,
              0.5 * model.parameters().image_height_px);
  print_row_view("nearest (top row)", view.top_row);
  if (view.bottom_row) {
    print_row_view("farthest (bottom row)", *view.bottom_row);
  } else {
    std::printf("  farthest: the sheet recedes to infinity at row %.1f; rows below it see no sheet\n",
                view.vanishing_row_px);
  }
  const StructuredLightParameters& p = model.parameters();
  std::printf("  spatial uncertainty from Delta u = %.2f px, Delta v = %.2f px (Fig. 3):\n", p.column_error_px,
              p.row_error_px);
  for (const double depth : {0.25, 0.5, 0.75, 1.0}) {
    const double row = model.row_at_sheet_depth_px(depth);
    const auto axis = pixel_point_uncertainty(model, 0.5 * p.image_width_px, row);
    const auto edge = pixel_point_uncertainty(model, 0.0, row);
    if (!axis || !edge) continue;
    std::printf("    z_c = %4.0f mm: Delta z_c = %6.2f mm, Delta x_c = %5.2f mm on the axis, %5.2f mm at the "
                "image edge\n",
                depth * kMm, axis->z_m * kMm, axis->x_m * kMm, edge->x_m * kMm);
  }
  std::printf("\n");
}

void print_ground(const StructuredLightModel& model) {
  const StructuredLightParameters& p = model.parameters();
  const GroundStripeReport r = ground_stripe_report(model);
  std::printf("Mount: pitch alpha = %.2f deg (towards the ground), camera %.1f mm above the ground\n",
              p.mount.pitch_rad * kDegPerRad, p.mount.height_m * kMm);
  std::printf("Flat ground, level trunk (distances horizontal, from the point under the camera):\n");
  std::printf("  stripe at image row v = %.1f of %d (%.1f %% down the image), across the full width\n",
              r.stripe_row_px, p.image_height_px, 100.0 * r.stripe_row_px / p.image_height_px);
  std::printf("  nearest ground point:  %.1f mm ahead (the stripe's centre; slant range %.1f mm, z_c = %.1f mm)\n",
              r.nearest_distance_m * kMm, r.nearest_slant_range_m * kMm, r.stripe_depth_m * kMm);
  std::printf("  farthest ground point: %.1f mm (the stripe's ends; slant range %.1f mm)\n",
              r.farthest_distance_m * kMm, r.farthest_slant_range_m * kMm);
  std::printf("  stripe width on the ground: %.1f mm\n", r.stripe_width_m * kMm);
  const StructuredLightElevationPartials& d = r.centre_partials;
  std::printf("  elevation per image row there: %.3f mm/px\n", r.elevation_per_row_m_per_px * kMm);
  std::printf("  eq. (8) error terms there: b %.2f + beta %.2f + tau_c %.2f + v %.2f = %.2f mm; "
              "pitch, roll, alpha (1 deg each) %.2f mm\n",
              std::abs(d.d_baseline) * p.baseline_error_m * kMm,
              std::abs(d.d_sheet_angle_m_per_rad) * p.sheet_angle_error_rad * kMm,
              std::abs(d.d_half_fov_vertical_m_per_rad) * p.half_fov_vertical_error_rad * kMm,
              std::abs(d.d_row_m_per_px) * p.row_error_px * kMm, r.sensor_error_bound_m * kMm,
              r.pose_error_bound_m * kMm);
  if (r.horizon_row_px <= 0.0) {
    std::printf("  every image row looks down at the ground\n");
  } else {
    std::printf("  image rows below v = %.1f look down at the ground\n", r.horizon_row_px);
  }
  const char* searched = " (still in view where the search stopped)";
  std::printf("  the stripe stays in the image for trunk pitch (positive nose down) %+.2f deg%s to %+.2f deg%s\n",
              r.min_trunk_pitch_rad * kDegPerRad, r.min_pitch_is_search_limit ? searched : "",
              r.max_trunk_pitch_rad * kDegPerRad, r.max_pitch_is_search_limit ? searched : "");
  std::printf("Measurable along the sheet (level trunk):\n");
  std::printf("  near end (top row):     %.1f mm ahead, %+.1f mm above the ground, field %.1f mm wide\n",
              r.near_end.forward_m * kMm, r.near_end.height_above_ground_m * kMm, r.near_end.lateral_field_m * kMm);
  if (r.far_end) {
    std::printf("  far end (bottom row):   %.1f mm ahead, %+.1f mm above the ground, field %.1f mm wide\n",
                r.far_end->forward_m * kMm, r.far_end->height_above_ground_m * kMm,
                r.far_end->lateral_field_m * kMm);
  }
}

void write_map(const std::string& directory, const std::string& name, const std::string& title,
               const Eigen::MatrixXf& values_m, const UncertaintyMaps& maps) {
  io::GridCsvOptions csv;
  csv.layer_name = name;
  csv.units = "m";
  csv.cell_size_m = maps.cell_size_m;
  csv.origin_x_m = maps.first_depth_m;
  csv.origin_y_m = maps.first_lateral_m;
  const std::string base = (std::filesystem::path(directory) / name).string();
  io::write_grid_csv(base + ".csv", values_m, csv);

  io::GridRenderOptions render;
  render.title = title;
  render.units = "mm";
  render.cell_size_m = maps.cell_size_m;
  render.unknown_label = "not seen";
  render.up_axis_label = "z_c depth";
  render.left_axis_label = "x_c left";
  const Eigen::MatrixXf values_mm = values_m * static_cast<float>(kMm);
  io::write_png(base + ".png", io::render_grid(values_mm, render).image);
  std::printf("wrote %s.csv and %s.png\n", printable_text(base).c_str(), printable_text(base).c_str());
}

void write_maps(const StructuredLightModel& model, const SensorReportOptions& options) {
  refuse_output_that_is_an_input("--uncertainty-out", options.uncertainty_dir, {{"--config", options.config_path}});
  io::check_output_folder(options.uncertainty_dir, "--uncertainty-out", other_files(options.overwrite));
  const UncertaintyMaps maps = structured_light_uncertainty_maps(model, options.maps);
  const StructuredLightParameters& p = model.parameters();
  char source[160];
  std::snprintf(source, sizeof source, "Delta u = %.2g px, Delta v = %.2g px%s", p.column_error_px, p.row_error_px,
                options.maps.include_parameter_errors ? " + calibration errors" : "");
  std::printf("\nSpatial uncertainty maps (x_c across, z_c up the page; %s):\n", source);
  write_output_set(options.uncertainty_dir, "--uncertainty-out", [&](const std::string& folder) {
    write_map(folder, "x_uncertainty", "x_c uncertainty", maps.x_uncertainty_m, maps);
    write_map(folder, "z_uncertainty", "z_c uncertainty", maps.z_uncertainty_m, maps);
  }, other_files(options.overwrite));
}

void run(const SensorReportOptions& options) {
  const StructuredLightConfig config = load_structured_light_config(options.config_path);
  const StructuredLightModel model(config.parameters);
  print_parameters(options.config_path, config.parameters);
  print_sheet(model);
  if (config.has_mount) {
    try {
      print_ground(model);
    } catch (const InputError& e) {
      throw InputError(options.config_path + ": " + e.what());
    }
  } else {
    std::printf("No mount section: the flat-ground report needs mount.pitch_deg and mount.height_m.\n");
  }
  if (!options.uncertainty_dir.empty()) write_maps(model, options);
}

}  // namespace

void register_sensor_report(CLI::App& app) {
  auto options = std::make_shared<SensorReportOptions>();
  CLI::App* command = app.add_subcommand(
      "sensor-report",
      "What a structured-light configuration measures: the sheet in the image, the stripe on flat ground "
      "(paper section 3.3), and optionally the spatial uncertainty maps of Fig. 3");
  command->add_option("--config", options->config_path, "Structured-light YAML configuration")->required();
  command->add_option("--uncertainty-out", options->uncertainty_dir,
                      "Write x_uncertainty and z_uncertainty maps (.csv in m, .png in mm) into this folder");
  add_output_folder_overwrite_flag(*command, options->overwrite, "--uncertainty-out");
  command->add_option("--max-depth", options->maps.max_depth_m, "Largest depth z_c of the maps [m]")
      ->capture_default_str()
      ->check(number_from_to(0.001, 1000.0, "m"));
  command->add_option("--cell-size", options->maps.cell_size_m, "Cell side of the maps [m]")->capture_default_str()
      ->check(number_from_to(kMinCellSizeM, kMaxCellSizeM, "m"));
  command->add_flag("--with-parameter-errors", options->maps.include_parameter_errors,
                    "Add the calibration errors (Delta b, Delta beta, Delta tau_c) to the pixel errors in the maps");
  command->callback([options] { run(*options); });
}

}  // namespace stridemap::cli
