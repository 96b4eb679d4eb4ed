#pragma once
// Baseline: the "speckle" filter for isolated points, with the two rules of ROS
// laser_filters' LaserScanSpeckleFilter (algorithms.md 2.5) as they are meant
// to work (not their index quirks):
// - distance: a point survives when it belongs to a run of `window`
//   consecutive valid beams whose ranges all lie within max_range_difference
//   of the run's first range;
// - radius outlier: a point survives when at least `window` of the beams
//   within `window` indices of it lie within max_range_difference of it
//   (Euclidean distance in the scan plane).
// Points beyond max_range_m are never removed.
#include <cstddef>
#include <cstdint>
#include <limits>
#include <vector>

#include "stridemap/core/planar_scan.hpp"
#include "stridemap/preprocess/scan_checks.hpp"

namespace stridemap {

enum class SpeckleMode : std::uint8_t { distance, radius_outlier };

struct SpeckleFilterOptions {
  SpeckleMode mode = SpeckleMode::distance;
  /// Points farther than this are kept untested [m]. ROS uses 2 m because on a
  /// long-range indoor scanner speckles are near-range clutter; on the tilted
  /// URG every terrain point is within about 1 m and mixed points can appear
  /// at any range (also behind the far surface), so all ranges are tested.
  double max_range_m = std::numeric_limits<double>::infinity();
  /// Range (distance mode) or Euclidean (radius mode) tolerance [m]. ROS uses
  /// 0.1-0.4 m for rooms; terrain ranges are 0.2-1 m and box edges a few cm
  /// high, so 5 cm: above the step between neighbours on ground seen at 75 deg
  /// incidence at 1 m (about 2.3 cm per beam), below typical mixed-point offsets.
  double max_range_difference_m = 0.05;
  /// Run length (distance) or neighbour count and half window (radius). ROS
  /// defaults 2-4; 3 removes single points and pairs.
  std::size_t window = 3;

  /// Throws InputError naming the field when an option is out of range.
  void validate() const;
};

class SpeckleFilter {
 public:
  explicit SpeckleFilter(const SpeckleFilterOptions& options = {});

  const SpeckleFilterOptions& options() const { return options_; }

  /// Filters `scan` in place (removed beams become NaN, removed[i] = 1). A scan
  /// shorter than `window` in distance mode has no complete run, so all its
  /// valid points within max_range_m are removed.
  ScanFilterStats apply(PlanarScan& scan, std::vector<std::uint8_t>& removed);

 private:
  void mark_distance_runs(const PlanarScan& scan);
  void mark_radius_inliers(const PlanarScan& scan);

  SpeckleFilterOptions options_;
  std::vector<std::uint8_t> keep_;
  std::vector<double> cached_delta_rad_;  // per offset j - i, radius mode
  std::vector<double> cached_cos_;
};

}  // namespace stridemap
