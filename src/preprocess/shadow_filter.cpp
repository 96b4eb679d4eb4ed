#include "stridemap/preprocess/shadow_filter.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>

#include "option_checks.hpp"

namespace stridemap {
namespace {


}  // namespace

void ShadowFilterOptions::validate() const {
  const char* owner = "ShadowFilterOptions";
  detail::require_angle_in_range(owner, "min_angle_rad", min_angle_rad, 0.0, true, 90.0, false);
  detail::require_angle_in_range(owner, "max_angle_rad", max_angle_rad, 90.0, false, 180.0, true);
  detail::require_at_least(owner, "window", window, 1);
}

ShadowFilter::ShadowFilter(const ShadowFilterOptions& options) : options_(options) {
  options_.validate();
  tan_min_angle_ = std::tan(options_.min_angle_rad);
  tan_supplement_max_angle_ = std::tan(std::numbers::pi - options_.max_angle_rad);
  const std::size_t offsets = 2 * options_.window + 1;
  cached_delta_rad_.assign(offsets, std::numeric_limits<double>::quiet_NaN());
  cached_abs_sin_.assign(offsets, 0.0);
  cached_cos_.assign(offsets, 0.0);
}

ScanFilterStats ShadowFilter::apply(PlanarScan& scan, std::vector<std::uint8_t>& removed) {
  ScanFilterStats stats = prepare_scan_for_filter(scan, removed, "shadow filter");
  const std::size_t n = scan.size();
  const std::vector<double>& range = scan.range_m;
  const std::size_t window = options_.window;
  const std::size_t neighbors = options_.neighbors;

  for (std::size_t i = 0; i < n; ++i) {
    const double r_i = range[i];
    if (std::isnan(r_i)) continue;
    bool veil = false;
    const std::size_t j_first = i >= window ? i - window : 0;
    const std::size_t j_last = std::min(n - 1, i + window);
    for (std::size_t j = j_first; j <= j_last && !veil; ++j) {
      const double r_j = range[j];
      if (j == i || std::isnan(r_j)) continue;
      const std::size_t slot = j + window - i;
      const double delta = scan.angle_rad[j] - scan.angle_rad[i];
      // Steps repeat up to rounding; 1e-9 rad changes sin/cos by at most 1e-9.
      if (!(std::abs(delta - cached_delta_rad_[slot]) <= 1e-9)) {
        cached_delta_rad_[slot] = delta;
        cached_abs_sin_[slot] = std::abs(std::sin(delta));
        cached_cos_[slot] = std::cos(delta);
      }
      // The angle at P_i between the way back to the sensor and P_i -> P_j is
      // atan2(num, den); compared through its tangent to avoid atan2 per pair.
      const double num = r_j * cached_abs_sin_[slot];
      const double den = r_i - r_j * cached_cos_[slot];
      veil = (den > 0.0 && num < den * tan_min_angle_) ||            // angle < min_angle
             (den < 0.0 && num < -den * tan_supplement_max_angle_);  // angle > max_angle
    }
    if (!veil) continue;
    const std::size_t k_first = i >= neighbors ? i - neighbors : 0;
    const std::size_t k_last = std::min(n - 1, i + neighbors);
    for (std::size_t k = k_first; k <= k_last; ++k) {
      if (range[k] > r_i) removed[k] = 1;  // NaN compares false: invalid beams stay unmarked
    }
    if (options_.remove_shadow_start_point) removed[i] = 1;
  }
  stats.removed = apply_removal_mask(scan, removed);
  return stats;
}

}  // namespace stridemap
