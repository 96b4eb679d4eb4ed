#pragma once
// The range calibration of the paper's Fig. 6, done on the simulated URG
// before a walk: the scanner, level, faces a white wall at known distances,
// and the cubic correction (sensors/range_calibration.hpp) is fitted to the
// (measured, true) ranges of the beams that meet the wall head-on. A real
// robot's owner does this once per unit on the lab bench (`stridemap
// calibrate-range` takes the pairs from a file); `experiment rocky-walk
// --calibrate-range on` does it in the simulator, so that the map is not
// built from a range that reads a few millimetres short at the terrain's
// 0.4-0.9 m, which lifts every floor point and which the flat-floor
// attitude calibration would otherwise take for a pitch bias
// (docs/experiments.md, "A calibrated range").
//
// Results are from the simulator, not from a real sensor.
#include <cstdint>

#include "stridemap/sensors/range_calibration.hpp"
#include "stridemap/sensors/urg04lx.hpp"
#include "stridemap/sim/urg_simulator.hpp"

namespace stridemap {

struct WallRangeCalibrationOptions {
  /// Wall distances from the scanner: first, last and step [m]. Defaults:
  /// 0.1 to 1.5 m every 5 cm, beyond the terrain ranges of the paper's
  /// mounts (0.3-1 m) at both ends, so the cubic is not extrapolated there.
  double nearest_m = 0.1;
  double farthest_m = 1.5;
  double step_m = 0.05;
  /// Scans per distance; each gives one pair per beam used.
  int scans_per_distance = 20;
  /// Beams either side of the one pointing straight ahead (2: five beams,
  /// within 0.7 deg of head-on).
  int beams_each_side = 2;
  /// The wall's diffuse reflectance: white paper, the target of the
  /// product's accuracy figures.
  double wall_reflectance = 0.9;

  /// Throws InputError naming the field.
  void validate() const;
};

/// Simulates the procedure with the sensor model of `urg` and `sim`
/// (single-ray beams: a flat wall seen head-on has no mixed pixels) and
/// fits the correction. Deterministic for the seed. Throws InputError when
/// too few valid readings come back to fit.
RangeCalibrationFit calibrate_range_on_wall(const UrgParameters& urg, const UrgSimOptions& sim, std::uint64_t seed,
                                            const WallRangeCalibrationOptions& options = {});

/// The seed of the wall run made before a walk of seed `walk_seed`: the wall
/// gets noise of its own, not a copy of the walk's first scans' noise.
inline std::uint64_t wall_calibration_seed(std::uint64_t walk_seed) { return walk_seed ^ 0x3A11CA1BULL; }

}  // namespace stridemap
