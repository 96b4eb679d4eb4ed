#include "stridemap/experiments/cart_rail_report.hpp"

#include "stridemap/mapfile/map_file.hpp"

#include <cmath>
#include <cstdio>
#include <filesystem>
#include <system_error>

#include <nlohmann/json.hpp>

#include "stripe_tally_json.hpp"

#include "stridemap/core/error.hpp"
#include "stridemap/experiments/fidelity.hpp"
#include "stridemap/io/text_file.hpp"
#include "stridemap/mapfile/detail/settings_json.hpp"
#include "stridemap/mapfile/grid_csv.hpp"
#include "stridemap/mapfile/map_outputs.hpp"
#include "stridemap/render/grid_render.hpp"
#include "stridemap/render/png_image.hpp"

namespace stridemap {
namespace {

using nlohmann::json;

json dimensions_json(const ObjectDimensions& d) {
  return {{"length", d.length_m}, {"width", d.width_m}, {"height", d.height_m}};
}

// JSON has no NaN; an object the map did not show gets nulls.
json error_pct_json(const ObjectMeasurement& m) {
  if (!m.found) return {{"length", nullptr}, {"width", nullptr}, {"height", nullptr}};
  return {{"length", relative_error_pct(m.measured.length_m, m.truth.length_m)},
          {"width", relative_error_pct(m.measured.width_m, m.truth.width_m)},
          {"height", relative_error_pct(m.measured.height_m, m.truth.height_m)}};
}

io::CellMask filled_mask(const MapSnapshot& s) {
  const CellMask& states = s.state();
  io::CellMask mask(states.rows(), states.cols());
  for (Eigen::Index i = 0; i < states.rows(); ++i)
    for (Eigen::Index j = 0; j < states.cols(); ++j)
      mask(i, j) = static_cast<CellState>(states(i, j)) == CellState::filled;
  return mask;
}

json structured_light_json(const CartRailResult& r, const CartRailOptions& options) {
  const StructuredLightRailOptions& sl = options.structured_light;
  const StructuredLightParameters& p = sl.parameters;
  const StripeTally& t = r.stripe;
  json out = {{"pipeline", std::string(name(sl.pipeline))},
              {"ambient_lux", sl.image.ambient.illuminance_lux},
              {"baseline_m", p.baseline_m},
              {"sheet_angle_rad", p.sheet_angle_rad},
              {"image_width_px", p.image_width_px},
              {"image_height_px", p.image_height_px},
              {"frames", t.frames},
              {"columns", t.columns},
              {"row_tolerance_px", sl.row_tolerance_px},
              {"pixels_without_point", r.stripe_conversion.pixels - r.stripe_conversion.converted}};
  detail::add_stripe_tally(out, t);
  return out;
}

// Null for a side without a fit (cylinders, boxes not found).
json edge_errors_json(const ObjectMeasurement& m) {
  json sides = json::object();
  for (std::size_t k = 0; k < m.edge_errors_m.size(); ++k) {
    const double e = m.edge_errors_m[k];
    sides[to_string(static_cast<EdgeSide>(k))] = std::isfinite(e) ? json(e) : json(nullptr);
  }
  return sides;
}

}  // namespace

std::string cart_rail_summary_json(const CartRailResult& r, const CartRailOptions& options,
                                   const CartRailRunInfo& info) {
  json objects = json::array();
  for (const ObjectMeasurement& m : r.objects) {
    objects.push_back({{"name", m.name},
                       {"kind", m.kind},
                       {"found", m.found},
                       {"cells", m.cells},
                       {"truth_m", dimensions_json(m.truth)},
                       {"measured_m", m.found ? dimensions_json(m.measured) : json(nullptr)},
                       {"trimmed_m", m.found ? dimensions_json(m.measured_trimmed) : json(nullptr)},
                       {"untrimmed_m", m.found ? dimensions_json(m.measured_untrimmed) : json(nullptr)},
                       {"edges_trimmed_m", m.found ? dimensions_json(m.edges_trimmed) : json(nullptr)},
                       {"edges_untrimmed_m", m.found ? dimensions_json(m.edges_untrimmed) : json(nullptr)},
                       {"measured_yaw_rad", m.measured_yaw_rad},
                       {"edge_errors_m", edge_errors_json(m)},
                       {"seen_share", std::isfinite(m.seen_share) ? json(m.seen_share) : json(nullptr)},
                       {"error_pct", error_pct_json(m)}});
  }
  const MapScore& s = r.score;
  const SensorMount& mount =
      options.sensor == CartRailSensor::structured_light ? options.structured_light.parameters.mount : options.mount;
  json summary = {
      {"experiment", "cart-rail"},
      {"tool_version", io::tool_version()},
      {"sensor", info.sensor},
      {"seed", options.seed},
      {"source", "simulation"},
      {"scene", info.scene_path},
      {"map",
       {{"rms_error_m", s.rms_error_m},
        {"max_error_m", s.max_error_m},
        {"coverage", s.coverage},
        {"artifact_cells", s.artifact_cells},
        {"artifact_threshold_m", s.artifact_threshold_m},
        {"clear_cells", s.clear_cells},
        {"clear_artifact_cells", s.clear_artifact_cells},
        {"clear_max_error_m", s.clear_max_error_m},
        {"mean_error_m", s.mean_error_m},
        {"rms_error_measured_m", s.rms_error_measured_m},
        {"rms_error_filled_m", s.rms_error_filled_m},
        {"level_cells", s.level_cells},
        {"rms_error_level_m", s.rms_error_level_m},
        {"rms_beyond_span_m", s.rms_beyond_span_m},
        {"max_beyond_span_m", s.max_beyond_span_m},
        {"beyond_span_artifact_cells", s.beyond_span_artifact_cells},
        {"known_cells", s.known_cells},
        {"measured_cells", s.measured_cells},
        {"filled_cells", s.filled_cells},
        {"swept_area_cells", s.scored_area_cells},
        {"cell_size_m", r.snapshot.cell_size_m},
        {"cells_per_side", r.snapshot.elevation_m().rows()}}},
      {"rail",
       {{"start_x_m", r.rail.start_x_m},
        {"end_x_m", r.rail.end_x_m},
        {"y_m", r.rail.y_m},
        {"step_m", r.rail.step_m},
        {"scans", r.scans}}},
      {"mount", {{"height_m", mount.height_m}, {"pitch_rad", mount.pitch_rad}}},
      {"elevation_rule", std::string(name(options.update.elevation_rule))},
      {"beams",
       {{"valid", r.sensor_totals.valid},
        {"error_codes", r.sensor_totals.error_codes},
        {"beyond_max_range", r.sensor_totals.beyond_max_range},
        {"integrated", r.mapper_totals.integrated},
        {"implausible", r.mapper_totals.implausible},
        {"outside_map", r.mapper_totals.outside_map}}},
      {"mixed_pixels", options.mixed_pixels},
      // The receiver's coupling acts only with the footprint model (mixed pixels on).
      {"coupling", options.mixed_pixels && options.sim.receiver.enabled},
      {"cas_removed_cells", r.cas_removed_cells},
      {"beam_labels",
       {{"clean", r.beams.clean},
        {"mixed", r.beams.mixed},
        {"dropped", r.beams.dropped},
        {"clean_removed", r.beams.clean_removed},
        {"mixed_removed", r.beams.mixed_removed},
        {"mixed_recall", r.beams.mixed_recall()},
        {"clean_drop_rate", r.beams.clean_drop_rate()},
        {"clean_in_window", r.beams.clean_in_window},
        {"clean_in_window_removed", r.beams.clean_in_window_removed},
        {"clean_in_window_drop_rate", r.beams.clean_in_window_drop_rate()},
        {"f1", r.beams.f1()}}},
      {"objects", objects}};
  summary.update(io::detail::run_settings_json(scan_filter_list_name(options.filters), options.map_filter));
  if (options.sensor == CartRailSensor::structured_light) summary["structured_light"] = structured_light_json(r, options);
  return summary.dump(2) + "\n";
}

std::string cart_rail_table(const CartRailResult& r, const CartRailRunInfo& info) {
  std::string out;
  char line[256];
  std::snprintf(line, sizeof line, "cart-rail, sensor %s (simulated), %zu scans, %.0f mm cells\n",
                info.sensor.c_str(), r.scans, r.snapshot.cell_size_m * 1000);
  out += line;
  const MapScore& s = r.score;
  std::snprintf(line, sizeof line,
                "map: RMS error %.1f mm, max %.1f mm, coverage %.1f %%, artifact cells %zu (> %.0f mm), "
                "measured %zu, filled %zu\n",
                s.rms_error_m * 1000, s.max_error_m * 1000, s.coverage * 100, s.artifact_cells,
                s.artifact_threshold_m * 1000, s.measured_cells, s.filled_cells);
  out += line;
  std::snprintf(line, sizeof line, "clear of objects (%.0f mm margin): %zu cells off by > %.0f mm, max %.1f mm\n",
                kObjectMarginM * 1000, s.clear_artifact_cells, s.artifact_threshold_m * 1000,
                s.clear_max_error_m * 1000);
  out += line;
  std::snprintf(line, sizeof line,
                "level cells (relief <= %.0f mm): %zu, RMS %.1f mm; beyond each cell's true span: RMS %.1f mm, "
                "max %.1f mm, %zu cells > %.0f mm\n",
                s.level_relief_m * 1000, s.level_cells, s.rms_error_level_m * 1000, s.rms_beyond_span_m * 1000, s.max_beyond_span_m * 1000,
                s.beyond_span_artifact_cells, s.artifact_threshold_m * 1000);
  out += line;
  if (r.stripe.frames > 0) {
    const StripeTally& t = r.stripe;
    std::snprintf(line, sizeof line,
                  "stripe: %zu frames; %.1f %% of the %zu visible columns detected within tolerance, %zu false "
                  "detections (%.2f %%; %.2f %% off the true row, %.3f %% on no laser light), row error RMS %.2f px; "
                  "%zu map points\n",
                  t.frames, 100.0 * t.detection_rate(), t.truth_visible, t.false_detections, 100.0 * t.false_rate(),
                  100.0 * t.off_row_rate(), 100.0 * t.no_laser_light_rate(), t.row_error_rms_px, t.map_points);
  } else {
    std::snprintf(line, sizeof line,
                  "beams: %zu clean, %zu mixed, %zu error codes; filters removed %zu mixed, %zu clean\n", r.beams.clean,
                  r.beams.mixed, r.beams.dropped, r.beams.mixed_removed, r.beams.clean_removed);
  }
  out += line;
  out += "object        dim      truth [mm]  map [mm]  error [%]\n";
  const double min_seen_share = FidelityOptions{}.min_seen_share;
  for (const ObjectMeasurement& m : r.objects) {
    const double truth[] = {m.truth.length_m, m.truth.width_m, m.truth.height_m};
    const double measured[] = {m.measured.length_m, m.measured.width_m, m.measured.height_m};
    const char* names[] = {"length", "width", "height"};
    for (int k = 0; k < 3; ++k) {
      if (m.found) {
        std::snprintf(line, sizeof line, "%-13s %-8s %10.1f %9.1f %10.1f\n", k == 0 ? m.name.c_str() : "", names[k],
                      truth[k] * 1000, measured[k] * 1000, relative_error_pct(measured[k], truth[k]));
      } else {
        std::snprintf(line, sizeof line, "%-13s %-8s %10.1f %9s %10s\n", k == 0 ? m.name.c_str() : "", names[k],
                      truth[k] * 1000, "-", "not found");
      }
      out += line;
    }
    // As the fidelity experiment judges it: an extent of a top the sweep
    // did not reach in full is not an error of the map.
    if (std::isfinite(m.seen_share) && m.seen_share < min_seen_share) {
      std::snprintf(line, sizeof line, "%-13s partly seen: the sweep reaches %.0f %% of its top\n", "",
                    100.0 * m.seen_share);
      out += line;
    }
  }
  return out;
}

void write_cart_rail_outputs(const CartRailResult& r, const CartRailOptions& options, const CartRailRunInfo& info,
                             const std::string& directory) {
  const std::filesystem::path dir(directory);
  std::error_code ec;
  std::filesystem::create_directories(dir, ec);
  if (ec) throw InputError(dir.string() + ": cannot create the output folder: " + ec.message());

  const MapSnapshot& s = r.snapshot;
  // One colour scale for elevation and truth, so the two pictures compare.
  const float lo = std::min(0.0f, s.truth_m.minCoeff());
  const float hi = std::max(s.truth_m.maxCoeff(), lo + 0.01f);
  io::MapOutputOptions map_style;
  map_style.elevation_title = "Elevation (" + info.sensor + ", simulated)";
  map_style.elevation_min_m = lo;
  map_style.elevation_max_m = hi;
  map_style.certainty_max = options.update.certainty_max;
  io::write_map_layers(s, directory, map_style);

  io::GridRenderOptions elevation_style;
  elevation_style.units = "m";
  elevation_style.cell_size_m = s.cell_size_m;
  elevation_style.min_value = lo;
  elevation_style.max_value = hi;
  elevation_style.title = "Ground truth: highest point per cell";
  io::write_png((dir / "truth.png").string(), io::render_grid(s.truth_m, elevation_style).image);

  const io::CellMask filled = filled_mask(s);
  const Eigen::MatrixXf error = s.elevation_m() - s.truth_m;
  io::GridRenderOptions error_style;
  error_style.title = "Elevation error (map - truth)";
  error_style.units = "m";
  error_style.cell_size_m = s.cell_size_m;
  error_style.min_value = -0.05;
  error_style.max_value = 0.05;
  error_style.colour_scale = io::ColourScale::diverging;
  io::write_png((dir / "error.png").string(), io::render_grid(error, filled, error_style).image);

  const Eigen::Vector2d origin = s.cell_center(0, 0);
  const auto csv = [&](const char* name, const Eigen::MatrixXf& values, const char* units) {
    io::GridCsvOptions o;
    o.layer_name = name;
    o.units = units;
    o.cell_size_m = s.cell_size_m;
    o.origin_x_m = origin.x();
    o.origin_y_m = origin.y();
    io::write_grid_csv((dir / (std::string(name) + ".csv")).string(), values, o);
  };
  csv("truth", s.truth_m, "m");
  csv("swept_area", r.swept_area.cast<float>(), "");

  io::write_text_file((dir / "summary.json").string(), cart_rail_summary_json(r, options, info), "summary");
  // The printed table, for the report page to show as it is.
  io::write_text_file((dir / "table.txt").string(), cart_rail_table(r, info), "table");
  // The final map whole, for map-info, export and other software.
  io::save_map_file((dir / "map.smap").string(), r.map,
                    io::map_file_metadata(r.map_config, "experiment cart-rail --sensor " + info.sensor + " --scene " +
                                                            info.scene_path));
}

}  // namespace stridemap
