#include "stridemap/core/cas_filter.hpp"

#include <algorithm>
#include <cmath>
#include <string>

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

CasResult CasFilter::apply(ElevationMap& map) {
  const int n = map.cells_per_side();
  const int w = options_.window_radius_cells;
  const auto measured = static_cast<std::uint8_t>(CellState::measured);
  const float* h = map.elevation_data();
  const float* c = map.certainty_data();
  const std::uint8_t* state = map.state_data();
  const auto tolerance = static_cast<float>(options_.elevation_tolerance_m);
  to_remove_.clear();
  // Slot = row_[i] + column_[j]: the circular buffer's modulo once per row
  // and column, not twice per neighbour.
  const auto un = static_cast<std::size_t>(n);
  row_.resize(un);
  column_.resize(un);
  for (int k = 0; k < n; ++k) {
    const std::size_t corner = map.slot(map.cell_at_local(k, k));
    row_[static_cast<std::size_t>(k)] = corner / un * un;
    column_[static_cast<std::size_t>(k)] = corner % un;
  }

  for (int i = 0; i < n; ++i) {
    for (int j = 0; j < n; ++j) {
      const std::size_t s = row_[static_cast<std::size_t>(i)] + column_[static_cast<std::size_t>(j)];
      if (state[s] != measured || c[s] > options_.max_removable_certainty) continue;
      // Elevation continuity: a cell with enough agreeing 8-neighbours is no
      // isolated peak, whatever the window's median: the window is only
      // gathered for the others.
      int agreeing = 0;
      for (int di = -1; di <= 1; ++di) {
        for (int dj = -1; dj <= 1; ++dj) {
          const int ii = i + di, jj = j + dj;
          if ((di == 0 && dj == 0) || ii < 0 || jj < 0 || ii >= n || jj >= n) continue;
          const std::size_t t = row_[static_cast<std::size_t>(ii)] + column_[static_cast<std::size_t>(jj)];
          if (state[t] == measured && std::abs(h[t] - h[s]) <= tolerance) ++agreeing;
        }
      }
      if (agreeing >= options_.min_agreeing_neighbours) continue;
      window_values_.clear();
      window_certainties_.clear();
      double certainty_sum = 0.0;
      for (int di = -w; di <= w; ++di) {
        const int ii = i + di;
        if (ii < 0 || ii >= n) continue;
        const std::size_t row = row_[static_cast<std::size_t>(ii)];
        for (int dj = -w; dj <= w; ++dj) {
          const int jj = j + dj;
          if (jj < 0 || jj >= n) continue;
          const std::size_t t = row + column_[static_cast<std::size_t>(jj)];
          if (state[t] != measured) continue;
          certainty_sum += c[t];
          if (di == 0 && dj == 0) continue;
          window_values_.push_back(h[t]);
          window_certainties_.push_back(c[t]);
        }
      }
      if (window_values_.empty()) continue;
      const bool isolated_peak = h[s] > median_of(window_values_) + tolerance;
      if (!isolated_peak) continue;
      const bool weak = certainty_sum < options_.min_window_certainty ||
                        c[s] < options_.certainty_ratio * median_of(window_certainties_);
      if (weak) to_remove_.push_back(s);
    }
  }
  for (std::size_t s : to_remove_) map.reset_slot(s);
  CasResult result;
  result.removed = to_remove_.size();
  result.filled = fill_.apply(map);
  return result;
}

}  // namespace stridemap
