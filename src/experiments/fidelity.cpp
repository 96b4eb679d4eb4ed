#include "stridemap/experiments/fidelity.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <limits>
#include <system_error>

#include <nlohmann/json.hpp>

#include "stridemap/config/scene_yaml.hpp"
#include "stridemap/core/error.hpp"
#include "stridemap/io/text_file.hpp"
#include "stridemap/mapfile/map_file.hpp"
#include "stridemap/sim/structured_light_simulator.hpp"

namespace stridemap {
namespace {

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();

bool is_bystander(const ObjectMeasurement& m) { return m.name.starts_with(kBystanderPrefix); }

// NaN (not worked out) counts as fully seen.
bool partly_seen(const ObjectMeasurement& m, double min_seen_share) { return m.seen_share < min_seen_share; }

// What the extent figures score: found boxes of the line, fully seen.
bool scored_box(const ObjectMeasurement& m, double min_seen_share) {
  return m.kind == "box" && m.found && !is_bystander(m) && !partly_seen(m, min_seen_share);
}

// The fully seen boxes' extents and edges, over all scenes, per sensor.
struct ExtentErrors {
  std::vector<double> every_pct;  // |relative error| of every scored extent
  std::vector<double> width_abs_mm, length_abs_mm;
  std::array<std::vector<double>, 4> edge_mm;  // signed, by EdgeSide

  void add(const std::vector<ObjectMeasurement>& objects, const FidelityOptions& options) {
    for (const ObjectMeasurement& m : objects) {
      if (!scored_box(m, options.min_seen_share)) continue;
      if (m.truth.width_m >= options.min_scored_extent_m)
        width_abs_mm.push_back(1000.0 * std::abs(m.measured.width_m - m.truth.width_m));
      if (m.truth.length_m >= options.min_scored_extent_m)
        length_abs_mm.push_back(1000.0 * std::abs(m.measured.length_m - m.truth.length_m));
      for (std::size_t side = 0; side < 4; ++side)
        if (std::isfinite(m.edge_errors_m[side])) edge_mm[side].push_back(1000.0 * m.edge_errors_m[side]);
    }
  }
};

double quantile_of(std::vector<double> values, double q) {
  std::sort(values.begin(), values.end());
  const double position = q * static_cast<double>(values.size() - 1);
  const auto lo = static_cast<std::size_t>(std::floor(position));
  const std::size_t hi = std::min(lo + 1, values.size() - 1);
  return values[lo] + (values[hi] - values[lo]) * (position - static_cast<double>(lo));
}

void add_edge_spreads(const std::string& sensor, const ExtentErrors& errors, std::vector<EdgeErrorSpread>& out) {
  for (std::size_t side = 0; side < 4; ++side) {
    const std::vector<double>& values = errors.edge_mm[side];
    EdgeErrorSpread spread{sensor, static_cast<EdgeSide>(side), values.size(), kNaN, kNaN, kNaN};
    if (!values.empty()) {
      spread.p10_mm = quantile_of(values, 0.1);
      spread.median_mm = quantile_of(values, 0.5);
      spread.p90_mm = quantile_of(values, 0.9);
    }
    out.push_back(spread);
  }
}

// Log-uniform in [lo, hi] from the scene's seed: light levels spread by
// factors, not by lux.
double scene_lux(std::uint64_t scene_seed, double lo, double hi) {
  if (lo == hi) return lo;
  const double unit = static_cast<double>(mix_seed(scene_seed ^ 0x1A4B1E47ULL) >> 11) * 0x1.0p-53;
  return lo * std::pow(hi / lo, unit);
}

// The largest |relative error| over the box extents long enough to score,
// and every such error into `all`.
double worst_extent_error(const std::vector<ObjectMeasurement>& objects, double min_extent_m, double min_seen_share,
                          std::vector<double>& all, ObjectDimensions ObjectMeasurement::* estimate) {
  double worst = kNaN;
  for (const ObjectMeasurement& m : objects) {
    if (!scored_box(m, min_seen_share)) continue;
    const ObjectDimensions& d = m.*estimate;
    for (const auto& [truth, measured] : {std::pair{m.truth.length_m, d.length_m},
                                          std::pair{m.truth.width_m, d.width_m}}) {
      if (truth < min_extent_m) continue;
      const double error = std::abs(relative_error_pct(measured, truth));
      all.push_back(error);
      worst = std::isnan(worst) ? error : std::max(worst, error);
    }
  }
  return worst;
}

std::size_t missed(const std::vector<ObjectMeasurement>& objects, double min_seen_share) {
  return static_cast<std::size_t>(std::count_if(objects.begin(), objects.end(), [&](const ObjectMeasurement& m) {
    return !m.found && !is_bystander(m) && !partly_seen(m, min_seen_share);
  }));
}

std::size_t count_partly_seen(const std::vector<ObjectMeasurement>& objects, double min_seen_share) {
  return static_cast<std::size_t>(std::count_if(objects.begin(), objects.end(), [&](const ObjectMeasurement& m) {
    return !is_bystander(m) && partly_seen(m, min_seen_share);
  }));
}

}  // namespace

CartRailOptions FidelityOptions::default_structured_light_rail() {
  CartRailOptions options;
  options.sensor = CartRailSensor::structured_light;
  options.structured_light.pipeline = StripePipeline::image;
  options.structured_light.image.ambient.illuminance_lux = 300.0;
  options.cell_size_m = 0.005;
  options.map_filter = MapFilter::cas;
  return options;
}

FigureDistribution distribution_of(const std::string& figure, std::vector<double> values, bool higher_is_better) {
  FigureDistribution d;
  d.figure = figure;
  d.higher_is_better = higher_is_better;
  std::erase_if(values, [](double v) { return std::isnan(v); });
  d.count = values.size();
  if (values.empty()) {
    d.median = d.p90 = d.worst = kNaN;
    return d;
  }
  // Sorted from best to worst, so the 90th percentile lies on the bad side.
  if (higher_is_better) std::sort(values.begin(), values.end(), std::greater<>());
  else std::sort(values.begin(), values.end());
  const auto at = [&](double q) {
    const double position = q * static_cast<double>(values.size() - 1);
    const auto lo = static_cast<std::size_t>(std::floor(position));
    const std::size_t hi = std::min(lo + 1, values.size() - 1);
    return values[lo] + (values[hi] - values[lo]) * (position - static_cast<double>(lo));
  };
  d.median = at(0.5);
  d.p90 = at(0.9);
  d.worst = values.back();
  return d;
}

namespace {

void check_fidelity_options(const FidelityOptions& options) {
  if (options.scenes == 0) throw InputError("fidelity: the number of scenes must be at least 1");
  if (options.filters.empty()) {
    throw InputError("fidelity: the filtered run needs at least one scan filter (the unfiltered run is the reference)");
  }
  if (!(options.min_lux >= 0.0) || !(options.max_lux >= options.min_lux) || !std::isfinite(options.max_lux) ||
      (options.min_lux == 0.0 && options.max_lux > 0.0)) {
    throw InputError("fidelity: the light levels must be finite with 0 <= min_lux <= max_lux, and min_lux > 0 unless "
                     "both are 0 (they are drawn log-uniform); got " + std::to_string(options.min_lux) + " and " +
                     std::to_string(options.max_lux));
  }
}

// The extent figures of one run's objects: the worst error per scene by
// each estimate, the objects missed and those partly seen; every extent's
// error goes into `errors`.
struct ExtentScores {
  double worst_pct, edges_untrimmed_pct, trimmed_pct, untrimmed_pct;
  std::size_t missed, partly_seen;
};

ExtentScores score_extents(const std::vector<ObjectMeasurement>& objects, const FidelityOptions& options,
                           ExtentErrors& errors) {
  std::vector<double> unused;
  const double min_extent = options.min_scored_extent_m, min_seen = options.min_seen_share;
  ExtentScores s{};
  s.worst_pct = worst_extent_error(objects, min_extent, min_seen, errors.every_pct, &ObjectMeasurement::measured);
  s.edges_untrimmed_pct = worst_extent_error(objects, min_extent, min_seen, unused, &ObjectMeasurement::edges_untrimmed);
  s.trimmed_pct = worst_extent_error(objects, min_extent, min_seen, unused, &ObjectMeasurement::measured_trimmed);
  s.untrimmed_pct = worst_extent_error(objects, min_extent, min_seen, unused, &ObjectMeasurement::measured_untrimmed);
  s.missed = missed(objects, min_seen);
  s.partly_seen = count_partly_seen(objects, min_seen);
  errors.add(objects, options);
  return s;
}

// The URG's three runs of one scene: the ideal sensor as the reference, then
// with mixed pixels unfiltered and filtered.
template <typename Run>
void score_urg(FidelitySceneResult& row, const FidelityOptions& options, const Run& run, ExtentErrors& errors,
               ExtentErrors& ideal_sensor_errors) {
  CartRailOptions urg = options.urg;
  urg.sensor = CartRailSensor::urg;
  urg.mixed_pixels = false;
  urg.filters = {};
  // The reference is the ideal sensor: no mixed measurement of any kind,
  // neither the footprint's nor the receiver's (its lagging gain control).
  const bool coupling = urg.sim.receiver.enabled;
  urg.sim.receiver.enabled = false;
  const CartRailResult reference = run(urg);
  row.urg_ideal_sensor_objects = reference.objects;
  ideal_sensor_errors.add(reference.objects, options);
  urg.sim.receiver.enabled = coupling;
  urg.mixed_pixels = true;
  const CartRailResult unfiltered = run(urg);
  // The yardstick: drop exactly the beams the simulator labels mixed.
  urg.drop_labelled_mixed = true;
  const CartRailResult ideal = run(urg);
  urg.drop_labelled_mixed = false;
  urg.filters = options.filters;
  const CartRailResult filtered = run(urg);
  row.urg_objects = filtered.objects;
  const ExtentScores extents = score_extents(filtered.objects, options, errors);
  row.urg_extent_error_pct = extents.worst_pct;
  row.urg_extent_error_edges_untrimmed_pct = extents.edges_untrimmed_pct;
  row.urg_extent_error_trimmed_pct = extents.trimmed_pct;
  row.urg_extent_error_untrimmed_pct = extents.untrimmed_pct;
  row.urg_objects_missed = extents.missed;
  row.urg_objects_partly_seen = extents.partly_seen;
  row.urg_rms_error_mm = filtered.score.rms_error_m * 1000.0;
  row.urg_rms_level_mm = filtered.score.rms_error_level_m * 1000.0;
  row.urg_rms_beyond_span_mm = filtered.score.rms_beyond_span_m * 1000.0;
  row.artifact_cells_reference = reference.score.artifact_cells;
  row.artifact_cells_unfiltered = unfiltered.score.artifact_cells;
  row.artifact_cells_filtered = filtered.score.artifact_cells;
  row.artifact_cells_ideal = ideal.score.artifact_cells;
  const double added = static_cast<double>(row.artifact_cells_unfiltered) -
                       static_cast<double>(row.artifact_cells_reference);
  const auto removed_pct = [&](std::size_t cells) {
    return added > 0.0
               ? 100.0 * (static_cast<double>(row.artifact_cells_unfiltered) - static_cast<double>(cells)) / added
               : kNaN;
  };
  row.mixed_artifacts_removed_pct = removed_pct(row.artifact_cells_filtered);
  row.ideal_filter_artifacts_removed_pct = removed_pct(row.artifact_cells_ideal);
  row.clean_beams_dropped_pct = 100.0 * filtered.beams.clean_drop_rate();
  row.clean_beams_in_map_dropped_pct = 100.0 * filtered.beams.clean_in_window_drop_rate();
}

// The structured-light run of one scene, at the scene's drawn light level.
template <typename Run>
void score_structured_light(FidelitySceneResult& row, const FidelityOptions& options, const Run& run,
                            ExtentErrors& errors) {
  CartRailOptions sl_options = options.structured_light_rail;
  row.structured_light_lux = scene_lux(row.scene_seed, options.min_lux, options.max_lux);
  sl_options.structured_light.image.ambient.illuminance_lux = row.structured_light_lux;
  const CartRailResult sl = run(sl_options);
  row.structured_light_false_detections_pct = 100.0 * sl.stripe.false_rate();
  row.structured_light_off_row_detections_pct = 100.0 * sl.stripe.off_row_rate();
  row.structured_light_off_surface_detections_pct = 100.0 * sl.stripe.off_surface_rate();
  row.structured_light_no_laser_light_detections_pct = 100.0 * sl.stripe.no_laser_light_rate();
  row.structured_light_clear_artifact_cells = static_cast<double>(sl.score.clear_artifact_cells);
  row.structured_light_clear_max_error_mm = sl.score.clear_max_error_m * 1000.0;
  row.structured_light_max_error_mm = sl.score.max_error_m * 1000.0;
  row.structured_light_rms_error_mm = sl.score.rms_error_m * 1000.0;
  row.structured_light_rms_level_mm = sl.score.rms_error_level_m * 1000.0;
  row.structured_light_rms_beyond_span_mm = sl.score.rms_beyond_span_m * 1000.0;
  row.structured_light_beyond_span_cells = static_cast<double>(sl.score.beyond_span_artifact_cells);
  row.structured_light_objects = sl.objects;
  const ExtentScores extents = score_extents(sl.objects, options, errors);
  row.structured_light_extent_error_pct = extents.worst_pct;
  row.structured_light_extent_error_edges_untrimmed_pct = extents.edges_untrimmed_pct;
  row.structured_light_extent_error_trimmed_pct = extents.trimmed_pct;
  row.structured_light_extent_error_untrimmed_pct = extents.untrimmed_pct;
  row.structured_light_objects_missed = extents.missed;
  row.structured_light_objects_partly_seen = extents.partly_seen;
}

void mark_structured_light_not_run(FidelitySceneResult& row) {
  row.structured_light_extent_error_pct = row.structured_light_extent_error_edges_untrimmed_pct =
      row.structured_light_extent_error_trimmed_pct = row.structured_light_extent_error_untrimmed_pct = kNaN;
  row.structured_light_lux = row.structured_light_false_detections_pct =
      row.structured_light_off_row_detections_pct = row.structured_light_off_surface_detections_pct =
      row.structured_light_no_laser_light_detections_pct =
      row.structured_light_clear_artifact_cells =
      row.structured_light_clear_max_error_mm = row.structured_light_max_error_mm =
      row.structured_light_rms_error_mm = row.structured_light_rms_level_mm =
      row.structured_light_rms_beyond_span_mm = row.structured_light_beyond_span_cells = kNaN;
}

// Each figure's distribution over the scenes, in the table's order.
void add_figures(FidelityResult& result, bool structured_light, const ExtentErrors& urg_errors,
                 const ExtentErrors& urg_ideal_errors, const ExtentErrors& sl_errors) {
  const auto figure = [&](const std::string& name, auto field, bool higher_is_better) {
    std::vector<double> values;
    for (const FidelitySceneResult& row : result.scenes) values.push_back(static_cast<double>(row.*field));
    result.figures.push_back(distribution_of(name, values, higher_is_better));
  };
  using R = FidelitySceneResult;
  figure("urg_box_extent_error_pct (worst per scene)", &R::urg_extent_error_pct, false);
  result.figures.push_back(distribution_of("urg_box_extent_error_pct (every extent)", urg_errors.every_pct, false));
  result.figures.push_back(distribution_of("urg_box_width_error_mm (every width, |error|)", urg_errors.width_abs_mm, false));
  result.figures.push_back(
      distribution_of("urg_box_length_error_mm (every length, |error|)", urg_errors.length_abs_mm, false));
  result.figures.push_back(distribution_of("urg_ideal_sensor_box_width_error_mm (every width, |error|)",
                                           urg_ideal_errors.width_abs_mm, false));
  result.figures.push_back(distribution_of("urg_ideal_sensor_box_length_error_mm (every length, |error|)",
                                           urg_ideal_errors.length_abs_mm, false));
  figure("urg_box_extent_error_pct, sub-cell edges untrimmed", &R::urg_extent_error_edges_untrimmed_pct, false);
  figure("urg_box_extent_error_pct, trimmed cells", &R::urg_extent_error_trimmed_pct, false);
  figure("urg_box_extent_error_pct, untrimmed cells", &R::urg_extent_error_untrimmed_pct, false);
  figure("urg_objects_missed", &R::urg_objects_missed, false);
  figure("urg_objects_partly_seen", &R::urg_objects_partly_seen, false);
  if (structured_light) {
    figure("structured_light_box_extent_error_pct (worst per scene)", &R::structured_light_extent_error_pct, false);
    result.figures.push_back(
        distribution_of("structured_light_box_extent_error_pct (every extent)", sl_errors.every_pct, false));
    result.figures.push_back(
        distribution_of("structured_light_box_width_error_mm (every width, |error|)", sl_errors.width_abs_mm, false));
    result.figures.push_back(distribution_of("structured_light_box_length_error_mm (every length, |error|)",
                                             sl_errors.length_abs_mm, false));
    figure("structured_light_box_extent_error_pct, sub-cell edges untrimmed",
           &R::structured_light_extent_error_edges_untrimmed_pct, false);
    figure("structured_light_box_extent_error_pct, trimmed cells", &R::structured_light_extent_error_trimmed_pct,
           false);
    figure("structured_light_box_extent_error_pct, untrimmed cells", &R::structured_light_extent_error_untrimmed_pct,
           false);
    figure("structured_light_objects_missed", &R::structured_light_objects_missed, false);
    figure("structured_light_objects_partly_seen", &R::structured_light_objects_partly_seen, false);
    figure("structured_light_false_detections_pct", &R::structured_light_false_detections_pct, false);
    figure("structured_light_false_detections_off_row_pct", &R::structured_light_off_row_detections_pct, false);
    figure("structured_light_false_detections_off_surface_pct", &R::structured_light_off_surface_detections_pct,
           false);
    figure("structured_light_false_detections_no_laser_light_pct", &R::structured_light_no_laser_light_detections_pct,
           false);
    figure("structured_light_cells_off_20mm_clear_of_objects", &R::structured_light_clear_artifact_cells, false);
    figure("structured_light_max_error_clear_of_objects_mm", &R::structured_light_clear_max_error_mm, false);
    figure("structured_light_max_error_mm", &R::structured_light_max_error_mm, false);
    figure("structured_light_rms_error_mm", &R::structured_light_rms_error_mm, false);
    figure("structured_light_rms_error_level_cells_mm", &R::structured_light_rms_level_mm, false);
    figure("structured_light_rms_beyond_span_mm", &R::structured_light_rms_beyond_span_mm, false);
    figure("structured_light_cells_beyond_span_20mm", &R::structured_light_beyond_span_cells, false);
  }
  figure("mixed_artifacts_removed_pct", &R::mixed_artifacts_removed_pct, true);
  figure("ideal_filter_artifacts_removed_pct", &R::ideal_filter_artifacts_removed_pct, true);
  figure("clean_beams_dropped_pct", &R::clean_beams_dropped_pct, false);
  figure("clean_beams_in_map_dropped_pct", &R::clean_beams_in_map_dropped_pct, false);
  figure("urg_rms_error_mm", &R::urg_rms_error_mm, false);
  figure("urg_rms_error_level_cells_mm", &R::urg_rms_level_mm, false);
  figure("urg_rms_beyond_span_mm", &R::urg_rms_beyond_span_mm, false);
}

}  // namespace

FidelityResult run_fidelity(const FidelityOptions& options) {
  check_fidelity_options(options);
  FidelityResult result;
  ExtentErrors urg_errors, urg_ideal_errors, sl_errors;
  const std::size_t runs_per_scene = options.structured_light ? 4 : 3;
  for (std::size_t k = 0; k < options.scenes; ++k) {
    FidelitySceneResult row;
    row.scene_seed = options.seed * 1000 + k;
    row.scene_yaml = random_scene_yaml(options.kind, row.scene_seed, options.bystanders);
    const Scene scene = parse_scene_yaml(row.scene_yaml, "random scene " + std::to_string(row.scene_seed));
    std::size_t part = k * runs_per_scene;
    const auto run = [&](CartRailOptions run_options) {
      run_options.seed = row.scene_seed;
      run_options.progress = progress_of_part(options.progress, part++, options.scenes * runs_per_scene);
      return run_cart_rail(scene, run_options);
    };
    score_urg(row, options, run, urg_errors, urg_ideal_errors);
    if (options.structured_light) {
      score_structured_light(row, options, run, sl_errors);
    } else {
      mark_structured_light_not_run(row);
    }
    result.scenes.push_back(std::move(row));
  }
  add_figures(result, options.structured_light, urg_errors, urg_ideal_errors, sl_errors);
  add_edge_spreads("urg", urg_errors, result.edges);
  add_edge_spreads("urg_ideal_sensor", urg_ideal_errors, result.edges);
  if (options.structured_light) add_edge_spreads("structured_light", sl_errors, result.edges);
  return result;
}

std::string fidelity_table(const FidelityResult& result) {
  std::string out = "fidelity, cart rail on " + std::to_string(result.scenes.size()) +
                    " random scenes (simulated)\nfigure                                                      scenes"
                    "    median       p90     worst\n";
  char line[256];
  for (const FigureDistribution& d : result.figures) {
    std::snprintf(line, sizeof line, "%-60s %6zu %9.2f %9.2f %9.2f\n", d.figure.c_str(), d.count, d.median, d.p90,
                  d.worst);
    out += line;
  }
  if (!result.edges.empty()) {
    out += "edges of fully seen boxes, signed error outwards [mm]             boxes       p10    median       p90\n";
    for (const EdgeErrorSpread& e : result.edges) {
      const std::string name = e.sensor + " " + to_string(e.side);
      std::snprintf(line, sizeof line, "%-60s %6zu %9.2f %9.2f %9.2f\n", name.c_str(), e.count, e.p10_mm, e.median_mm,
                    e.p90_mm);
      out += line;
    }
  }
  return out;
}

namespace {

nlohmann::json number_or_null(double value) { return std::isnan(value) ? nlohmann::json() : nlohmann::json(value); }

nlohmann::json objects_json(const std::vector<ObjectMeasurement>& objects, double min_seen_share) {
  nlohmann::json list = nlohmann::json::array();
  for (const ObjectMeasurement& m : objects) {
    list.push_back({{"name", m.name},
                    {"kind", m.kind},
                    {"found", m.found},
                    {"truth_m", {{"length", m.truth.length_m}, {"width", m.truth.width_m}, {"height", m.truth.height_m}}},
                    {"measured_m",
                     {{"length", m.measured.length_m}, {"width", m.measured.width_m}, {"height", m.measured.height_m}}},
                    {"trimmed_m", {{"length", m.measured_trimmed.length_m}, {"width", m.measured_trimmed.width_m}}},
                    {"untrimmed_m",
                     {{"length", m.measured_untrimmed.length_m}, {"width", m.measured_untrimmed.width_m}}},
                    {"edges_trimmed_m", {{"length", number_or_null(m.edges_trimmed.length_m)},
                                         {"width", number_or_null(m.edges_trimmed.width_m)}}},
                    {"edges_untrimmed_m", {{"length", number_or_null(m.edges_untrimmed.length_m)},
                                           {"width", number_or_null(m.edges_untrimmed.width_m)}}},
                    {"edge_errors_m", {{"near", number_or_null(m.edge_errors_m[0])},
                                       {"far", number_or_null(m.edge_errors_m[1])},
                                       {"left", number_or_null(m.edge_errors_m[2])},
                                       {"right", number_or_null(m.edge_errors_m[3])}}},
                    {"seen_share", number_or_null(m.seen_share)},
                    {"partly_seen", partly_seen(m, min_seen_share)},
                    {"measured_yaw_rad", m.measured_yaw_rad}});
  }
  return list;
}

}  // namespace

std::string fidelity_summary_json(const FidelityResult& result, const FidelityOptions& options) {
  nlohmann::json figures = nlohmann::json::array();
  for (const FigureDistribution& d : result.figures) {
    figures.push_back({{"figure", d.figure},
                       {"higher_is_better", d.higher_is_better},
                       {"scenes", d.count},
                       {"median", number_or_null(d.median)},
                       {"p90", number_or_null(d.p90)},
                       {"worst", number_or_null(d.worst)}});
  }
  nlohmann::json edges = nlohmann::json::array();
  for (const EdgeErrorSpread& e : result.edges) {
    edges.push_back({{"sensor", e.sensor},
                     {"side", to_string(e.side)},
                     {"boxes", e.count},
                     {"p10_mm", number_or_null(e.p10_mm)},
                     {"median_mm", number_or_null(e.median_mm)},
                     {"p90_mm", number_or_null(e.p90_mm)}});
  }
  nlohmann::json scenes = nlohmann::json::array();
  for (const FidelitySceneResult& row : result.scenes) {
    nlohmann::json entry = {{"scene_seed", row.scene_seed},
                            {"urg_box_extent_error_pct", number_or_null(row.urg_extent_error_pct)},
                            {"urg_objects_missed", row.urg_objects_missed},
                            {"urg_objects_partly_seen", row.urg_objects_partly_seen},
                            {"urg_rms_error_mm", row.urg_rms_error_mm},
                            {"urg_rms_error_level_cells_mm", row.urg_rms_level_mm},
                            {"urg_rms_beyond_span_mm", row.urg_rms_beyond_span_mm},
                            {"artifact_cells",
                             {{"reference", row.artifact_cells_reference},
                              {"unfiltered", row.artifact_cells_unfiltered},
                              {"filtered", row.artifact_cells_filtered},
                              {"ideal_filter", row.artifact_cells_ideal}}},
                            {"mixed_artifacts_removed_pct", number_or_null(row.mixed_artifacts_removed_pct)},
                            {"ideal_filter_artifacts_removed_pct", number_or_null(row.ideal_filter_artifacts_removed_pct)},
                            {"clean_beams_dropped_pct", row.clean_beams_dropped_pct},
                            {"clean_beams_in_map_dropped_pct", row.clean_beams_in_map_dropped_pct},
                            {"urg_objects", objects_json(row.urg_objects, options.min_seen_share)},
                            {"urg_ideal_sensor_objects",
                             objects_json(row.urg_ideal_sensor_objects, options.min_seen_share)}};
    if (options.structured_light) {
      entry["structured_light_box_extent_error_pct"] = number_or_null(row.structured_light_extent_error_pct);
      entry["structured_light_objects_missed"] = row.structured_light_objects_missed;
      entry["structured_light_objects_partly_seen"] = row.structured_light_objects_partly_seen;
      entry["structured_light_objects"] = objects_json(row.structured_light_objects, options.min_seen_share);
      entry["structured_light_lux"] = row.structured_light_lux;
      entry["structured_light_false_detections_pct"] = row.structured_light_false_detections_pct;
      entry["structured_light_false_detections_off_row_pct"] = row.structured_light_off_row_detections_pct;
      entry["structured_light_false_detections_off_surface_pct"] = row.structured_light_off_surface_detections_pct;
      entry["structured_light_false_detections_no_laser_light_pct"] = row.structured_light_no_laser_light_detections_pct;
      entry["structured_light_cells_off_20mm_clear_of_objects"] = row.structured_light_clear_artifact_cells;
      entry["structured_light_max_error_clear_of_objects_mm"] = row.structured_light_clear_max_error_mm;
      entry["structured_light_max_error_mm"] = row.structured_light_max_error_mm;
      entry["structured_light_rms_error_mm"] = row.structured_light_rms_error_mm;
      entry["structured_light_rms_error_level_cells_mm"] = row.structured_light_rms_level_mm;
      entry["structured_light_rms_beyond_span_mm"] = row.structured_light_rms_beyond_span_mm;
      entry["structured_light_cells_beyond_span_20mm"] = row.structured_light_beyond_span_cells;
    }
    scenes.push_back(std::move(entry));
  }
  const nlohmann::json summary = {
      {"experiment", "fidelity"},
      {"tool_version", io::tool_version()},
      {"source", "simulation"},
      {"seed", options.seed},
      {"kind", std::string(name(options.kind))},
      {"scene_count", options.scenes},
      {"min_scored_extent_m", options.min_scored_extent_m},
      {"filters", scan_filter_list_name(options.filters)},
      {"coupling", options.urg.sim.receiver.enabled},
      {"bystanders", options.bystanders},
      {"lux", {{"min", options.min_lux}, {"max", options.max_lux}}},
      {"saturation_halo_dn", options.structured_light_rail.structured_light.detector.saturation_halo_dn},
      {"structured_light", options.structured_light
                               ? std::string(name(options.structured_light_rail.structured_light.pipeline))
                               : std::string("off")},
      {"min_seen_share", options.min_seen_share},
      {"figures", figures},
      {"edges", edges},
      {"scenes", scenes}};
  return summary.dump(2) + "\n";
}

void write_fidelity_outputs(const FidelityResult& result, const FidelityOptions& options,
                            const std::string& directory) {
  const std::filesystem::path dir(directory);
  std::error_code ec;
  std::filesystem::create_directories(dir / "scenes", ec);
  if (ec) throw InputError((dir / "scenes").string() + ": cannot create the output folder: " + ec.message());
  for (const FidelitySceneResult& row : result.scenes) {
    io::write_text_file((dir / "scenes" / ("scene_" + std::to_string(row.scene_seed) + ".yaml")).string(),
                        row.scene_yaml, "scene");
  }
  io::write_text_file((dir / "summary.json").string(), fidelity_summary_json(result, options), "summary");
  // The printed table, for the report page to show as it is.
  io::write_text_file((dir / "table.txt").string(), fidelity_table(result), "table");
}

}  // namespace stridemap
