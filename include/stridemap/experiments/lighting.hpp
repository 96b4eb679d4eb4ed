#pragma once
// Structured light under ambient light (paper section 6.1, Fig. 21): the
// cart-rail run with the full image path (render, detect, map) at light
// levels from a dim lab to daylight, against the simulator's truth, and the
// URG-04LX beside it. Results are from the simulator, not from a real sensor.
//
// What the models assume: the camera is white-balanced to the ambient light
// and auto-exposes to it (sim/structured_light_image.hpp), so more light
// dims the laser relative to the scene; the URG-04LX model has no ambient
// light input at all (sim/urg_simulator.hpp): its range noise, systematic
// error and dropouts depend on range and echo amplitude only, following the
// paper (Fig. 21c, "almost no dependency") and Kneip et al. 2009 ("lighting
// has little effect"). Its row in the table is therefore the same at every
// level by construction, not a measurement of insensitivity.
#include <string>
#include <vector>

#include "stridemap/core/progress.hpp"
#include "stridemap/experiments/cart_rail.hpp"
#include "stridemap/render/png_image.hpp"

namespace stridemap {

struct LightingLevel {
  std::string name;
  double illuminance_lux = 0.0;
};

/// Dim lab 50, lab 300, bright lab 1000, beside a window 3000, overcast
/// daylight 10 000, daylight 30 000, sunlight 100 000 lux.
std::vector<LightingLevel> default_lighting_levels();

struct LightingOptions {
  /// The structured-light run (image pipeline forced); its ambient light is
  /// replaced by each level.
  CartRailOptions structured_light;
  /// The URG run, once.
  CartRailOptions urg;
  std::vector<LightingLevel> levels = default_lighting_levels();
  /// Where along the rail the example images of each level are taken [m]
  /// (trunk x); NaN: the middle of the rail.
  double example_x_m = 0.62;
  /// How far the runs are, as one loop over all levels and the URG's run
  /// (core/progress.hpp); the runs' own `progress` fields are not used.
  ProgressCallback progress{};
};

struct LightingRow {
  LightingLevel level;
  StripeTally stripe;
  MapScore score;
  std::vector<ObjectMeasurement> objects;
  io::RgbImage example;          ///< the camera image at example_x_m
  io::RgbImage example_overlay;  ///< with the detection drawn
};

/// The URG's range error from its model over the rail: simulated ranges
/// against the exact ranges of the same beams, for beams whose exact range
/// is within CartRailOptions::swept_max_range_m (the scored part).
struct UrgRangeError {
  std::size_t beams = 0;  ///< valid ranges compared
  double rms_m = 0.0;
  double max_m = 0.0;
};

struct LightingResult {
  std::vector<LightingRow> rows;
  CartRailResult urg;
  UrgRangeError urg_range;
};

/// Throws InputError for an empty or non-positive level list.
LightingResult run_lighting(const Scene& scene, const LightingOptions& options);

/// The URG's model error over the rail poses of `options` (same seed and
/// model as run_cart_rail).
UrgRangeError urg_range_error(const Scene& scene, const CartRailOptions& options);

std::string lighting_table(const LightingResult& result);
/// lighting.png (plots), lighting.csv (table), summary.json, and per level
/// image_<lux>lx.png with its overlay. Throws InputError naming the file
/// that cannot be written.
void write_lighting_outputs(const LightingResult& result, const LightingOptions& options, const std::string& scene_path,
                            const std::string& directory);

}  // namespace stridemap
