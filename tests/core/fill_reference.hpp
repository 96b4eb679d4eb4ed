#pragma once
// The fill-in (eq. 11) and the CAS filter as they were before they were
// made faster, kept verbatim as the reference the fast versions
// must match bit for bit (weighted_median_fill_test.cpp, cas_filter_test.cpp).
#include <algorithm>
#include <array>
#include <bit>
#include <cmath>
#include <limits>
#include <vector>

#include "stridemap/core/cas_filter.hpp"
#include "stridemap/core/grid_map.hpp"
#include "stridemap/core/weighted_median_fill.hpp"

namespace stridemap::reference {

constexpr int kMaxRadius = 7;
constexpr float kNaN = std::numeric_limits<float>::quiet_NaN();

inline int quadrant_of(int di, int dj) {
  if (di > 0 && dj >= 0) return 0;
  if (di <= 0 && dj > 0) return 1;
  if (di < 0 && dj <= 0) return 2;
  return 3;
}

inline float median_of(std::vector<float>& values) {
  const auto mid = values.begin() + static_cast<std::ptrdiff_t>(values.size() / 2);
  std::nth_element(values.begin(), mid, values.end());
  return *mid;
}

inline std::size_t reference_fill(ElevationMap& map, const FillOptions& options_) {
  struct Candidate {
    float value;
    float weight;
  };
  std::vector<float> result_;
  std::vector<std::size_t> row_offset_, column_offset_;
  const int n = map.cells_per_side();
  const int w = options_.window_radius_cells;
  const auto measured = static_cast<std::uint8_t>(CellState::measured);
  result_.assign(static_cast<std::size_t>(n) * static_cast<std::size_t>(n), kNaN);
  const float* elevation = map.elevation_data();
  const float* certainty = map.certainty_data();
  const std::uint8_t* state = map.state_data();

  // Slot = row_offset[i] + column_offset[j]: the modulo of the circular
  // buffer once per row and column instead of once per neighbour.
  row_offset_.resize(static_cast<std::size_t>(n));
  column_offset_.resize(static_cast<std::size_t>(n));
  for (int k = 0; k < n; ++k) {
    const std::size_t corner = map.slot(map.cell_at_local(k, k));
    row_offset_[static_cast<std::size_t>(k)] = corner / static_cast<std::size_t>(n) * static_cast<std::size_t>(n);
    column_offset_[static_cast<std::size_t>(k)] = corner % static_cast<std::size_t>(n);
  }
  const auto slot_of = [&](int i, int j) {
    return row_offset_[static_cast<std::size_t>(i)] + column_offset_[static_cast<std::size_t>(j)];
  };

  std::array<Candidate, (2 * kMaxRadius + 1) * (2 * kMaxRadius + 1)> candidates{};
  for (int i = 0; i < n; ++i) {
    for (int j = 0; j < n; ++j) {
      const std::size_t s = slot_of(i, j);
      if (state[s] == measured) continue;
      std::size_t count = 0;
      unsigned quadrants = 0;
      float total_weight = 0.0f;
      for (int di = -w; di <= w; ++di) {
        const int ii = i + di;
        if (ii < 0 || ii >= n) continue;
        for (int dj = -w; dj <= w; ++dj) {
          const int jj = j + dj;
          if ((di == 0 && dj == 0) || jj < 0 || jj >= n) continue;
          const std::size_t t = slot_of(ii, jj);
          if (state[t] != measured) continue;
          const bool near = std::max(std::abs(di), std::abs(dj)) == 1;
          const float weight = certainty[t] * static_cast<float>(near ? options_.near_weight : 1.0);
          candidates[count++] = {elevation[t], weight};
          total_weight += weight;
          quadrants |= 1u << quadrant_of(di, dj);
        }
      }
      if (static_cast<int>(count) < options_.min_known_neighbours ||
          std::popcount(quadrants) < options_.min_quadrants || total_weight <= 0.0f) {
        continue;
      }
      std::sort(candidates.begin(), candidates.begin() + static_cast<std::ptrdiff_t>(count),
                [](const Candidate& a, const Candidate& b) { return a.value < b.value; });
      // Weighted quantile q: the smallest value at which the cumulative
      // weight reaches q of the total.
      const auto quantile = [&](float q) {
        float cumulative = 0.0f;
        for (std::size_t k = 0; k < count; ++k) {
          cumulative += candidates[k].weight;
          if (cumulative >= q * total_weight) return candidates[k].value;
        }
        return candidates[count - 1].value;
      };
      if (options_.max_quartile_spread_m > 0.0 &&
          quantile(0.75f) - quantile(0.25f) > static_cast<float>(options_.max_quartile_spread_m)) {
        continue;
      }
      result_[s] = quantile(0.5f);
    }
  }

  std::size_t filled = 0;
  float* out_elevation = map.elevation_data();
  std::uint8_t* out_state = map.state_data();
  for (std::size_t s = 0; s < result_.size(); ++s) {
    if (out_state[s] == measured) continue;
    if (std::isnan(result_[s])) {
      map.reset_slot(s);
    } else {
      out_elevation[s] = result_[s];
      out_state[s] = static_cast<std::uint8_t>(CellState::filled);
      ++filled;
    }
  }
  return filled;
}


inline CasResult reference_cas(ElevationMap& map, const CasOptions& options_) {
  std::vector<std::size_t> to_remove_;
  std::vector<float> window_values_, window_certainties_;
  const int n = map.cells_per_side();
  const int w = options_.window_radius_cells;
  const auto measured = static_cast<std::uint8_t>(CellState::measured);
  const float* h = map.elevation_data();
  const float* c = map.certainty_data();
  const std::uint8_t* state = map.state_data();
  const auto tolerance = static_cast<float>(options_.elevation_tolerance_m);
  to_remove_.clear();

  for (int i = 0; i < n; ++i) {
    for (int j = 0; j < n; ++j) {
      const std::size_t s = map.slot(map.cell_at_local(i, j));
      if (state[s] != measured || c[s] > options_.max_removable_certainty) continue;
      // Elevation continuity: agreeing 8-neighbours, and the window's median.
      int agreeing = 0;
      window_values_.clear();
      window_certainties_.clear();
      double certainty_sum = 0.0;
      for (int di = -w; di <= w; ++di) {
        for (int dj = -w; dj <= w; ++dj) {
          const int ii = i + di, jj = j + dj;
          if (ii < 0 || jj < 0 || ii >= n || jj >= n) continue;
          const std::size_t t = map.slot(map.cell_at_local(ii, jj));
          if (state[t] != measured) continue;
          certainty_sum += c[t];
          if (di == 0 && dj == 0) continue;
          window_values_.push_back(h[t]);
          window_certainties_.push_back(c[t]);
          if (std::max(std::abs(di), std::abs(dj)) == 1 && std::abs(h[t] - h[s]) <= tolerance) ++agreeing;
        }
      }
      if (window_values_.empty()) continue;
      const bool isolated_peak =
          agreeing < options_.min_agreeing_neighbours && h[s] > median_of(window_values_) + tolerance;
      if (!isolated_peak) continue;
      const bool weak = certainty_sum < options_.min_window_certainty ||
                        c[s] < options_.certainty_ratio * median_of(window_certainties_);
      if (weak) to_remove_.push_back(s);
    }
  }
  for (std::size_t s : to_remove_) map.reset_slot(s);
  CasResult result;
  result.removed = to_remove_.size();
  result.filled = reference_fill(map, options_.fill);
  return result;
}


}  // namespace stridemap::reference
