#pragma once
// Measures the boxes and cylinders of a scene from an elevation map, as the
// paper measures its boxes in Table 1: length (along the rail, X), width
// (across it, Y) and height above the ground around the object.
#include <string>
#include <vector>

#include "stridemap/experiments/map_evaluation.hpp"
#include "stridemap/sim/scene.hpp"

namespace stridemap {

struct ObjectDimensions {
  double length_m = 0.0;
  double width_m = 0.0;
  double height_m = 0.0;
};

struct ObjectMeasurement {
  std::string name;
  std::string kind;  ///< "box" or "cylinder"
  ObjectDimensions truth;
  ObjectDimensions measured;
  bool found = false;  ///< false when the map holds no cell above the half-height threshold
  std::size_t cells = 0;  ///< cells of the connected region taken as the object
};

struct ObjectMeasureOptions {
  /// How far around the object's true footprint the map is searched [m].
  double search_margin_m = 0.05;
  /// Width of the ring around the search area whose median elevation is the
  /// local ground [m].
  double ground_ring_m = 0.05;
  /// A cell belongs to the object when it rises above the local ground by
  /// at least this fraction of the object's height in the map.
  double height_fraction = 0.5;
};

/// For each object: the connected region of known cells higher than half
/// way between the local ground and the region's top, grown from the cell
/// nearest the object's centre. Length and width are the spread of the
/// region's cell centres along the object's axes (for a max-height map that
/// spread is an unbiased estimate of the true extent), height is the median
/// of the region's measured elevations above the ground ring's median.
std::vector<ObjectMeasurement> measure_objects(const MapSnapshot& snapshot, const Scene& scene,
                                               const ObjectMeasureOptions& options = {});

/// Relative error in per cent, (measured - truth) / truth * 100.
double relative_error_pct(double measured, double truth);

}  // namespace stridemap
