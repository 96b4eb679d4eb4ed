// The foothold experiment's walks over scenes and its outputs.
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <limits>

#include <nlohmann/json.hpp>

#include "stridemap/config/scene_yaml.hpp"
#include "stridemap/core/error.hpp"
#include "stridemap/experiments/foothold.hpp"
#include "stridemap/experiments/urg_walk_sensor.hpp"
#include "stridemap/io/text_file.hpp"
#include "stridemap/mapfile/map_file.hpp"
#include "stridemap/mapfile/map_outputs.hpp"
#include "stridemap/render/grid_render.hpp"
#include "stridemap/render/png_image.hpp"
#include "stridemap/sim/random_scene.hpp"

namespace stridemap {
namespace {

using nlohmann::json;

json number(double v) { return std::isfinite(v) ? json(v) : json(nullptr); }

json confusion_json(const FootholdConfusion& c) {
  return {{"scored_cells", c.scored_cells},   {"true_safe", c.true_safe},
          {"false_safe", c.false_safe},       {"false_unsafe", c.false_unsafe},
          {"true_unsafe", c.true_unsafe},     {"unknown_score", c.unknown_score},
          {"precision", number(c.precision())}, {"recall", number(c.recall())}};
}

// Linear interpolation between order statistics; NaN runs left out.
double percentile(std::vector<double> values, double p) {
  values.erase(std::remove_if(values.begin(), values.end(), [](double v) { return std::isnan(v); }), values.end());
  if (values.empty()) return std::numeric_limits<double>::quiet_NaN();
  std::sort(values.begin(), values.end());
  const double at = p * static_cast<double>(values.size() - 1);
  const auto lo = static_cast<std::size_t>(std::floor(at));
  const std::size_t hi = std::min(lo + 1, values.size() - 1);
  return values[lo] + (at - static_cast<double>(lo)) * (values[hi] - values[lo]);
}

struct Group {
  const char* name;
  std::vector<const FootholdRun*> runs;
};

std::vector<Group> groups_of(const FootholdExperimentResult& r, std::size_t mockup_runs) {
  Group mockup{"mockup", {}}, random{"random", {}}, all{"all", {}};
  for (std::size_t k = 0; k < r.runs.size(); ++k) {
    (k < mockup_runs ? mockup : random).runs.push_back(&r.runs[k]);
    all.runs.push_back(&r.runs[k]);
  }
  return {mockup, random, all};
}

json distribution(const std::vector<const FootholdRun*>& runs, double (*get)(const FootholdRun&)) {
  std::vector<double> v;
  for (const FootholdRun* run : runs) v.push_back(get(*run));
  return {{"p10", number(percentile(v, 0.1))}, {"median", number(percentile(v, 0.5))}, {"p90", number(percentile(v, 0.9))}};
}

std::size_t mockup_count(const FootholdExperimentResult& r) {
  return static_cast<std::size_t>(
      std::count_if(r.runs.begin(), r.runs.end(), [](const FootholdRun& run) { return run.scene.rfind("random", 0) != 0; }));
}

}  // namespace

FootholdExperimentResult run_foothold_experiment(const Scene& mockup, const WalkPath& mockup_path,
                                                 const std::string& mockup_name,
                                                 const FootholdExperimentOptions& options) {
  options.validate();
  if (options.mockup_seeds + options.random_scenes == 0) {
    throw InputError("foothold experiment: no walks (mock-up seeds and random scenes are both 0)");
  }
  FootholdExperimentResult result;
  const std::size_t total = options.mockup_seeds + options.random_scenes;
  std::size_t part = 0;
  const auto walk = [&](const Scene& scene, const WalkPath& path, std::uint64_t seed, const std::string& name) {
    FootholdExperimentOptions run_options = options;
    run_options.walk.seed = seed;
    UrgWalkSensor sensor(scene, UrgWalkSensorOptions{}, run_options.walk.mapper.update, seed);
    FootholdRun run = run_foothold_walk(scene, path, sensor, run_options, result.runs.empty() ? &result : nullptr);
    run.scene = name;
    result.runs.push_back(run);
    if (options.progress) options.progress(++part, total);
  };
  for (std::size_t k = 0; k < options.mockup_seeds; ++k) walk(mockup, mockup_path, options.seed + k, mockup_name);
  for (std::size_t k = 0; k < options.random_scenes; ++k) {
    const std::uint64_t scene_seed = options.seed * 1000 + k;
    const std::string name = "random rocky " + std::to_string(scene_seed);
    const Scene scene = parse_scene_yaml(random_scene_yaml(RandomSceneKind::rocky, scene_seed), name);
    if (!scene.walk_path) throw InputError(name + ": the generated scene has no walk path");
    walk(scene, *scene.walk_path, scene_seed, name);
  }
  return result;
}

std::string foothold_summary_json(const FootholdExperimentResult& r, const FootholdExperimentOptions& options) {
  const FootholdOptions& f = options.foothold;
  json runs = json::array();
  for (const FootholdRun& run : r.runs) {
    runs.push_back({{"scene", run.scene},
                    {"seed", run.seed},
                    {"all", confusion_json(run.all)},
                    {"measured", confusion_json(run.measured)},
                    {"truth_safe_cells", run.truth_safe_cells},
                    {"mean_slope_error_deg", number(run.mean_slope_error_deg)},
                    {"mean_step_error_m", number(run.mean_step_error_m)},
                    {"mean_score_error", number(run.mean_score_error)}});
  }
  json distributions = json::object();
  for (const Group& g : groups_of(r, mockup_count(r))) {
    if (g.runs.empty()) continue;
    distributions[g.name] = {
        {"runs", g.runs.size()},
        {"precision", distribution(g.runs, [](const FootholdRun& x) { return x.all.precision(); })},
        {"recall", distribution(g.runs, [](const FootholdRun& x) { return x.all.recall(); })},
        {"precision_measured", distribution(g.runs, [](const FootholdRun& x) { return x.measured.precision(); })},
        {"recall_measured", distribution(g.runs, [](const FootholdRun& x) { return x.measured.recall(); })}};
  }
  const json summary = {
      {"experiment", "foothold"},
      {"simulated", true},
      {"tool_version", io::tool_version()},
      {"sensor", "urg"},
      {"foothold",
       {{"foot_radius_m", f.foot_radius_m},
        {"max_slope_deg", f.max_slope_deg},
        {"max_step_m", f.max_step_m},
        {"max_roughness_m", f.max_roughness_m},
        {"edge_search_radius_m", f.edge_search_radius_m},
        {"edge_clearance_m", f.edge_clearance_m},
        {"full_certainty", f.full_certainty},
        {"min_known_fraction", f.min_known_fraction},
        {"safe_score", f.safe_score}}},
      {"mockup_seeds", options.mockup_seeds},
      {"random_scenes", options.random_scenes},
      {"seed", options.seed},
      {"runs", runs},
      {"distributions", distributions},
  };
  return summary.dump(2) + "\n";
}

std::string foothold_table(const FootholdExperimentResult& r) {
  std::string out = "foothold (simulated): \"safe\" = score >= threshold, every mapped cell of the swept area\n";
  char line[256];
  std::snprintf(line, sizeof line, "%-26s %5s %8s %9s %7s %10s %10s %9s\n", "scene", "seed", "cells", "precision",
                "recall", "false_safe", "slope_err", "step_err");
  out += line;
  for (const FootholdRun& run : r.runs) {
    std::snprintf(line, sizeof line, "%-26s %5llu %8zu %9.3f %7.3f %10zu %8.2f d %7.1f mm\n", run.scene.c_str(),
                  static_cast<unsigned long long>(run.seed), run.all.scored_cells, run.all.precision(),
                  run.all.recall(), run.all.false_safe, run.mean_slope_error_deg, run.mean_step_error_m * 1000.0);
    out += line;
  }
  for (const Group& g : groups_of(r, mockup_count(r))) {
    if (g.runs.empty()) continue;
    std::vector<double> p, rc;
    for (const FootholdRun* run : g.runs) {
      p.push_back(run->all.precision());
      rc.push_back(run->all.recall());
    }
    std::snprintf(line, sizeof line, "%-7s (%zu runs): precision median %.3f [p10 %.3f, p90 %.3f], recall median %.3f "
                                     "[p10 %.3f, p90 %.3f]\n",
                  g.name, g.runs.size(), percentile(p, 0.5), percentile(p, 0.1), percentile(p, 0.9),
                  percentile(rc, 0.5), percentile(rc, 0.1), percentile(rc, 0.9));
    out += line;
  }
  return out;
}

void write_foothold_outputs(const FootholdExperimentResult& result, const FootholdExperimentOptions& options,
                            const std::string& directory) {
  const std::filesystem::path dir(directory);
  io::write_text_file((dir / "summary.json").string(), foothold_summary_json(result, options), "summary");
  io::write_text_file((dir / "table.txt").string(), foothold_table(result), "table");
  if (!result.first_map || !result.first_truth) return;
  io::MapOutputOptions style;
  style.elevation_title = "Elevation, " + result.runs.front().scene + " seed " + std::to_string(result.runs.front().seed) +
                          " (simulated)";
  style.certainty_max = options.walk.mapper.update.certainty_max;
  io::write_map_layers(export_map(*result.first_map), (dir / "map").string(), style);
  const std::vector<std::string> score_layer{"foothold_score"};
  const ExportedMap truth = export_map(*result.first_truth, score_layer);
  io::GridRenderOptions truth_style;
  truth_style.title = "Foothold score of the truth";
  truth_style.cell_size_m = truth.cell_size_m;
  truth_style.min_value = 0.0;
  truth_style.max_value = 1.0;
  io::write_png((dir / "truth_foothold_score.png").string(),
                io::render_grid(truth.layer("foothold_score").f32, truth_style).image);
}

}  // namespace stridemap
