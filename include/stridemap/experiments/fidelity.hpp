#pragma once
// The fidelity experiment: the cart-rail measurements on many
// random scenes (sim/random_scene.hpp) instead of the shipped few, reported
// as distributions (median, 90th percentile, worst) so that no figure rests
// on one scene. Per scene: the URG with mixed pixels and the paper's filters
// (the default run), the same scene without mixed pixels and with no filter
// (the references for the artifact figures), and the structured-light
// sensor. Results are from the simulator, not from a real sensor.
#include <cstdint>
#include <string>
#include <vector>

#include "stridemap/core/progress.hpp"
#include "stridemap/experiments/cart_rail.hpp"
#include "stridemap/sim/random_scene.hpp"

namespace stridemap {

struct FidelityOptions {
  std::size_t scenes = 30;
  /// Scene k is random scene seed * 1000 + k (`stridemap scene random
  /// --seed` makes it again), and that number seeds its simulation too.
  std::uint64_t seed = 1;
  RandomSceneKind kind = RandomSceneKind::boxes;
  /// The URG's runs: every setting but mixed_pixels, filters and seed.
  CartRailOptions urg{};
  /// The scan filters of the URG's filtered run (the unfiltered and the
  /// no-mixed-pixels references run without). Must not be empty. The
  /// default is "urg": the paper's pair and the between-scans test.
  std::vector<ScanFilterKind> filters{ScanFilterKind::range_clustering, ScanFilterKind::scan_sequence,
                                      ScanFilterKind::between_scans};
  /// Structured light: off skips it (then nothing is reported for it).
  bool structured_light = true;
  CartRailOptions structured_light_rail = default_structured_light_rail();
  /// Box extents at least this long are scored against the targets [m].
  double min_scored_extent_m = 0.09;
  /// An object whose top the ideal sensor saw less of than this share
  /// (ObjectMeasurement::seen_share) is partly seen: listed apart, out of
  /// the extent figures and the missed count.
  double min_seen_share = 0.95;
  /// Tall white and black boxes beside the line (random_scene_yaml's
  /// bystanders; boxes only). Not measured, but in every map's figures.
  bool bystanders = true;
  /// Structured light: scene k's ambient light is drawn from its seed,
  /// log-uniform between these [lux]; equal bounds fix it.
  double min_lux = 50.0, max_lux = 1000.0;
  ProgressCallback progress{};

  /// The CLI's structured-light defaults: Ragno's sensor, the image path at
  /// 300 lux, 5 mm cells, the CAS filter.
  static CartRailOptions default_structured_light_rail();
};

/// The figures of one scene.
struct FidelitySceneResult {
  std::uint64_t scene_seed = 0;
  std::string scene_yaml;
  std::vector<ObjectMeasurement> urg_objects;
  /// The same objects as the URG without mixed measurements of any kind
  /// (the artifact figures' reference run) maps them: what the beam
  /// spacing, the range noise and the grid leave of the extents.
  std::vector<ObjectMeasurement> urg_ideal_sensor_objects;
  std::vector<ObjectMeasurement> structured_light_objects;
  /// Largest |relative error| [%] over the box extents (length, width) of
  /// at least min_scored_extent_m; NaN when the scene has none.
  double urg_extent_error_pct = 0.0;
  double structured_light_extent_error_pct = 0.0;
  /// The same from the sub-cell edges with every reading (ObjectMeasurement::edges_untrimmed).
  double urg_extent_error_edges_untrimmed_pct = 0.0, structured_light_extent_error_edges_untrimmed_pct = 0.0;
  /// The same from the whole-cell extents (ObjectMeasurement::measured_trimmed, measured_untrimmed).
  double urg_extent_error_trimmed_pct = 0.0, urg_extent_error_untrimmed_pct = 0.0;
  double structured_light_extent_error_trimmed_pct = 0.0, structured_light_extent_error_untrimmed_pct = 0.0;
  std::size_t urg_objects_missed = 0;
  std::size_t structured_light_objects_missed = 0;
  /// Objects seen in part (FidelityOptions::min_seen_share), bystanders aside.
  std::size_t urg_objects_partly_seen = 0;
  std::size_t structured_light_objects_partly_seen = 0;
  /// Artifact cells of the map: without mixed pixels, with them unfiltered,
  /// with them and the filters, and with them and the ideal filter (the
  /// beams the simulator labels mixed dropped, nothing else).
  std::size_t artifact_cells_reference = 0, artifact_cells_unfiltered = 0, artifact_cells_filtered = 0;
  std::size_t artifact_cells_ideal = 0;
  /// Of the artifact cells mixed pixels add (unfiltered minus reference),
  /// the share the filters remove [%]; NaN when mixed pixels add none.
  double mixed_artifacts_removed_pct = 0.0;
  /// The same for the ideal filter: what dropping beams can remove at best,
  /// the rest being the receiver's lag and range noise at faces [%].
  double ideal_filter_artifacts_removed_pct = 0.0;
  /// Clean beams the filters drop [%].
  double clean_beams_dropped_pct = 0.0;
  /// The same of the clean beams that end inside the map's window [%]: what
  /// the map loses (BeamTally::clean_in_window).
  double clean_beams_in_map_dropped_pct = 0.0;
  double urg_rms_error_mm = 0.0;
  /// The map's RMS over level cells and beyond each cell's true span
  /// (MapScore::rms_error_level_m, rms_beyond_span_m) [mm].
  double urg_rms_level_mm = 0.0, urg_rms_beyond_span_mm = 0.0;
  /// Structured light (NaN without it): the ambient light of its run
  /// [lux]; detections off the true stripe [% of detections]; map cells
  /// clear of objects (MapSnapshot::clear_of_objects) off by more than
  /// the artifact threshold, and the largest error there [mm]; the map's
  /// largest error and RMS error [mm].
  double structured_light_lux = 0.0;
  double structured_light_false_detections_pct = 0.0;
  /// The false detections off the true row (StripeTally::off_row_rate) [%].
  double structured_light_off_row_detections_pct = 0.0;
  /// The false detections off every surface (StripeTally::off_surface_rate) [%].
  double structured_light_off_surface_detections_pct = 0.0;
  /// The false detections with no laser light near them
  /// (StripeTally::no_laser_light_rate) [%].
  double structured_light_no_laser_light_detections_pct = 0.0;
  double structured_light_clear_artifact_cells = 0.0;
  double structured_light_clear_max_error_mm = 0.0;
  double structured_light_max_error_mm = 0.0;
  double structured_light_rms_error_mm = 0.0;
  double structured_light_rms_level_mm = 0.0, structured_light_rms_beyond_span_mm = 0.0;
  /// Cells beyond their true span by more than the artifact threshold.
  double structured_light_beyond_span_cells = 0.0;
};

/// Median, 90th percentile and worst of a figure over scenes; "worse" is
/// higher, or lower for figures where more is better (the 90th percentile
/// is then taken from the low side). NaN values are left out.
struct FigureDistribution {
  std::string figure;
  bool higher_is_better = false;
  std::size_t count = 0;
  double median = 0.0, p90 = 0.0, worst = 0.0;
};

/// One side of the fully seen boxes over all scenes: its signed error
/// (outwards positive) at the 10th, 50th and 90th percentiles [mm].
struct EdgeErrorSpread {
  std::string sensor;  ///< "urg" or "structured_light"
  EdgeSide side = EdgeSide::near;
  std::size_t count = 0;
  double p10_mm = 0.0, median_mm = 0.0, p90_mm = 0.0;
};

struct FidelityResult {
  std::vector<FidelitySceneResult> scenes;
  std::vector<FigureDistribution> figures;
  std::vector<EdgeErrorSpread> edges;
};

FidelityResult run_fidelity(const FidelityOptions& options);

FigureDistribution distribution_of(const std::string& figure, std::vector<double> values, bool higher_is_better);

std::string fidelity_table(const FidelityResult& result);
std::string fidelity_summary_json(const FidelityResult& result, const FidelityOptions& options);
/// summary.json and the scenes (scenes/scene_<seed>.yaml) into `directory`.
void write_fidelity_outputs(const FidelityResult& result, const FidelityOptions& options, const std::string& directory);

}  // namespace stridemap
