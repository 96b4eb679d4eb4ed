#include "stridemap/experiments/rocky_walk_report.hpp"

#include "stridemap/mapfile/map_file.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <numbers>
#include <system_error>
#include <vector>

#include <nlohmann/json.hpp>

#include "stridemap/core/error.hpp"
#include "stridemap/io/text_file.hpp"
#include "stridemap/mapfile/grid_csv.hpp"
#include "stridemap/render/grid_overlay.hpp"
#include "stridemap/render/grid_render.hpp"
#include "stridemap/render/png_image.hpp"
#include "stridemap/render/terrain_view.hpp"

namespace stridemap {
namespace {

using nlohmann::json;
constexpr double kDegPerRad = 180.0 / std::numbers::pi;

// The error with the map's mean height offset taken out: what a drifting
// h_ref leaves of the shapes once the whole map is shifted back.
double offset_free_rms_m(const MapScore& s) {
  return std::sqrt(std::max(0.0, s.rms_error_m * s.rms_error_m - s.mean_error_m * s.mean_error_m));
}

json score_json(const MapScore& s, std::size_t unknown_swept) {
  return {{"rms_error_m", s.rms_error_m},
          {"rms_error_offset_free_m", offset_free_rms_m(s)},
          {"max_error_m", s.max_error_m},
          {"mean_error_m", s.mean_error_m},
          {"artifact_cells", s.artifact_cells},
          {"artifact_threshold_m", s.artifact_threshold_m},
          {"coverage", s.coverage},
          {"unknown_swept_cells", unknown_swept},
          {"known_cells", s.known_cells},
          {"measured_cells", s.measured_cells},
          {"filled_cells", s.filled_cells},
          {"rms_error_measured_m", s.rms_error_measured_m},
          {"rms_error_filled_m", s.rms_error_filled_m},
          {"swept_area_cells", s.scored_area_cells}};
}

json pose_json(const PoseErrorStats& p) {
  return {{"x_m", p.x_m},           {"y_m", p.y_m},
          {"yaw_deg", p.yaw_rad * kDegPerRad}, {"pitch_deg", p.pitch_rad * kDegPerRad},
          {"roll_deg", p.roll_rad * kDegPerRad}, {"sensor_height_m", p.sensor_height_m},
          {"mean_sensor_height_m", p.mean_sensor_height_m}};
}

/// The walk's mean trunk-height error and its parts (they add up), and the
/// share of scans on which no foot read the map.
json height_error_json(const std::vector<HeightReferenceError>& errors) {
  HeightReferenceError mean;
  std::size_t unread = 0;
  for (const HeightReferenceError& e : errors) {
    mean.error_m += e.error_m;
    mean.odometry_m += e.odometry_m;
    mean.map_m += e.map_m;
    mean.placement_m += e.placement_m;
    mean.kinematics_m += e.kinematics_m;
    unread += e.feet_read == 0;
  }
  const double n = errors.empty() ? 1.0 : static_cast<double>(errors.size());
  return {{"mean_error_m", mean.error_m / n},          {"mean_from_odometry_m", mean.odometry_m / n},
          {"mean_from_map_m", mean.map_m / n},         {"mean_from_placement_m", mean.placement_m / n},
          {"mean_from_kinematics_m", mean.kinematics_m / n}, {"scans_without_reading", unread},
          {"scans", errors.size()}};
}

io::CellMask state_mask(const MapSnapshot& s, CellState state) {
  const CellMask& states = s.state();
  io::CellMask mask(states.rows(), states.cols());
  for (Eigen::Index i = 0; i < states.rows(); ++i)
    for (Eigen::Index j = 0; j < states.cols(); ++j) mask(i, j) = static_cast<CellState>(states(i, j)) == state;
  return mask;
}

struct Origin {
  double x_m, y_m;
};
Origin origin_of(const MapSnapshot& s) {
  const Eigen::Vector2d centre = s.cell_center(0, 0);
  return {centre.x(), centre.y()};
}

// elevation, certainty, error and truth pictures of one snapshot, with the
// track drawn on the elevation, truth and error maps.
void write_map_pictures(const std::filesystem::path& dir, const std::string& prefix, const std::string& what,
                        const MapSnapshot& s, const CellMask& swept, const std::vector<Eigen::Vector2d>& track,
                        const RockyWalkResult& r, double certainty_max) {
  const io::CellMask filled = state_mask(s, CellState::filled);
  const Origin o = origin_of(s);
  // The colour range: the truth's over the swept cells, widened to the
  // map's 2nd-98th percentile there, so that neither the ground nor the
  // bulk of the map is clipped while one outlier cell cannot stretch it.
  float lo = std::numeric_limits<float>::infinity(), hi = -lo;
  const Eigen::MatrixXf elevation = s.elevation_m();
  std::vector<float> mapped;
  for (Eigen::Index i = 0; i < s.truth_m.rows(); ++i)
    for (Eigen::Index j = 0; j < s.truth_m.cols(); ++j) {
      if (!swept(i, j)) continue;
      lo = std::min(lo, s.truth_m(i, j)), hi = std::max(hi, s.truth_m(i, j));
      if (std::isfinite(elevation(i, j))) mapped.push_back(elevation(i, j));
    }
  if (mapped.size() >= 50) {
    const auto at = [&](double share) {
      auto k = mapped.begin() + static_cast<std::ptrdiff_t>(share * static_cast<double>(mapped.size() - 1));
      std::nth_element(mapped.begin(), k, mapped.end());
      return *k;
    };
    lo = std::min(lo, at(0.02));
    hi = std::max(hi, at(0.98));
  }
  if (!(lo < hi)) lo = s.truth_m.minCoeff(), hi = std::max(s.truth_m.maxCoeff(), lo + 0.01f);

  io::GridRenderOptions style;
  style.units = "m";
  style.cell_size_m = s.cell_size_m;
  style.min_value = lo;
  style.max_value = hi;
  const auto save = [&](const char* name, io::RenderedGrid rendered, bool with_track) {
    if (with_track) io::draw_path(rendered, track, o.x_m, o.y_m, s.cell_size_m);
    io::write_png((dir / (prefix + name)).string(), rendered.image);
  };
  style.title = "Elevation, " + what + " (" + r.sensor + ", simulated)";
  save("elevation.png", io::render_grid(s.elevation_m(), filled, style), true);
  style.title = "Ground truth: highest point per cell";
  save("truth.png", io::render_grid(s.truth_m, style), true);

  io::GridRenderOptions certainty_style;
  certainty_style.title = "Certainty, " + what;
  certainty_style.cell_size_m = s.cell_size_m;
  certainty_style.min_value = 0.0;
  certainty_style.max_value = certainty_max;
  Eigen::MatrixXf certainty = s.certainty();
  const CellMask& states = s.state();
  for (Eigen::Index i = 0; i < certainty.rows(); ++i)
    for (Eigen::Index j = 0; j < certainty.cols(); ++j)
      if (static_cast<CellState>(states(i, j)) == CellState::unknown) certainty(i, j) = NAN;
  save("certainty.png", io::render_grid(certainty, certainty_style), false);

  // Errors only where the walk is scored (the swept area).
  Eigen::MatrixXf error = s.elevation_m() - s.truth_m;
  for (Eigen::Index i = 0; i < error.rows(); ++i)
    for (Eigen::Index j = 0; j < error.cols(); ++j)
      if (!swept(i, j)) error(i, j) = NAN;
  io::GridRenderOptions error_style;
  error_style.title = "Elevation error (map - truth), swept area, " + what;
  error_style.units = "m";
  error_style.cell_size_m = s.cell_size_m;
  error_style.min_value = -0.05;
  error_style.max_value = 0.05;
  error_style.colour_scale = io::ColourScale::diverging;
  save("error.png", io::render_grid(error, filled, error_style), true);
}

}  // namespace

std::string rocky_walk_summary_json(const RockyWalkResult& r, const RockyWalkOptions& options,
                                    const RockyWalkRunInfo& info) {
  const PoseErrorOptions& e = options.walk.pose_errors;
  const WalkResult& w = r.main;
  json sweep = json::array();
  for (const PoseSweepRow& row : r.sweep) {
    json entry = score_json(row.score, row.unknown_swept_cells);
    entry["label"] = row.label;
    entry["scale"] = row.scale;
    entry["reference"] = std::string(name(row.reference));
    entry["pose_rms"] = pose_json(row.pose);
    sweep.push_back(entry);
  }
  json summary = {
      {"experiment", "rocky-walk"},
      {"tool_version", io::tool_version()},
      {"sensor", r.sensor},
      {"source", "simulation"},
      {"seed", options.walk.seed},
      {"scene", info.scene_path},
      {"path", info.path_source},
      {"walk",
       {{"scans", w.scans},
        {"duration_s", w.duration_s},
        {"distance_m", w.distance_m},
        {"turned_deg", w.turned_rad * kDegPerRad},
        {"scans_with_yaw_change", w.scans_with_yaw_change}}},
      {"pose_error_options",
       {{"imu_pitch_noise_sigma_deg", e.imu_pitch_noise_sigma_rad * kDegPerRad},
        {"imu_pitch_bias_deg", e.imu_pitch_bias_rad * kDegPerRad},
        {"imu_roll_noise_sigma_deg", e.imu_roll_noise_sigma_rad * kDegPerRad},
        {"imu_roll_bias_deg", e.imu_roll_bias_rad * kDegPerRad},
        {"camera_position_noise_sigma_m", e.camera_position_noise_sigma_m},
        {"camera_yaw_noise_sigma_deg", e.camera_yaw_noise_sigma_rad * kDegPerRad},
        {"leg_height_noise_sigma_m", e.leg_height_noise_sigma_m},
        {"reference", std::string(name(e.reference))}}},
      {"pose_rms", pose_json(w.pose_errors)},
      {"map", score_json(w.mosaic_score, w.unknown_swept_cells)},
      {"local_map", score_json(w.local_score, 0)},
      {"visibility",
       {{"enabled", w.visibility_enabled},
        {"cells_contradicted", w.visibility_cells_contradicted},
        {"cells_cleared", w.visibility_cleared},
        {"cells_wrongly_cleared", w.visibility_wrongly_cleared},
        {"artifact_cells_cleared", w.visibility_artifacts_cleared},
        {"scans", w.visibility_scans},
        {"scans_with_maxima_from_whole_map", w.visibility_whole_map_scans}}},
      {"cell_size_m", w.local.cell_size_m},
      {"map_filter", std::string(map_filter_name(options.walk.map_filter))},
      {"elevation_rule", std::string(name(options.walk.mapper.update.elevation_rule))},
      {"cells_per_side", w.local.elevation_m().rows()},
      {"beams",
       {{"integrated", w.mapper_totals.integrated},
        {"implausible", w.mapper_totals.implausible},
        {"outside_map", w.mapper_totals.outside_map},
        {"invalid_range", w.mapper_totals.invalid_range}}},
      {"pose_error_sweep", sweep}};
  summary["local_map"].erase("unknown_swept_cells");
  if (!w.height_errors.empty()) summary["h_ref_error"] = height_error_json(w.height_errors);
  if (w.fused_under_soles_scans > 0) {
    summary["fused_under_soles"] = {
        {"mean_error_m", w.fused_under_soles_error_sum_m / static_cast<double>(w.fused_under_soles_scans)},
        {"scans", w.fused_under_soles_scans}};
  }
  if (reads_fused_layer(e.reference)) {
    const HeightFusionOptions& f = options.walk.height_fusion;
    summary["height_fusion"] = {{"mahalanobis_gate", f.mahalanobis_gate},
                                {"outlier_variance_m2", f.outlier_variance_m2},
                                {"min_variance_m2", f.min_variance_m2},
                                {"sigma_per_uncertainty", f.sigma_per_uncertainty}};
  }
  if (r.calibration) {
    const AttitudeCalibration& c = *r.calibration;
    summary["attitude_calibration"] = {{"pitch_bias_deg", c.pitch_bias_rad * kDegPerRad},
                                       {"roll_bias_deg", c.roll_bias_rad * kDegPerRad},
                                       {"height_offset_m", c.height_offset_m},
                                       {"points", c.points},
                                       {"residual_rms_m", c.residual_rms_m}};
  }
  if (r.receiver_coupling) summary["coupling"] = *r.receiver_coupling;
  if (r.range_calibration) {
    const RangeCalibrationFit& f = *r.range_calibration;
    summary["range_calibration"] = {{"coefficients", f.calibration.coefficients},
                                    {"pairs", f.residuals_m.size()},
                                    {"rms_residual_m", f.rms_residual_m},
                                    {"max_abs_residual_m", f.max_abs_residual_m}};
  }
  return summary.dump(2) + "\n";
}

std::string rocky_walk_table(const RockyWalkResult& r) {
  std::string out;
  char line[320];
  const WalkResult& w = r.main;
  std::snprintf(line, sizeof line,
                "rocky-walk, sensor %s (simulated): %zu scans, %.2f m walked, %.0f deg turned, %.0f mm cells\n",
                r.sensor.c_str(), w.scans, w.distance_m, w.turned_rad * kDegPerRad, w.local.cell_size_m * 1000);
  out += line;
  const MapScore& s = w.mosaic_score;
  std::snprintf(line, sizeof line,
                "whole walk: RMS error %.1f mm (%.1f mm without the mean offset of %+.1f mm), max %.1f mm, artifact "
                "cells %zu (> %.0f mm), coverage %.1f %%, unknown cells behind obstacles %zu (of %zu swept)\n",
                s.rms_error_m * 1000, offset_free_rms_m(s) * 1000, s.mean_error_m * 1000, s.max_error_m * 1000, s.artifact_cells, s.artifact_threshold_m * 1000,
                s.coverage * 100, w.unknown_swept_cells, s.scored_area_cells);
  out += line;
  const MapScore& l = w.local_score;
  std::snprintf(line, sizeof line, "final local map: RMS error %.1f mm, max %.1f mm, artifact cells %zu, coverage %.1f %%\n",
                l.rms_error_m * 1000, l.max_error_m * 1000, l.artifact_cells, l.coverage * 100);
  out += line;
  if (w.visibility_enabled) {
    std::snprintf(line, sizeof line,
                  "visibility clean-up: %zu cells passed below, %zu cleared: %zu wrongly (height within %.0f mm of the "
                  "truth), %zu artifacts\n",
                  w.visibility_cells_contradicted, w.visibility_cleared, w.visibility_wrongly_cleared,
                  w.visibility_correct_m * 1000, w.visibility_artifacts_cleared);
    out += line;
  }
  const PoseErrorStats& p = w.pose_errors;
  std::snprintf(line, sizeof line,
                "pose estimate RMS error: x %.1f mm, y %.1f mm, yaw %.2f deg, pitch %.2f deg, roll %.2f deg, "
                "sensor height %.1f mm (mean %+.1f mm)\n",
                p.x_m * 1000, p.y_m * 1000, p.yaw_rad * kDegPerRad, p.pitch_rad * kDegPerRad, p.roll_rad * kDegPerRad,
                p.sensor_height_m * 1000, p.mean_sensor_height_m * 1000);
  out += line;
  if (!w.height_errors.empty()) {
    const json h = height_error_json(w.height_errors);
    std::snprintf(line, sizeof line,
                  "sensor height's mean error by cause: odometry %+.1f, map under the soles %+.1f, soles misplaced "
                  "%+.1f, kinematics %+.1f mm; %zu of %zu scans without a map reading\n",
                  h["mean_from_odometry_m"].get<double>() * 1000, h["mean_from_map_m"].get<double>() * 1000,
                  h["mean_from_placement_m"].get<double>() * 1000, h["mean_from_kinematics_m"].get<double>() * 1000,
                  h["scans_without_reading"].get<std::size_t>(), w.height_errors.size());
    out += line;
  }
  if (w.fused_under_soles_scans > 0) {
    std::snprintf(line, sizeof line,
                  "fused layer under the true stance soles: mean error %+.2f mm over %zu scans (what the map alone "
                  "gives an h_ref read there)\n",
                  1000 * w.fused_under_soles_error_sum_m / static_cast<double>(w.fused_under_soles_scans),
                  w.fused_under_soles_scans);
    out += line;
  }
  if (r.calibration) {
    std::snprintf(line, sizeof line,
                  "attitude calibration on a flat floor: pitch bias %+.3f deg, roll bias %+.3f deg (%zu points, "
                  "residual %.1f mm)\n",
                  r.calibration->pitch_bias_rad * kDegPerRad, r.calibration->roll_bias_rad * kDegPerRad, r.calibration->points,
                  r.calibration->residual_rms_m * 1000);
    out += line;
  }
  if (r.range_calibration) {
    const RangeCalibrationFit& f = *r.range_calibration;
    std::snprintf(line, sizeof line,
                  "range calibration on a wall: correction %+.1f mm at 0.4 m, %+.1f mm at 0.8 m (%zu readings, "
                  "residual %.1f mm)\n",
                  f.calibration.correction_m(0.4) * 1000, f.calibration.correction_m(0.8) * 1000, f.residuals_m.size(),
                  f.rms_residual_m * 1000);
    out += line;
  }
  out += "pose errors  h_ref      pitch RMS  height RMS  map RMS  offset-free  max    artifacts  coverage  unknown behind\n";
  out += "                          [deg]      [mm]        [mm]     RMS [mm]     [mm]              [%]       obstacles\n";
  for (const PoseSweepRow& row : r.sweep) {
    std::snprintf(line, sizeof line, "%-12s %-9s %9.2f %11.1f %8.1f %12.1f %7.1f %10zu %9.1f %10zu\n", row.label.c_str(),
                  std::string(name(row.reference)).c_str(), row.pose.pitch_rad * kDegPerRad, row.pose.sensor_height_m * 1000,
                  row.score.rms_error_m * 1000, offset_free_rms_m(row.score) * 1000, row.score.max_error_m * 1000,
                  row.score.artifact_cells,
                  row.score.coverage * 100, row.unknown_swept_cells);
    out += line;
  }
  return out;
}

void write_rocky_walk_outputs(const RockyWalkResult& r, const RockyWalkOptions& options, const RockyWalkRunInfo& info,
                              const std::string& directory) {
  const std::filesystem::path dir(directory);
  std::error_code ec;
  std::filesystem::create_directories(dir, ec);
  if (ec) throw InputError(dir.string() + ": cannot create the output folder: " + ec.message());
  const WalkResult& w = r.main;
  const double certainty_max = options.walk.mapper.update.certainty_max;
  write_map_pictures(dir, "", "whole walk", w.mosaic, w.mosaic_swept, w.trajectory, r, certainty_max);
  write_map_pictures(dir, "local_", "final local map", w.local, w.local_swept, w.trajectory, r, certainty_max);

  io::TerrainViewOptions view;
  view.title = "Elevation map of the walk, 3D (" + r.sensor + ", simulated; heights x2)";
  const io::CellMask filled = state_mask(w.mosaic, CellState::filled);
  // Only the swept area: the mosaic's border holds stray far-range cells.
  Eigen::MatrixXf shown = w.mosaic.elevation_m(), truth = w.mosaic.truth_m;
  for (Eigen::Index i = 0; i < shown.rows(); ++i)
    for (Eigen::Index j = 0; j < shown.cols(); ++j)
      if (!w.mosaic_swept(i, j)) shown(i, j) = NAN, truth(i, j) = NAN;
  float lo = std::numeric_limits<float>::infinity(), hi = -lo;
  for (Eigen::Index i = 0; i < truth.rows(); ++i)
    for (Eigen::Index j = 0; j < truth.cols(); ++j)
      if (std::isfinite(truth(i, j))) lo = std::min(lo, truth(i, j)), hi = std::max(hi, truth(i, j));
  if (lo < hi) view.min_value = lo, view.max_value = hi;
  io::write_png((dir / "view3d.png").string(), io::render_terrain_view(shown, filled, w.mosaic.cell_size_m, view));
  view.title = "Ground truth over the same cells, 3D (heights x2)";
  io::write_png((dir / "truth_view3d.png").string(), io::render_terrain_view(truth, io::CellMask(), w.mosaic.cell_size_m, view));

  const Origin o = origin_of(w.mosaic);
  const auto csv = [&](const char* name, const Eigen::MatrixXf& values, const char* units) {
    io::GridCsvOptions c;
    c.layer_name = name;
    c.units = units;
    c.cell_size_m = w.mosaic.cell_size_m;
    c.origin_x_m = o.x_m;
    c.origin_y_m = o.y_m;
    io::write_grid_csv((dir / (std::string(name) + ".csv")).string(), values, c);
  };
  csv("elevation", w.mosaic.elevation_m(), "m");
  csv("certainty", w.mosaic.certainty(), "");
  csv("state", w.mosaic.state().cast<float>(), "");
  csv("truth", w.mosaic.truth_m, "m");
  csv("swept_area", w.mosaic_swept.cast<float>(), "");
  // The track drawn on the pictures, for the report page's 3D view.
  Eigen::MatrixXf track(static_cast<Eigen::Index>(w.trajectory.size()), 2);
  for (std::size_t k = 0; k < w.trajectory.size(); ++k) track.row(static_cast<Eigen::Index>(k)) = w.trajectory[k].cast<float>().transpose();
  if (track.rows() > 0) {
    io::GridCsvOptions columns;
    columns.layer_name = "path_x_m_y_m";
    columns.units = "m";
    io::write_grid_csv((dir / "path.csv").string(), track, columns);
  }
  if (!w.height_errors.empty()) {
    // Per scan: the trunk-height error and its parts by cause, and the feet read.
    Eigen::MatrixXf parts(static_cast<Eigen::Index>(w.height_errors.size()), 6);
    for (std::size_t k = 0; k < w.height_errors.size(); ++k) {
      const HeightReferenceError& e = w.height_errors[k];
      parts.row(static_cast<Eigen::Index>(k)) << static_cast<float>(e.error_m), static_cast<float>(e.odometry_m),
          static_cast<float>(e.map_m), static_cast<float>(e.placement_m), static_cast<float>(e.kinematics_m),
          static_cast<float>(e.feet_read);
    }
    io::GridCsvOptions columns;
    columns.layer_name = "error_m_odometry_m_map_m_placement_m_kinematics_m_feet_read";
    columns.units = "m";
    io::write_grid_csv((dir / "h_ref_error.csv").string(), parts, columns);
  }
  io::write_text_file((dir / "summary.json").string(), rocky_walk_summary_json(r, options, info), "summary");
  // The printed table, for the report page to show as it is.
  io::write_text_file((dir / "table.txt").string(), rocky_walk_table(r), "table");
  // The final map whole (the mosaic the CSVs hold), for map-info, export and other software.
  io::save_map_file((dir / "map.smap").string(), w.map,
                    io::map_file_metadata(w.map_config, "experiment rocky-walk --sensor " + r.sensor + " --scene " +
                                                            info.scene_path));
}

}  // namespace stridemap
