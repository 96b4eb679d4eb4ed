#include "stridemap/experiments/mount_analysis_report.hpp"

#include <cmath>
#include <cstdio>
#include <filesystem>
#include <functional>
#include <numbers>
#include <system_error>

#include <nlohmann/json.hpp>

#include "stridemap/core/error.hpp"
#include "stridemap/io/text_file.hpp"
#include "stridemap/mapfile/map_file.hpp"
#include "stridemap/render/heat_map.hpp"
#include "stridemap/render/png_image.hpp"

namespace stridemap {
namespace {

using nlohmann::json;
constexpr double kMountDegPerRad = 180.0 / std::numbers::pi;

json metrics_json(const MountMetrics& m) {
  json j = {{"name", m.mount.name},
            {"height_m", m.mount.mount.height_m},
            {"pitch_deg", m.mount.mount.pitch_rad * kMountDegPerRad},
            {"sees_ground", m.sees_ground},
            {"unobserved_fraction", m.unobserved_fraction},
            {"mean_height_uncertainty_m", m.mean_height_uncertainty_m},
            {"stripe_width_m", m.stripe_width_m},
            {"look_ahead_m", m.look_ahead_m},
            {"ground_cells", m.ground_cells},
            {"score", m.score}};
  j["sheet_angle_deg"] = m.mount.sheet_angle_rad ? json(*m.mount.sheet_angle_rad * kMountDegPerRad) : json(nullptr);
  j["favourable_range_share"] = m.favourable_range_share ? json(*m.favourable_range_share) : json(nullptr);
  return j;
}

std::string row_text(const MountMetrics& m) {
  char line[256];
  char share[16] = "-";
  if (m.favourable_range_share) std::snprintf(share, sizeof share, "%.1f", *m.favourable_range_share * 100);
  if (!m.sees_ground) {
    std::snprintf(line, sizeof line, "%-16s %5.1f %6.1f   cannot see the ground\n", m.mount.name.c_str(),
                  m.mount.mount.height_m * 100, m.mount.mount.pitch_rad * kMountDegPerRad);
    return line;
  }
  std::snprintf(line, sizeof line, "%-16s %5.1f %6.1f %10.1f %11.1f %9.2f %9.2f %9s %7.3f\n", m.mount.name.c_str(),
                m.mount.mount.height_m * 100, m.mount.mount.pitch_rad * kMountDegPerRad, m.unobserved_fraction * 100,
                m.mean_height_uncertainty_m * 1000, m.stripe_width_m, m.look_ahead_m, share, m.score);
  return line;
}

}  // namespace

std::string mount_analysis_summary_json(const MountAnalysisResult& r, const MountAnalysisOptions& o) {
  json named = json::array(), sweep = json::array();
  for (const MountMetrics& m : r.named) named.push_back(metrics_json(m));
  for (const MountMetrics& m : r.sweep) sweep.push_back(metrics_json(m));
  const json summary = {
      {"experiment", "mount-analysis"},
      {"tool_version", io::tool_version()},
      {"sensor", r.sensor},
      {"source", "simulation"},
      {"seed", o.seed},
      {"fields", o.fields},
      {"step_field",
       {{"block_size_m", o.field.block_size_m},
        {"min_height_m", o.field.min_height_m},
        {"max_height_m", o.field.max_height_m},
        {"empty_fraction", o.field.empty_fraction}}},
      {"corridor_half_width_m", o.corridor_half_width_m},
      {"max_ground_range_m", o.max_ground_range_m},
      {"stripe_max_range_m", o.stripe_max_range_m},
      {"score",
       {{"min_stripe_width_m", o.score.min_stripe_width_m},
        {"min_look_ahead_m", o.score.min_look_ahead_m},
        {"uncertainty_scale_m", o.score.uncertainty_scale_m}}},
      {"named", named},
      {"sweep", sweep},
      {"best", r.sweep.empty() ? json(nullptr) : metrics_json(r.sweep[r.best])}};
  return summary.dump(2) + "\n";
}

std::string mount_analysis_table(const MountAnalysisResult& r) {
  std::string out = "mount-analysis, sensor " + r.sensor + " (simulated), random step fields\n";
  out += "mount            height pitch  unobserved  uncertainty  stripe  look-ahead  in 0.2-0.9 m  score\n";
  out += "                 [cm]   [deg]  [%]         [mm]         [m]     [m]         [%]\n";
  for (const MountMetrics& m : r.named) out += row_text(m);
  if (!r.sweep.empty()) {
    out += "best of the sweep (" + std::to_string(r.pitches) + " pitches x " + std::to_string(r.heights) + " heights):\n";
    out += row_text(r.sweep[r.best]);
    const std::size_t row = r.best / r.heights, col = r.best % r.heights;
    if (r.sweep.size() > 1 && (row == 0 || col == 0 || row + 1 == r.pitches || col + 1 == r.heights)) {
      out += "warning: the best mount lies on the sweep's edge, so the optimum may lie outside it "
             "(widen --heights-cm / --pitches-deg)\n";
    }
  }
  return out;
}

void write_mount_analysis_outputs(const MountAnalysisResult& r, const MountAnalysisOptions& o,
                                  const std::string& directory) {
  const std::filesystem::path dir(directory);
  std::error_code ec;
  std::filesystem::create_directories(dir, ec);
  if (ec) throw InputError(dir.string() + ": cannot create the output folder: " + ec.message());

  io::HeatMapOptions style;
  style.x_label = "sensor height [cm]";
  style.y_label = "pitch alpha [deg]";
  style.missing_label = "cannot see the ground";
  for (double h : o.sweep_heights_m) {
    char t[16];
    std::snprintf(t, sizeof t, "%.0f", h * 100);
    style.x_ticks.emplace_back(t);
  }
  for (double p : o.sweep_pitches_rad) {
    char t[16];
    std::snprintf(t, sizeof t, "%.0f", p * kMountDegPerRad);
    style.y_ticks.emplace_back(t);
  }
  const int best_row = static_cast<int>(r.best / r.heights), best_col = static_cast<int>(r.best % r.heights);
  style.highlight = std::make_pair(best_row, best_col);
  // The frame says which mount won; a winner on the sweep's edge may only
  // be the best of a range that is too narrow, so the pictures say so.
  const bool on_edge = best_row == 0 || best_col == 0 || best_row + 1 == static_cast<int>(r.pitches) ||
                       best_col + 1 == static_cast<int>(r.heights);
  std::string best_text;
  if (!r.sweep.empty()) {
    char t[200];
    std::snprintf(t, sizeof t, "\nframed: the best mount, %.0f cm, %.0f deg", r.sweep[r.best].mount.mount.height_m * 100,
                  r.sweep[r.best].mount.mount.pitch_rad * kMountDegPerRad);
    best_text = t;
    if (on_edge && r.sweep.size() > 1) best_text += "\nWARNING: it lies on the sweep's edge; widen the sweep";
  }
  const auto heat = [&](const char* file, const std::string& title, const char* units, double scale,
                        const std::function<std::optional<double>(const MountMetrics&)>& value) {
    Eigen::MatrixXf grid(static_cast<Eigen::Index>(r.pitches), static_cast<Eigen::Index>(r.heights));
    for (std::size_t i = 0; i < r.pitches; ++i) {
      for (std::size_t j = 0; j < r.heights; ++j) {
        const MountMetrics& m = r.at(i, j);
        const std::optional<double> v = m.sees_ground ? value(m) : std::nullopt;
        grid(static_cast<Eigen::Index>(i), static_cast<Eigen::Index>(j)) = v ? static_cast<float>(*v * scale) : NAN;
      }
    }
    io::HeatMapOptions s = style;
    s.title = title + " (" + r.sensor + ", simulated)" + best_text;
    s.units = units;
    io::write_png((dir / file).string(), io::render_heat_map(grid, s));
  };
  heat("unobserved.png", "Ground ahead never observed", "%", 100.0,
       [](const MountMetrics& m) { return m.unobserved_fraction; });
  heat("uncertainty.png", "Mean predicted height uncertainty", "mm", 1000.0,
       [](const MountMetrics& m) { return m.mean_height_uncertainty_m; });
  heat("stripe_width.png", "Width of the observed stripe", "m", 1.0, [](const MountMetrics& m) { return m.stripe_width_m; });
  heat("look_ahead.png", "Look-ahead distance", "m", 1.0, [](const MountMetrics& m) { return m.look_ahead_m; });
  if (!r.sweep.empty() && r.sweep.front().favourable_range_share) {
    heat("range_share.png", "Ranges to -0.10..+0.15 m surfaces in 0.2-0.9 m", "%", 100.0,
         [](const MountMetrics& m) { return m.favourable_range_share; });
  }
  char score_title[200];
  std::snprintf(score_title, sizeof score_title,
                "Score = (1 - unobserved) x in-range share / (1 + uncertainty / %.0f mm)\n"
                "(0 if stripe < %.2f m or look-ahead < %.2f m), higher is better", o.score.uncertainty_scale_m * 1000, o.score.min_stripe_width_m,
                o.score.min_look_ahead_m);
  heat("score.png", score_title, "", 1.0, [](const MountMetrics& m) { return m.score; });

  std::string csv = "name,height_m,pitch_deg,sees_ground,unobserved_fraction,mean_height_uncertainty_m,stripe_width_m,"
                    "look_ahead_m,favourable_range_share,score\n";
  for (const auto* list : {&r.named, &r.sweep}) {
    for (const MountMetrics& m : *list) {
      char line[256];
      char share[24] = "";
      if (m.favourable_range_share) std::snprintf(share, sizeof share, "%.6g", *m.favourable_range_share);
      std::snprintf(line, sizeof line, "%s,%.6g,%.6g,%d,%.6g,%.6g,%.6g,%.6g,%s,%.6g\n", m.mount.name.c_str(),
                    m.mount.mount.height_m, m.mount.mount.pitch_rad * kMountDegPerRad, m.sees_ground ? 1 : 0, m.unobserved_fraction,
                    m.mean_height_uncertainty_m, m.stripe_width_m, m.look_ahead_m, share, m.score);
      csv += line;
    }
  }
  io::write_text_file((dir / "mounts.csv").string(), csv, "mount table");
  io::write_text_file((dir / "summary.json").string(), mount_analysis_summary_json(r, o), "summary");
  // The printed table, for the report page to show as it is.
  io::write_text_file((dir / "table.txt").string(), mount_analysis_table(r), "table");
}

}  // namespace stridemap
