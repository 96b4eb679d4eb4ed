#pragma once
// The cart-on-a-rail experiment (paper section 6.1, Figs. 16b, 18-20,
// Table 1): the URG-04LX rides a straight rail over a scene, one scan every
// step, with a perfect pose; the map it builds is scored against the
// scene's ground truth and the objects are measured from it.
//
// Results are from the simulator (sim/), not from a real sensor.
#include <cstdint>
#include <string>
#include <vector>

#include "stridemap/core/terrain_mapper.hpp"
#include "stridemap/core/weighted_median_fill.hpp"
#include "stridemap/experiments/map_evaluation.hpp"
#include "stridemap/experiments/object_extents.hpp"
#include "stridemap/sensors/urg04lx.hpp"
#include "stridemap/sim/cart_rail.hpp"
#include "stridemap/sim/scene.hpp"
#include "stridemap/sim/urg_simulator.hpp"

namespace stridemap {

struct CartRailOptions {
  std::uint64_t seed = 1;
  /// The paper's Messor mount: 0.26 m high, pitched 35 deg down (Fig. 8c).
  SensorMount mount{};
  double cell_size_m = 0.01;
  /// Cells per side of the (fixed) map window; 0 sizes it to hold the swept
  /// area.
  int cells_per_side = 0;
  UpdateOptions update{};
  bool fill_in = true;
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
};

struct CartRailResult {
  CartRailPath rail;
  std::size_t scans = 0;
  MapperTotals mapper_totals;
  UrgConversionStats sensor_totals;
  std::size_t filled_cells = 0;
  MapSnapshot snapshot;
  CellMask swept_area;
  MapScore score;
  std::vector<ObjectMeasurement> objects;
};

/// Runs the experiment; deterministic for a seed. Throws InputError for a
/// scene or options that cannot run (e.g. a rail that does not move).
CartRailResult run_cart_rail(const Scene& scene, const CartRailOptions& options);

/// Cells (in window order) that the beams sweep on an empty floor at the
/// terrain's base elevation within `max_range_m`: each beam's ground point
/// moves along a segment parallel to the rail.
CellMask swept_floor_area(const ElevationMap& map, const std::vector<TrunkPose>& poses, const SensorMount& mount,
                          const UrgParameters& urg, double floor_elevation_m, double max_range_m);

}  // namespace stridemap
