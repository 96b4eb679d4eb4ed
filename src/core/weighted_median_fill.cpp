#include "stridemap/core/weighted_median_fill.hpp"

#include <algorithm>
#include <array>
#include <bit>
#include <cmath>
#include <limits>
#include <string>

#include "stridemap/core/error.hpp"

namespace stridemap {
namespace {

constexpr int kMaxRadius = 7;
constexpr float kNaN = std::numeric_limits<float>::quiet_NaN();

int quadrant_of(int di, int dj) {
  if (di > 0 && dj >= 0) return 0;
  if (di <= 0 && dj > 0) return 1;
  if (di < 0 && dj <= 0) return 2;
  return 3;
}

}  // namespace

WeightedMedianFill::WeightedMedianFill(const FillOptions& options) : options_(options) {
  if (options.window_radius_cells < 1 || options.window_radius_cells > kMaxRadius) {
    throw InputError("fill options: window_radius_cells must be between 1 and " + std::to_string(kMaxRadius) +
                     ", got " + std::to_string(options.window_radius_cells));
  }
  if (options.min_known_neighbours < 1) {
    throw InputError("fill options: min_known_neighbours must be at least 1, got " +
                     std::to_string(options.min_known_neighbours));
  }
  if (options.min_quadrants < 1 || options.min_quadrants > 4) {
    throw InputError("fill options: min_quadrants must be between 1 and 4, got " +
                     std::to_string(options.min_quadrants));
  }
  if (!std::isfinite(options.max_quartile_spread_m)) {
    throw InputError("fill options: max_quartile_spread_m must be finite (<= 0 disables it)");
  }
  if (!std::isfinite(options.near_weight) || options.near_weight <= 0.0) {
    throw InputError("fill options: near_weight must be a positive number, got " +
                     std::to_string(options.near_weight));
  }
}

std::size_t WeightedMedianFill::apply(ElevationMap& map) {
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

}  // namespace stridemap
