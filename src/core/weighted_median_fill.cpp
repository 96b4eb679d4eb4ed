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

namespace {

// Sorts by value through ranks: a candidate's place is the number of
// smaller values, counted without branches (the compiler vectorises the
// count), and it is written there. Returns false when two values are equal
// or one is NaN (two candidates share a place, or a place stays NaN):
// std::sort may order such values otherwise, and the order of the weights
// summed decides the float result, so the caller sorts those with
// std::sort as the fill always did. Distinct values have one sorted order.
template <typename Candidate>
bool sort_distinct(const Candidate* in, std::size_t count, float* values, Candidate* out) {
  for (std::size_t k = 0; k < count; ++k) values[k] = in[k].value;
  for (std::size_t k = 0; k < count; ++k) out[k].value = std::numeric_limits<float>::quiet_NaN();
  for (std::size_t k = 0; k < count; ++k) {
    const float v = values[k];
    unsigned rank = 0;
    for (std::size_t m = 0; m < count; ++m) rank += values[m] < v ? 1u : 0u;
    out[rank] = in[k];
  }
  for (std::size_t k = 0; k + 1 < count; ++k) {
    if (!(out[k].value < out[k + 1].value)) return false;
  }
  return count == 0 || !std::isnan(out[count - 1].value);
}

}  // namespace

std::size_t WeightedMedianFill::apply(ElevationMap& map) {
  const int n = map.cells_per_side();
  const int w = options_.window_radius_cells;
  const auto measured = static_cast<std::uint8_t>(CellState::measured);
  const auto cells = static_cast<std::size_t>(n) * static_cast<std::size_t>(n);
  result_.assign(cells, kNaN);
  const float* elevation = map.elevation_data();
  const float* certainty = map.certainty_data();
  const std::uint8_t* state = map.state_data();

  // The window unrolled from the circular buffer into local order with a
  // margin of w unknown cells: a neighbour is a fixed offset, no modulo and
  // no bounds test per neighbour. Unknown cells keep value and weight 0.
  const int p = n + 2 * w;
  const auto padded_cells = static_cast<std::size_t>(p) * static_cast<std::size_t>(p);
  known_.assign(padded_cells, 0);
  value_.assign(padded_cells, 0.0f);
  weight_.assign(padded_cells, 0.0f);
  slot_.resize(cells);
  for (int i = 0; i < n; ++i) {
    const std::size_t row = map.slot(map.cell_at_local(i, 0)) / static_cast<std::size_t>(n) * static_cast<std::size_t>(n);
    const auto first_column = static_cast<int>(map.slot(map.cell_at_local(0, 0)) % static_cast<std::size_t>(n));
    for (int j = 0; j < n; ++j) {
      int column = first_column + j;
      if (column >= n) column -= n;
      const std::size_t s = row + static_cast<std::size_t>(column);
      slot_[static_cast<std::size_t>(i) * static_cast<std::size_t>(n) + static_cast<std::size_t>(j)] = s;
      if (state[s] != measured) continue;
      const std::size_t q = static_cast<std::size_t>(i + w) * static_cast<std::size_t>(p) + static_cast<std::size_t>(j + w);
      known_[q] = 1;
      value_[q] = elevation[s];
      weight_[q] = certainty[s];
    }
  }
  // The neighbours in the order the fill has always visited them (rows
  // di = -w..w, in each dj = -w..w): the sums of the weights keep their order.
  struct Neighbour {
    std::ptrdiff_t offset;
    bool near;
    unsigned quadrant_bit;
  };
  std::array<Neighbour, (2 * kMaxRadius + 1) * (2 * kMaxRadius + 1)> neighbours{};
  std::size_t neighbour_count = 0;
  for (int di = -w; di <= w; ++di) {
    for (int dj = -w; dj <= w; ++dj) {
      if (di == 0 && dj == 0) continue;
      neighbours[neighbour_count++] = {static_cast<std::ptrdiff_t>(di) * p + dj,
                                       std::max(std::abs(di), std::abs(dj)) == 1, 1u << quadrant_of(di, dj)};
    }
  }
  const auto near_factor = static_cast<float>(options_.near_weight);
  const float spread = static_cast<float>(options_.max_quartile_spread_m);
  const bool test_spread = options_.max_quartile_spread_m > 0.0;

  std::array<Candidate, (2 * kMaxRadius + 1) * (2 * kMaxRadius + 1)> candidates{}, gathered{};
  std::array<float, (2 * kMaxRadius + 1) * (2 * kMaxRadius + 1)> scratch{};
  for (int i = 0; i < n; ++i) {
    for (int j = 0; j < n; ++j) {
      const std::size_t centre = static_cast<std::size_t>(i + w) * static_cast<std::size_t>(p) + static_cast<std::size_t>(j + w);
      if (known_[centre] != 0) continue;
      std::size_t count = 0;
      unsigned quadrants = 0;
      float total_weight = 0.0f;
      // Without branches on which neighbours are known (a third are not, at
      // random): each is written at the end and counted only when known;
      // the total adds the known weights in the same order as ever.
      for (std::size_t k = 0; k < neighbour_count; ++k) {
        const Neighbour& nb = neighbours[k];
        const std::size_t t = centre + static_cast<std::size_t>(nb.offset);
        const bool known = known_[t] != 0;
        // certainty * 1.0f is the certainty itself: the far weight as before.
        const float weight = weight_[t] * (nb.near ? near_factor : 1.0f);
        gathered[count] = {value_[t], weight};
        count += known ? 1 : 0;
        total_weight = known ? total_weight + weight : total_weight;
        quadrants |= known ? nb.quadrant_bit : 0u;
      }
      if (static_cast<int>(count) < options_.min_known_neighbours ||
          std::popcount(quadrants) < options_.min_quadrants || total_weight <= 0.0f) {
        continue;
      }
      if (!sort_distinct(gathered.data(), count, scratch.data(), candidates.data())) {
        std::copy(gathered.begin(), gathered.begin() + static_cast<std::ptrdiff_t>(count), candidates.begin());
        std::sort(candidates.begin(), candidates.begin() + static_cast<std::ptrdiff_t>(count),
                  [](const Candidate& a, const Candidate& b) { return a.value < b.value; });
      }
      // Weighted quantiles q: the smallest value at which the cumulative
      // weight reaches q of the total; the three in one pass over the same sums.
      const float at_quarter = 0.25f * total_weight, at_half = 0.5f * total_weight,
                  at_three_quarters = 0.75f * total_weight;
      const float last = candidates[count - 1].value;
      float quarter = last, half = last, three_quarters = last;
      bool have_quarter = false, have_half = false;
      float cumulative = 0.0f;
      for (std::size_t k = 0; k < count; ++k) {
        cumulative += candidates[k].weight;
        if (!have_quarter && cumulative >= at_quarter) {
          quarter = candidates[k].value;
          have_quarter = true;
        }
        if (!have_half && cumulative >= at_half) {
          half = candidates[k].value;
          have_half = true;
        }
        if (cumulative >= at_three_quarters) {
          three_quarters = candidates[k].value;
          break;
        }
      }
      if (test_spread && three_quarters - quarter > spread) continue;
      result_[slot_[static_cast<std::size_t>(i) * static_cast<std::size_t>(n) + static_cast<std::size_t>(j)]] = half;
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
