#include "stridemap/core/grid_map.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>
#include <string>

#include "stridemap/core/error.hpp"

namespace stridemap {
namespace {

constexpr float kNaN = std::numeric_limits<float>::quiet_NaN();
static_assert(kGridBytesPerCell == 4 * sizeof(float) + 2 * sizeof(std::uint8_t) + sizeof(std::uint16_t),
              "kGridBytesPerCell must count every layer of ElevationMap");

std::string number_text(double value) {
  char text[32];
  std::snprintf(text, sizeof text, "%g", value);
  return text;
}

std::string length_text(double metres) {
  char text[48];
  if (metres < 0.01) {
    std::snprintf(text, sizeof text, "%g mm", metres * 1000.0);
  } else {
    std::snprintf(text, sizeof text, "%.2f m", metres);
  }
  return text;
}

std::string limit_text() {
  const double n = kMaxGridCellsPerSide;
  return "the limit is " + std::to_string(kMaxGridCellsPerSide) + " cells per side (" +
         byte_size_text(n * n * static_cast<double>(kGridBytesPerCell)) + ")";
}

void check_cell_size(double cell_size_m) {
  if (!std::isfinite(cell_size_m) || cell_size_m < kMinCellSizeM || cell_size_m > kMaxCellSizeM) {
    throw GridSizeError("map options: cell_size_m must be between " + number_text(kMinCellSizeM) + " and " +
                        number_text(kMaxCellSizeM) + " m, got " + number_text(cell_size_m));
  }
}

}  // namespace

std::string byte_size_text(double bytes) {
  const char* units[] = {"B", "kB", "MB", "GB", "TB", "PB", "EB"};
  int unit = 0;
  while (bytes >= 1000.0 && unit < 6) {
    bytes /= 1000.0;
    ++unit;
  }
  char text[48];
  std::snprintf(text, sizeof text, unit == 0 ? "%.0f %s" : "%.1f %s", bytes, units[unit]);
  return text;
}

void validate_grid_options(const GridOptions& options) {
  const int n = options.cells_per_side;
  if (n < 1 || n > kMaxGridCellsPerSide) {
    std::string message = "map options: cells_per_side must be between 1 and " +
                          std::to_string(kMaxGridCellsPerSide) + ", got " + std::to_string(n);
    if (n > kMaxGridCellsPerSide) {
      const double cells = static_cast<double>(n) * static_cast<double>(n);
      message += ": " + std::to_string(n) + " x " + std::to_string(n) + " cells need " +
                 byte_size_text(cells * static_cast<double>(kGridBytesPerCell)) + "; " + limit_text();
    }
    throw GridSizeError(message);
  }
  check_cell_size(options.cell_size_m);
}

int cells_per_side_to_cover(double extent_m, double cell_size_m) {
  check_cell_size(cell_size_m);
  if (!std::isfinite(extent_m) || extent_m < 0.0) {
    throw GridSizeError("map options: the area to cover must be a finite size, got " + number_text(extent_m) + " m");
  }
  // In double until the count is known to fit an int.
  const double needed = std::max(1.0, std::ceil(extent_m / cell_size_m));
  if (needed > kMaxGridCellsPerSide) {
    throw GridSizeError("map options: a " + length_text(cell_size_m) + " map of this " + length_text(extent_m) +
                        " area needs " + number_text(needed) + " x " + number_text(needed) + " cells, " +
                        byte_size_text(needed * needed * static_cast<double>(kGridBytesPerCell)) + "; " +
                        limit_text() + ": use larger cells");
  }
  return static_cast<int>(needed);
}

ElevationMap::ElevationMap(const GridOptions& options)
    : n_(options.cells_per_side), cell_size_m_(options.cell_size_m), inverse_cell_size_(1.0 / options.cell_size_m) {
  validate_grid_options(options);
  const auto cells = static_cast<std::size_t>(n_) * static_cast<std::size_t>(n_);
  elevation_.assign(cells, kNaN);
  certainty_.assign(cells, 0.0f);
  state_.assign(cells, static_cast<std::uint8_t>(CellState::unknown));
  contradictions_.assign(cells, 0);
  pending_elevation_.assign(cells, kNaN);
  mean_elevation_.assign(cells, kNaN);
  mean_count_.assign(cells, 0);
  set_min_cell({-n_ / 2, -n_ / 2});
}

CellIndex ElevationMap::cell_of(double x_m, double y_m) const {
  // The same arithmetic as slot_at(), so both agree on boundary points.
  return {static_cast<std::int64_t>(std::floor(x_m * inverse_cell_size_)),
          static_cast<std::int64_t>(std::floor(y_m * inverse_cell_size_))};
}

bool ElevationMap::contains(CellIndex cell) const {
  return cell.x >= min_cell_.x && cell.x < min_cell_.x + n_ && cell.y >= min_cell_.y &&
         cell.y < min_cell_.y + n_;
}

Eigen::Vector2d ElevationMap::cell_center(CellIndex cell) const {
  return {(static_cast<double>(cell.x) + 0.5) * cell_size_m_, (static_cast<double>(cell.y) + 0.5) * cell_size_m_};
}

void ElevationMap::reset_slot(std::size_t s) {
  elevation_[s] = kNaN;
  certainty_[s] = 0.0f;
  state_[s] = static_cast<std::uint8_t>(CellState::unknown);
  contradictions_[s] = 0;
  pending_elevation_[s] = kNaN;
  mean_elevation_[s] = kNaN;
  mean_count_[s] = 0;
}

void ElevationMap::clear() {
  std::fill(elevation_.begin(), elevation_.end(), kNaN);
  std::fill(certainty_.begin(), certainty_.end(), 0.0f);
  std::fill(state_.begin(), state_.end(), static_cast<std::uint8_t>(CellState::unknown));
  std::fill(contradictions_.begin(), contradictions_.end(), std::uint8_t{0});
  std::fill(pending_elevation_.begin(), pending_elevation_.end(), kNaN);
  std::fill(mean_elevation_.begin(), mean_elevation_.end(), kNaN);
  std::fill(mean_count_.begin(), mean_count_.end(), std::uint16_t{0});
}

std::size_t ElevationMap::move_to(double x_m, double y_m) {
  if (!std::isfinite(x_m) || !std::isfinite(y_m)) return 0;
  // Coordinates this far out cannot be indexed; a caller's pose bug, not a move.
  const double limit = static_cast<double>(std::numeric_limits<std::int64_t>::max() / 4) * cell_size_m_;
  if (std::abs(x_m) > limit || std::abs(y_m) > limit) return 0;
  const CellIndex centre = cell_of(x_m, y_m);
  return move_corner_to({centre.x - n_ / 2, centre.y - n_ / 2});
}

std::size_t ElevationMap::move_corner_to(CellIndex new_min) {
  if (new_min == min_cell_) return 0;
  const std::int64_t dx = new_min.x - min_cell_.x;
  const std::int64_t dy = new_min.y - min_cell_.y;
  if (std::abs(dx) >= n_ || std::abs(dy) >= n_) {
    clear();
    set_min_cell(new_min);
    return static_cast<std::size_t>(n_) * static_cast<std::size_t>(n_);
  }
  std::size_t reset = 0;
  // Rows (constant x) that leave along x: their slots become the new rows.
  const std::int64_t first_x = dx > 0 ? min_cell_.x : new_min.x + n_;
  for (std::int64_t k = 0; k < std::abs(dx); ++k) {
    const std::int64_t row = wrap(first_x + k);
    for (int j = 0; j < n_; ++j) reset_slot(static_cast<std::size_t>(row * n_ + j));
    reset += static_cast<std::size_t>(n_);
  }
  // Columns that leave along y, skipping the rows already reset above.
  const std::int64_t first_y = dy > 0 ? min_cell_.y : new_min.y + n_;
  for (std::int64_t k = 0; k < std::abs(dy); ++k) {
    const std::int64_t col = wrap(first_y + k);
    for (std::int64_t i = new_min.x; i < new_min.x + n_; ++i) {
      const bool row_was_reset = dx > 0 ? i >= min_cell_.x + n_ : i < min_cell_.x;
      if (dx != 0 && row_was_reset) continue;
      reset_slot(static_cast<std::size_t>(wrap(i) * n_ + col));
      ++reset;
    }
  }
  set_min_cell(new_min);
  return reset;
}

void ElevationMap::export_layers(Eigen::MatrixXf* elevation, Eigen::MatrixXf* certainty,
                                 Eigen::Matrix<std::uint8_t, Eigen::Dynamic, Eigen::Dynamic>* state) const {
  if (elevation) elevation->resize(n_, n_);
  if (certainty) certainty->resize(n_, n_);
  if (state) state->resize(n_, n_);
  for (int i = 0; i < n_; ++i) {
    for (int j = 0; j < n_; ++j) {
      const std::size_t s = slot(cell_at_local(i, j));
      if (elevation) (*elevation)(i, j) = elevation_[s];
      if (certainty) (*certainty)(i, j) = certainty_[s];
      if (state) (*state)(i, j) = state_[s];
    }
  }
}

}  // namespace stridemap
