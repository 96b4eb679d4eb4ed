#pragma once
// The clustering test between neighbouring beams of a whole scan in one
// pass (internal), for range clustering without bridging and the line
// extractor's pre-segmentation. Their loops test one pair after another with
// a RangeRatioBandCache; when every step between neighbours is the same up
// to that cache's tolerance, the cache never recomputes after its first pair,
// so one band decides every pair and the tests no longer depend on each other.
#include <cstddef>
#include <cstdint>
#include <cstring>
#include <limits>
#include <vector>

#include "stridemap/core/planar_scan.hpp"
#include "stridemap/preprocess/beam_directions.hpp"
#include "stridemap/preprocess/range_clustering.hpp"
#include "stridemap/preprocess/range_sigma.hpp"

namespace stridemap::detail {

/// is_usable_range as selects, not branches.
inline bool usable_range(double range_m) {
  return (range_m > 0.0) & (range_m <= std::numeric_limits<double>::max());
}

/// The band a RangeRatioBandCache (fresh for the scan) hands every pair of
/// neighbouring usable beams, or nullptr when it could differ from pair to
/// pair: it is computed from the first such pair's step and kept while each
/// step stays within the tolerance of it, which all do when the steps'
/// spread (`directions` are the scan's) is within it: |s - s_first| <=
/// spread, and rounding keeps that order. nullptr too for no such pair.
inline const RangeRatioBand* uniform_step_band(const PlanarScan& scan, const BeamDirections& directions,
                                               RangeRatioBandMemo& memo) {
  if (!(directions.step_spread_rad() <= RangeRatioBandCache::angle_tolerance_rad)) return nullptr;
  const std::vector<double>& range = scan.range_m;
  for (std::size_t i = 1; i < range.size(); ++i) {
    if (usable_range(range[i - 1]) && usable_range(range[i])) {
      return &memo.band(scan.angle_rad[i] - scan.angle_rad[i - 1]);
    }
  }
  return nullptr;
}

/// The joined test of the pair (i - 1, i), as the loops form it.
inline bool joined_pair(double previous, double next, double previous_error, const RangeRatioBand& band,
                        double noise_sigmas, const RangeSigmaModel& sigma) {
  if (!usable_range(previous) || !usable_range(next)) return false;
  return ranges_on_one_surface(previous, next, noise_sigmas * sigma.sigma_m(previous, previous_error), band);
}

/// breaks[i] = 0 when beams i - 1 and i are both usable and pass
/// ranges_on_one_surface with `band` and noise_sigmas * sigma_r of beam i - 1
/// (the same doubles as the loops form), else 1; breaks[0] = 1. Four pairs
/// at a time; a group with a beam whose sigma_r comes from the URG spec
/// takes the scalar test.
inline void mark_range_breaks(const PlanarScan& scan, const RangeRatioBand& band, double noise_sigmas,
                              const RangeSigmaModel& sigma, std::vector<std::uint8_t>& breaks) {
  using Doubles2 = double __attribute__((vector_size(16)));
  using Lanes2 = std::int64_t __attribute__((vector_size(16)));
  const std::size_t n = scan.size();
  breaks.resize(n);
  if (n == 0) return;
  const double* range = scan.range_m.data();
  const double* error = scan.range_error_m.data();
  std::uint8_t* out = breaks.data();
  constexpr double max = std::numeric_limits<double>::max();
  const double lower = band.lower_factor, upper = band.upper_factor, per_error = sigma.sigma_per_range_error;
  const Doubles2 lower2 = {lower, lower}, upper2 = {upper, upper}, max2 = {max, max}, zero2 = {0.0, 0.0};
  const Doubles2 per_error2 = {per_error, per_error}, sigmas2 = {noise_sigmas, noise_sigmas};
  out[0] = 1;
  std::size_t i = 1;
  for (; !sigma.always_use_urg_spec && i + 2 <= n; i += 2) {
    Doubles2 previous, next, previous_error;
    std::memcpy(&previous, range + i - 1, sizeof previous);
    std::memcpy(&next, range + i, sizeof next);
    std::memcpy(&previous_error, error + i - 1, sizeof previous_error);
    const Lanes2 error_ok = (previous_error > zero2) & (previous_error <= max2);
    if ((error_ok[0] & error_ok[1]) == 0) {
      for (std::size_t k = i; k < i + 2; ++k) {
        out[k] = static_cast<std::uint8_t>(!joined_pair(range[k - 1], range[k], error[k - 1], band, noise_sigmas, sigma));
      }
      continue;
    }
    // sigma_m's product for a beam with its own Delta r, then the test's.
    const Doubles2 tolerance = sigmas2 * (per_error2 * previous_error);
    const Lanes2 joined = (previous > zero2) & (previous <= max2) & (next > zero2) & (next <= max2) &
                          (next > lower2 * previous - tolerance) & (next < upper2 * previous + tolerance);
    out[i] = static_cast<std::uint8_t>(joined[0] == 0);
    out[i + 1] = static_cast<std::uint8_t>(joined[1] == 0);
  }
  for (; i < n; ++i) {
    out[i] = static_cast<std::uint8_t>(!joined_pair(range[i - 1], range[i], error[i - 1], band, noise_sigmas, sigma));
  }
}

/// The end (one past) of the run of joined beams that starts at `first`.
inline std::size_t run_end(const std::vector<std::uint8_t>& breaks, std::size_t first) {
  const std::size_t from = first + 1;
  if (from >= breaks.size()) return breaks.size();
  const void* found = std::memchr(breaks.data() + from, 1, breaks.size() - from);
  return found == nullptr ? breaks.size() : static_cast<std::size_t>(static_cast<const std::uint8_t*>(found) - breaks.data());
}

}  // namespace stridemap::detail
