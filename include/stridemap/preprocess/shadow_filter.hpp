#pragma once
// Baseline: the "shadow" (veiling) filter common in laser pipelines, with the
// computation of ROS laser_filters' ScanShadowsFilter (algorithms.md 2.4). At
// each point P_i it measures the angle between the line of sight back to the
// sensor and the segment to a neighbour P_j; when that angle is within
// min_angle of the line of sight (either side), a veil starts at P_i and every
// point near i that is farther than P_i is removed. It only ever removes the
// farther side, so mixed points in front of the near surface survive.
#include <cstddef>
#include <cstdint>
#include <vector>

#include "stridemap/core/planar_scan.hpp"
#include "stridemap/preprocess/scan_checks.hpp"

namespace stridemap {

struct ShadowFilterOptions {
  /// A veil when the angle at P_i is below this [rad], in [0, 90 deg). ROS default 10 deg.
  double min_angle_rad = 10.0 * 3.14159265358979323846 / 180.0;
  /// ... or above this [rad], in (90 deg, 180 deg]. ROS default 170 deg.
  double max_angle_rad = 170.0 * 3.14159265358979323846 / 180.0;
  /// Neighbours j of i tested: |j - i| <= window (>= 1). ROS default 1.
  std::size_t window = 1;
  /// Beams k with |k - i| <= neighbors and r_k > r_i are removed. ROS default 20.
  std::size_t neighbors = 20;
  /// Also remove P_i itself (ROS remove_shadow_start_point, default false).
  bool remove_shadow_start_point = false;

  /// Throws InputError naming the field when an option is out of range.
  void validate() const;
};

class ShadowFilter {
 public:
  explicit ShadowFilter(const ShadowFilterOptions& options = {});

  const ShadowFilterOptions& options() const { return options_; }

  /// Filters `scan` in place (removed beams become NaN, removed[i] = 1). All
  /// decisions use the input ranges, so removals never cascade.
  ScanFilterStats apply(PlanarScan& scan, std::vector<std::uint8_t>& removed);

 private:
  ShadowFilterOptions options_;
  double tan_min_angle_ = 0.0;
  double tan_supplement_max_angle_ = 0.0;  // tan(180 deg - max_angle)
  // sin/cos of the last angle difference seen at each offset j - i: scans
  // have (nearly) constant steps, so this saves the trigonometry per pair.
  std::vector<double> cached_delta_rad_;
  std::vector<double> cached_abs_sin_;
  std::vector<double> cached_cos_;
};

}  // namespace stridemap
