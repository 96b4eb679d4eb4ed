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
/// (the same doubles as the loops form), else 1; breaks[0] = 1.
void mark_range_breaks(const PlanarScan& scan, const RangeRatioBand& band, double noise_sigmas,
                       const RangeSigmaModel& sigma, std::vector<std::uint8_t>& breaks);

/// Whether `known` (of a scan of `beams` beams) is what mark_range_breaks
/// makes with `band`, noise_sigmas and sigma, bit for bit: the same
/// verdicts, for a scan its maker tested.
bool made_with(const RangeBreaks& known, std::size_t beams, const RangeRatioBand& band, double noise_sigmas,
               const RangeSigmaModel& sigma);

/// The end (one past) of the run of joined beams that starts at `first`.
inline std::size_t run_end(const std::vector<std::uint8_t>& breaks, std::size_t first) {
  const std::size_t from = first + 1;
  if (from >= breaks.size()) return breaks.size();
  const void* found = std::memchr(breaks.data() + from, 1, breaks.size() - from);
  return found == nullptr ? breaks.size() : static_cast<std::size_t>(static_cast<const std::uint8_t*>(found) - breaks.data());
}

}  // namespace stridemap::detail
