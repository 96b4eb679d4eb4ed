#include "stridemap/preprocess/speckle_filter.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

#include "option_checks.hpp"

namespace stridemap {

void SpeckleFilterOptions::validate() const {
  const char* owner = "SpeckleFilterOptions";
  detail::require_in_range(owner, "max_range_m", max_range_m, 0.0, false,
                           std::numeric_limits<double>::infinity(), true, " m");
  detail::require_in_range(owner, "max_range_difference_m", max_range_difference_m, 0.0, true, 1e6, true,
                           " m");
  detail::require_at_least(owner, "window", window, 1);
}

SpeckleFilter::SpeckleFilter(const SpeckleFilterOptions& options) : options_(options) {
  options_.validate();
  cached_delta_rad_.assign(2 * options_.window + 1, std::numeric_limits<double>::quiet_NaN());
  cached_cos_.assign(2 * options_.window + 1, 0.0);
}

ScanFilterStats SpeckleFilter::apply(PlanarScan& scan, std::vector<std::uint8_t>& removed) {
  ScanFilterStats stats = prepare_scan_for_filter(scan, removed, "speckle filter");
  keep_.assign(scan.size(), 0);
  if (options_.mode == SpeckleMode::distance) {
    mark_distance_runs(scan);
  } else {
    mark_radius_inliers(scan);
  }
  for (std::size_t i = 0; i < scan.size(); ++i) {
    const double r = scan.range_m[i];
    if (!std::isnan(r) && r <= options_.max_range_m && keep_[i] == 0) removed[i] = 1;
  }
  stats.removed = apply_removal_mask(scan, removed);
  return stats;
}

void SpeckleFilter::mark_distance_runs(const PlanarScan& scan) {
  const std::size_t n = scan.size();
  const std::size_t window = options_.window;
  if (n < window) return;
  const std::vector<double>& range = scan.range_m;
  for (std::size_t start = 0; start + window <= n; ++start) {
    const double first = range[start];
    if (std::isnan(first)) continue;
    bool run = true;
    for (std::size_t m = 1; m < window && run; ++m) {
      // NaN fails the comparison, so an invalid beam breaks the run.
      run = std::abs(range[start + m] - first) <= options_.max_range_difference_m;
    }
    if (!run) continue;
    for (std::size_t m = 0; m < window; ++m) keep_[start + m] = 1;
  }
}

void SpeckleFilter::mark_radius_inliers(const PlanarScan& scan) {
  const std::size_t n = scan.size();
  const std::size_t window = options_.window;
  const std::vector<double>& range = scan.range_m;
  const double tolerance_sq = options_.max_range_difference_m * options_.max_range_difference_m;
  for (std::size_t i = 0; i < n; ++i) {
    const double r_i = range[i];
    if (std::isnan(r_i)) continue;
    std::size_t close = 0;
    const std::size_t j_first = i >= window ? i - window : 0;
    const std::size_t j_last = std::min(n - 1, i + window);
    for (std::size_t j = j_first; j <= j_last && close < window; ++j) {
      const double r_j = range[j];
      if (j == i || std::isnan(r_j)) continue;
      const std::size_t slot = j + window - i;
      const double delta = scan.angle_rad[j] - scan.angle_rad[i];
      // Steps repeat up to rounding; 1e-9 rad changes sin/cos by at most 1e-9.
      if (!(std::abs(delta - cached_delta_rad_[slot]) <= 1e-9)) {
        cached_delta_rad_[slot] = delta;
        cached_cos_[slot] = std::cos(delta);
      }
      const double distance_sq = r_i * r_i + r_j * r_j - 2.0 * r_i * r_j * cached_cos_[slot];
      if (distance_sq <= tolerance_sq) ++close;
    }
    keep_[i] = close >= window ? 1 : 0;
  }
}

}  // namespace stridemap
