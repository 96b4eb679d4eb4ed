#include "stridemap/core/cas_filter.hpp"

#include <algorithm>
#include <bit>
#include <cmath>
#include <cstring>
#include <limits>
#include <string>

#include "fill_exact_windows.hpp"
#include "stridemap/core/error.hpp"

namespace stridemap {
namespace {

void require(bool ok, const std::string& what) {
  if (!ok) throw InputError("CAS options: " + what);
}

float median_of(std::vector<float>& values) {
  const auto mid = values.begin() + static_cast<std::ptrdiff_t>(values.size() / 2);
  std::nth_element(values.begin(), mid, values.end());
  return *mid;
}

// Whether the median of `values` (the element at position size / 2 of the
// sorted order, as median_of picks it) satisfies `holds`, for a test that
// holds on a lower set of the sorted values (holds(v) and v' <= v give
// holds(v')): then it holds for the median exactly when it holds for at
// least size / 2 + 1 values. A count without a sort or a branch per value;
// only for values that compare in a total order (no NaN).
template <typename Test>
bool holds_below_median(const std::vector<float>& values, Test holds) {
  std::size_t count = 0;
  for (float v : values) count += holds(v) ? 1 : 0;
  return count >= values.size() / 2 + 1;
}

// The 8-neighbour test on four-lane vectors (GCC's vector extension: any
// target with 128-bit vectors).
using Heights4 = float __attribute__((vector_size(16)));
using Lanes4 = std::int32_t __attribute__((vector_size(16)));

Heights4 load4(const float* at) {
  Heights4 v;
  std::memcpy(&v, at, sizeof v);
  return v;
}

// Lane k from b where take_b[k] is -1, else from a.
Heights4 blend4(Heights4 a, Heights4 b, Lanes4 take_b) {
  return reinterpret_cast<Heights4>((reinterpret_cast<Lanes4>(a) & ~take_b) | (reinterpret_cast<Lanes4>(b) & take_b));
}

Heights4 abs4(Heights4 x) {
  const Lanes4 magnitude = {0x7fffffff, 0x7fffffff, 0x7fffffff, 0x7fffffff};
  return reinterpret_cast<Heights4>(reinterpret_cast<Lanes4>(x) & magnitude);
}

}  // namespace

CasFilter::CasFilter(const CasOptions& o) : options_(o), fill_(o.fill) {
  require(o.window_radius_cells >= 1 && o.window_radius_cells <= 7,
          "window_radius_cells must be between 1 and 7, got " + std::to_string(o.window_radius_cells));
  require(std::isfinite(o.elevation_tolerance_m) && o.elevation_tolerance_m > 0.0,
          "elevation_tolerance_m must be a positive number");
  require(o.min_agreeing_neighbours >= 0 && o.min_agreeing_neighbours <= 8,
          "min_agreeing_neighbours must be between 0 and 8, got " + std::to_string(o.min_agreeing_neighbours));
  require(std::isfinite(o.certainty_ratio) && o.certainty_ratio >= 0.0, "certainty_ratio must be a number >= 0");
  require(std::isfinite(o.min_window_certainty) && o.min_window_certainty >= 0.0,
          "min_window_certainty must be a number >= 0");
  require(std::isfinite(o.max_removable_certainty) && o.max_removable_certainty >= 0.0,
          "max_removable_certainty must be a number >= 0");
}

bool CasFilter::is_weak_isolated_peak(std::size_t q, float hs) {
  const int w = options_.window_radius_cells;
  const auto tolerance = static_cast<float>(options_.elevation_tolerance_m);
  const std::uint8_t* known = fill_.known_.data();
  const float* height = fill_.value_.data();
  const float* certainty = fill_.weight_.data();
  const auto sp = static_cast<std::ptrdiff_t>(fill_.pitch_);
  const auto window_cells = static_cast<std::size_t>((2 * w + 1) * (2 * w + 1));
  // The window's measured cells in the reference's order, without a
  // branch per cell (which are measured is random): each is written at
  // the end and kept when measured and not the centre. The others add
  // +0.0 to the double sum, which leaves it as it was (it starts at +0.0).
  window_values_.resize(window_cells);
  window_certainties_.resize(window_cells);
  float* values = window_values_.data();
  float* certainties = window_certainties_.data();
  double certainty_sum = 0.0;
  std::uint32_t unordered = 0;  // a NaN height or a certainty not finite
  std::size_t kept = 0;
  for (std::ptrdiff_t di = -w; di <= w; ++di) {
    const std::size_t row = q + static_cast<std::size_t>(di * sp);
    for (std::ptrdiff_t dj = -w; dj <= w; ++dj) {
      const std::size_t t = row + static_cast<std::size_t>(dj);
      const std::uint32_t is_known = known[t];
      const std::uint32_t mask = 0u - is_known;
      const float ht = height[t], ct = certainty[t];
      certainty_sum += static_cast<double>(std::bit_cast<float>(std::bit_cast<std::uint32_t>(ct) & mask));
      values[kept] = ht;
      certainties[kept] = ct;
      unordered |= is_known & (static_cast<std::uint32_t>(std::isnan(ht)) | static_cast<std::uint32_t>(!std::isfinite(ct)));
      kept += is_known & static_cast<std::uint32_t>(t != q);
    }
  }
  const bool ordered = unordered == 0;
  window_values_.resize(kept);
  window_certainties_.resize(kept);
  if (kept == 0) return false;
  // The median's tests as counts where the values are totally ordered
  // (fl(v + tolerance) and ratio * v do not decrease with v); the sort
  // where a NaN would make the median depend on nth_element's order.
  const double ratio = options_.certainty_ratio;
  const double cs = certainty[q];
  const bool isolated_peak =
      ordered ? holds_below_median(window_values_, [&](float v) { return hs > v + tolerance; })
              : hs > median_of(window_values_) + tolerance;
  if (!isolated_peak) return false;
  bool weak = certainty_sum < options_.min_window_certainty;
  if (!weak) {
    if (ordered) {
      // cs < ratio * v holds on an upper set: its negation on a lower one.
      weak = !holds_below_median(window_certainties_, [&](float v) { return !(cs < ratio * v); });
    } else {
      weak = cs < ratio * median_of(window_certainties_);
    }
  }
  return weak;
}

CasResult CasFilter::apply(ElevationMap& map) {
  const int n = map.cells_per_side();
  const int w = options_.window_radius_cells;
  const auto tolerance = static_cast<float>(options_.elevation_tolerance_m);
  to_remove_.clear();
  // The map in local order with a margin of unknown cells, shared with the
  // fill that follows (one copy for both): a neighbour is a fixed offset,
  // no modulo and no bounds test (cells outside the map are unknown, as the
  // reference's bounds tests treat them). Heights are +inf and certainties
  // 0 where unknown; every use below is masked by known.
  const auto un = static_cast<std::size_t>(n);
  const int margin = std::max(w, options_.fill.window_radius_cells);
  fill_.prepare(map, margin);
  const std::uint8_t* known = fill_.known_.data();
  const float* height = fill_.value_.data();
  const float* certainty = fill_.weight_.data();
  const std::size_t p = fill_.pitch_;
  const auto um = static_cast<std::size_t>(margin);
  // The largest float not above the limit: for a float certainty c,
  // c > limit exactly when c > that float (no float lies between them), a
  // comparison without a conversion to double per cell.
  auto max_removable = static_cast<float>(options_.max_removable_certainty);
  if (static_cast<double>(max_removable) > options_.max_removable_certainty) {
    max_removable = std::nextafter(max_removable, -std::numeric_limits<float>::infinity());
  }
  candidates_.resize(un + 8);  // room for the write past the last kept cell
  const Heights4 limit4 = {max_removable, max_removable, max_removable, max_removable};
  const Lanes4 low_bits = {1, 2, 4, 8}, high_bits = {16, 32, 64, 128};
  for (std::size_t i = 0; i < un; ++i) {
    // The row's removable cells listed first, 8 cells a step without a
    // branch per cell (which cells are measured and weak is as random as
    // the map). The padded copy has room for the reads past the row.
    std::size_t candidate_count = 0;
    const std::size_t row_start = (i + um) * p + um;
    for (std::size_t j = 0; j < un; j += 8) {
      const float* c = certainty + row_start + j;
      const Lanes4 not_above = (~(load4(c) > limit4) & low_bits) | (~(load4(c + 4) > limit4) & high_bits);
      const auto weak = static_cast<unsigned>(not_above[0] | not_above[1] | not_above[2] | not_above[3]);
      const unsigned in_row = un - j >= 8 ? 0xffu : (1u << (un - j)) - 1;  // columns past n are not listed
      candidate_count =
          fill_detail::append_set_flags(weak & fill_detail::flags_of_bytes(known + row_start + j) & in_row,
                                        static_cast<std::uint32_t>(j), candidates_.data(), candidate_count);
    }
    for (std::size_t k = 0; k < candidate_count; ++k) {
      const std::size_t j = candidates_[k];
      const std::size_t q = (i + um) * p + j + um;
      const float hs = height[q];
      // Elevation continuity: a cell with enough agreeing 8-neighbours is no
      // isolated peak, whatever the window's median: the window is only
      // gathered for the others.
      // Two four-lane vectors of the ring, blended from row loads; unknown
      // cells hold +inf, which never agrees (nor does a NaN on either side).
      const float* at = height + q;
      const Heights4 upper = blend4(load4(at - p - 1), load4(at - 4), Lanes4{0, 0, 0, -1});
      const Heights4 lower = blend4(load4(at + 1), load4(at + p - 2), Lanes4{0, -1, -1, -1});
      const Heights4 centre = {hs, hs, hs, hs}, tolerance4 = {tolerance, tolerance, tolerance, tolerance};
      const Lanes4 agree = reinterpret_cast<Lanes4>(abs4(upper - centre) <= tolerance4) +
                           reinterpret_cast<Lanes4>(abs4(lower - centre) <= tolerance4);  // -1 per agreeing cell
      const int agreeing = -(agree[0] + agree[1] + agree[2] + agree[3]);
      if (agreeing >= options_.min_agreeing_neighbours) continue;
      if (is_weak_isolated_peak(q, hs)) to_remove_.push_back(i * un + j);
    }
  }
  for (std::size_t local : to_remove_) {
    map.reset_slot(fill_.slot_[local]);
    fill_.forget(local, n);
  }
  CasResult result;
  result.removed = to_remove_.size();
  result.filled = fill_.fill_prepared(map);
  return result;
}

}  // namespace stridemap
