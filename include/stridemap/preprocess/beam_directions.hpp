#pragma once
// cos and sin of a scan's beam angles, recomputed only when the angles change.
// Scans of one sensor repeat the same angles, so the filters that need
// Cartesian points pay for the trigonometry once per stream, not per scan.
#include <algorithm>
#include <cmath>
#include <cstring>
#include <vector>

namespace stridemap {

class BeamDirections {
 public:
  /// Makes cos()/sin() match `angle_rad`; an O(n) comparison when unchanged.
  void update(const std::vector<double>& angle_rad) {
    // Equal bits are equal values (a NaN's cosine is NaN whichever it was):
    // memcmp settles the common case at memory speed; == decides the rest
    // (a -0 for a 0 keeps the directions, as it always did).
    if (angle_rad.size() == angle_rad_.size() &&
        (angle_rad.empty() ||
         std::memcmp(angle_rad.data(), angle_rad_.data(), angle_rad.size() * sizeof(double)) == 0)) {
      return;
    }
    if (angle_rad == angle_rad_) return;
    angle_rad_.assign(angle_rad.begin(), angle_rad.end());
    cos_.resize(angle_rad.size());
    sin_.resize(angle_rad.size());
    double step_min = 0.0, step_max = 0.0;
    for (std::size_t i = 0; i < angle_rad.size(); ++i) {
      cos_[i] = std::cos(angle_rad[i]);
      sin_[i] = std::sin(angle_rad[i]);
      if (i == 0) continue;
      const double step = std::abs(angle_rad[i] - angle_rad[i - 1]);
      step_min = i == 1 ? step : std::min(step_min, step);
      step_max = i == 1 ? step : std::max(step_max, step);
    }
    step_spread_rad_ = step_max - step_min;
  }
  const std::vector<double>& cos() const { return cos_; }
  const std::vector<double>& sin() const { return sin_; }
  /// Largest minus smallest |angle[i] - angle[i - 1]| (0 below two beams):
  /// whether every step between neighbours is the same up to rounding.
  double step_spread_rad() const { return step_spread_rad_; }

 private:
  std::vector<double> angle_rad_;
  std::vector<double> cos_;
  std::vector<double> sin_;
  double step_spread_rad_ = 0.0;
};

}  // namespace stridemap
