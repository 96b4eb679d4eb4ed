#pragma once
// The cart-on-a-rail experiment (paper section 6.1, Figs. 16, 17-20,
// Table 1): the URG-04LX or the structured-light sensor rides a straight
// rail over a scene, one scan (or camera frame) every step, with a perfect
// pose; the map it builds is scored against the scene's ground truth and the
// objects are measured from it.
//
// Results are from the simulator (sim/), not from a real sensor.
#include <cstdint>
#include <string>
#include <vector>

#include "stridemap/core/cas_filter.hpp"
#include "stridemap/core/map_filter.hpp"
#include "stridemap/core/progress.hpp"
#include "stridemap/core/enum_names.hpp"
#include "stridemap/core/terrain_mapper.hpp"
#include "stridemap/core/weighted_median_fill.hpp"
#include "stridemap/experiments/map_evaluation.hpp"
#include "stridemap/experiments/object_extents.hpp"
#include "stridemap/config/mapper_config.hpp"
#include "stridemap/vision/stripe_detector.hpp"
#include "stridemap/preprocess/scan_filter_chain.hpp"
#include "stridemap/sensors/urg04lx.hpp"
#include "stridemap/sim/cart_rail.hpp"
#include "stridemap/sim/footprint_beam_model.hpp"
#include "stridemap/sim/scene.hpp"
#include "stridemap/sim/structured_light_image.hpp"
#include "stridemap/sim/urg_simulator.hpp"

namespace stridemap {

/// The range sensors an experiment can carry.
enum class SimulatedSensor : std::uint8_t { urg, structured_light };
using CartRailSensor = SimulatedSensor;

inline constexpr EnumNameTable<SimulatedSensor, 2> kSimulatedSensorNames{{
    {SimulatedSensor::urg, "urg"},
    {SimulatedSensor::structured_light, "structured-light"},
}};
/// "urg" or "structured-light": the --sensor word and the outputs' name.
constexpr std::string_view name(SimulatedSensor sensor) { return enum_name_in(kSimulatedSensorNames, sensor); }
template <>
inline SimulatedSensor parse_enum_name<SimulatedSensor>(std::string_view text) {
  return enum_value_in(kSimulatedSensorNames, text, "a sensor");
}

/// How a structured-light frame becomes stripe pixels.
enum class StripePipeline : std::uint8_t {
  image,      ///< render the camera image, detect the stripe in it (the full path)
  geometric,  ///< the simulator's true stripe (plus its row noise option): no image
};

inline constexpr EnumNameTable<StripePipeline, 2> kStripePipelineNames{{
    {StripePipeline::image, "image"},
    {StripePipeline::geometric, "geometric"},
}};
/// "image" or "geometric": the --pipeline word and summary.json's.
constexpr std::string_view name(StripePipeline pipeline) { return enum_name_in(kStripePipelineNames, pipeline); }
template <>
inline StripePipeline parse_enum_name<StripePipeline>(std::string_view text) {
  return enum_value_in(kStripePipelineNames, text, "a pipeline");
}

struct StructuredLightRailOptions {
  /// Ragno's sensor (the defaults of StructuredLightParameters, as in
  /// configs/ragno_structured_light.yaml); its mount is used, not
  /// CartRailOptions::mount.
  StructuredLightParameters parameters{};
  StripePipeline pipeline = StripePipeline::image;
  StructuredLightSimOptions geometry{};
  StripeImageOptions image{};
  io::StripeDetectorOptions detector{};
  /// Detections below this confidence are not mapped.
  double min_confidence = 0.0;
  /// A detection within this many rows of the true stripe is correct [px];
  /// farther, or where the truth has no visible stripe, it is false.
  double row_tolerance_px = 2.0;
  /// A false detection is off every surface when its point (eq. 1, then
  /// eq. 5 at the frame's pose) lies more than this above the highest or
  /// below the lowest scene surface within this distance of it across [m].
  /// 5 mm: one 5 mm cell, and over twice the height a 2-row error gives at
  /// the rail's ranges; a lit box face is a surface, so light on it is not.
  double off_surface_m = 0.005;
  /// A false detection has no laser light under it when no peak of its
  /// column's noise-free laser signal within row_tolerance_px of its row
  /// reaches this signal-to-noise ratio
  /// (StructuredLightImageRenderer::laser_signal_to_noise): what the
  /// detector made of ambient light and noise alone. 3: a peak that noise
  /// reaches on about one pixel in a thousand.
  double laser_light_min_snr = 3.0;
};

/// The detector against the simulator's truth, over all frames.
struct StripeTally {
  std::size_t frames = 0;
  std::size_t columns = 0;          ///< frames x image width
  std::size_t truth_visible = 0;    ///< columns where the camera sees the lit stripe
  std::size_t detected = 0;         ///< columns with a (mapped) detection
  std::size_t correct = 0;          ///< visible and detected within the row tolerance
  std::size_t false_detections = 0; ///< detected where not visible, or beyond the tolerance
  /// Of the false detections, those on the true row (within the tolerance)
  /// of a stripe the truth marks hidden from the camera: at an occlusion
  /// edge the truth's visibility test and the rendered image can differ by
  /// a pixel, and such a row maps to the right point.
  std::size_t hidden_on_true_row = 0;
  /// Of the false detections, those whose point lies off every surface
  /// (StructuredLightRailOptions::off_surface_m): where the map would put
  /// a height no surface has. The rest are laser light on a real surface
  /// that the truth's one stripe per column does not name.
  std::size_t off_surface = 0;
  /// Of the false detections, those on no peak of laser light in the
  /// image (StructuredLightRailOptions::laser_light_min_snr): the
  /// detector's own errors. The rest are the laser's light where the
  /// truth's one stripe per column does not put it (an occlusion edge, the
  /// sheet's tail on a box's edge). 0 on the geometric path.
  std::size_t no_laser_light = 0;
  double row_error_rms_px = 0.0;    ///< over correct detections
  std::size_t map_points = 0;       ///< stripe pixels that became map points

  double detection_rate() const {
    return truth_visible ? static_cast<double>(correct) / static_cast<double>(truth_visible) : 0.0;
  }
  double false_rate() const {
    return detected ? static_cast<double>(false_detections) / static_cast<double>(detected) : 0.0;
  }
  /// False detections off every surface, per detection.
  double off_surface_rate() const {
    return detected ? static_cast<double>(off_surface) / static_cast<double>(detected) : 0.0;
  }
  /// False detections with no laser light near them, per detection.
  double no_laser_light_rate() const {
    return detected ? static_cast<double>(no_laser_light) / static_cast<double>(detected) : 0.0;
  }
  /// False detections off the true row, per detection.
  double off_row_rate() const {
    return detected ? static_cast<double>(false_detections - hidden_on_true_row) / static_cast<double>(detected) : 0.0;
  }
};

struct CartRailOptions {
  std::uint64_t seed = 1;
  /// Told the scans (rail positions) done so far.
  ProgressCallback progress{};
  CartRailSensor sensor = CartRailSensor::urg;
  /// Used when sensor is structured_light.
  StructuredLightRailOptions structured_light{};
  /// Simulate the beam's footprint and the phase-shift ranging, so that
  /// edges give mixed pixels (sim/footprint_beam_model.hpp); off: one ray
  /// per beam, no mixed pixels.
  bool mixed_pixels = false;
  FootprintBeamOptions footprint{};
  /// fill for the URG; the paper uses cas for structured light (set by the
  /// CLI with --sensor structured-light).
  MapFilter map_filter = MapFilter::fill;
  CasOptions cas{};
  /// The URG's mount: the paper's Messor mount: 0.26 m high, pitched 35 deg down (Fig. 8c).
  SensorMount mount{};
  double cell_size_m = 0.01;
  /// Cells per side of the (fixed) map window; 0 sizes it to hold the swept
  /// area.
  int cells_per_side = 0;
  UpdateOptions update{};
  /// Used by MapFilter::fill (and CAS's own fill takes cas.fill).
  FillOptions fill{};
  UrgParameters urg{};
  /// Per-unit range calibration applied by the sensor model (none by default).
  RangeCalibration calibration{};
  UrgSimOptions sim{};
  /// The rail when the scene has no `cart_rail:` section.
  CartRailPath default_rail{0.0, 1.2, 0.0, 0.01, 0.0};
  /// Ground a beam meets on an empty floor counts as swept (scored) only
  /// within this range [m]; 0.9 m ends the interval the paper calls the most
  /// favourable for the URG (section 4.2).
  double swept_max_range_m = 0.9;
  MapScoreOptions score{};
  ObjectMeasureOptions objects{};
  /// Scan filters applied between the sensor model and the mapper, in
  /// order (none by default; "paper" = range clustering + scan sequence).
  std::vector<ScanFilterKind> filters{};
  ScanFilterChainOptions filter_options{};
  /// For reference only: drop exactly the beams the simulator labels mixed,
  /// before the filters (an ideal filter that sees the ground truth). What
  /// its map still gets wrong no beam filter can mend (range noise and
  /// eq. 10's highest-value rule at faces), so it is the yardstick for how
  /// many of the mixed-pixel artifacts a real filter removes.
  bool drop_labelled_mixed = false;
};

/// How the filters treated the simulator's beams, against its labels (the
/// filters never see the labels).
struct BeamTally {
  std::size_t clean = 0;           ///< beams labelled clean
  std::size_t mixed = 0;           ///< beams labelled mixed
  std::size_t dropped = 0;         ///< error codes from the sensor
  std::size_t clean_removed = 0;   ///< clean beams a filter removed
  std::size_t mixed_removed = 0;   ///< mixed beams a filter removed
  /// Clean beams whose true end lies inside the map's window: what the map
  /// would have used. A filter that drops a beam outside it loses nothing.
  std::size_t clean_in_window = 0;
  std::size_t clean_in_window_removed = 0;  ///< of those, removed by a filter

  double mixed_recall() const { return mixed ? static_cast<double>(mixed_removed) / static_cast<double>(mixed) : 0.0; }
  double clean_drop_rate() const {
    return clean ? static_cast<double>(clean_removed) / static_cast<double>(clean) : 0.0;
  }
  double clean_in_window_drop_rate() const {
    return clean_in_window ? static_cast<double>(clean_in_window_removed) / static_cast<double>(clean_in_window) : 0.0;
  }
  /// Of the beams removed, the share that was mixed.
  double precision() const {
    const std::size_t removed = clean_removed + mixed_removed;
    return removed ? static_cast<double>(mixed_removed) / static_cast<double>(removed) : 0.0;
  }
  double f1() const {
    const double p = precision(), r = mixed_recall();
    return p + r > 0.0 ? 2.0 * p * r / (p + r) : 0.0;
  }
};

struct CartRailResult {
  CartRailPath rail;
  std::size_t scans = 0;
  MapperTotals mapper_totals;
  UrgConversionStats sensor_totals;
  std::size_t filled_cells = 0;
  std::size_t cas_removed_cells = 0;
  MapSnapshot snapshot;
  /// The final map (after the map filter) whole, and the settings it was
  /// made with: what the run's map.smap holds (mapfile/map_file.hpp).
  ElevationMap map;
  MapperConfig map_config;
  CellMask swept_area;
  MapScore score;
  std::vector<ObjectMeasurement> objects;
  BeamTally beams;
  /// Structured light only.
  StripeTally stripe;
  StripeConversionStats stripe_conversion;
};

/// Runs the experiment; deterministic for a seed. Throws InputError for a
/// scene or options that cannot run (e.g. a rail that does not move).
CartRailResult run_cart_rail(const Scene& scene, const CartRailOptions& options);

/// Cells (in window order) that the beams sweep on an empty floor at the
/// terrain's base elevation within `max_range_m`: each beam's ground point
/// moves along a segment parallel to the rail.
CellMask swept_floor_area(const ElevationMap& map, const std::vector<TrunkPose>& poses, const SensorMount& mount,
                          const UrgParameters& urg, double floor_elevation_m, double max_range_m);

/// Cells that the stripe's points sweep on an empty floor between the first
/// and the last pose: first[i] moves to last[i] parallel to the rail (NaN
/// entries are skipped).
CellMask swept_area_between(const ElevationMap& map, const std::vector<Eigen::Vector2d>& first,
                            const std::vector<Eigen::Vector2d>& last);

/// Where the structured-light stripe lies on an empty floor at
/// floor_elevation_m from `pose`, per image column (NaN where it is not seen).
std::vector<Eigen::Vector2d> stripe_floor_points(const StructuredLightParameters& parameters, const TrunkPose& pose,
                                                 double floor_elevation_m);

}  // namespace stridemap
