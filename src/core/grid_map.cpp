#include "stridemap/core/grid_map.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>
#include <string>

#include "stridemap/core/cell_center.hpp"
#include "stridemap/core/error.hpp"

namespace stridemap {
namespace {


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

// The slots of `count` consecutive rows (or columns) of a circular window
// of n whose first has slot `first` (0 <= first < n): one run, or two where
// they wrap. No modulo: a move costs tens of nanoseconds, and a 64-bit
// division is a good part of that.
struct Runs {
  std::size_t begin[2] = {0, 0}, end[2] = {0, 0};
  int count = 0;
};
Runs runs_from(int first, int count, int n) {
  Runs runs;
  if (count <= 0) return runs;
  runs.begin[0] = static_cast<std::size_t>(first);
  runs.end[0] = static_cast<std::size_t>(std::min(first + count, n));
  runs.count = 1;
  if (first + count > n) {
    runs.end[1] = static_cast<std::size_t>(first + count - n);
    runs.count = 2;
  }
  return runs;
}

// Slot of local position `offset` (0 <= offset < n) from slot `first`.
int wrapped(int first, int offset, int n) {
  const int s = first + offset;
  return s >= n ? s - n : s;
}

// Columns `columns` of the rows `rows` of one layer back to `value`. A
// one-cell move is one element per row, N elements apart: a plain strided
// store (the general loop below costs three times its instructions). Wider
// moves fill each row's runs while the row is in cache.
template <typename T>
void reset_columns(std::vector<T>& values, T value, std::size_t n, const Runs& rows, const Runs& columns) {
  T* data = values.data();
  if (columns.count == 1 && columns.end[0] - columns.begin[0] == 1) {
    for (int r = 0; r < rows.count; ++r) {
      std::size_t at = rows.begin[r] * n + columns.begin[0];
      for (std::size_t row = rows.begin[r]; row < rows.end[r]; ++row, at += n) data[at] = value;
    }
    return;
  }
  for (int r = 0; r < rows.count; ++r) {
    for (std::size_t row = rows.begin[r]; row < rows.end[r]; ++row) {
      T* line = data + row * n;
      for (int c = 0; c < columns.count; ++c) std::fill(line + columns.begin[c], line + columns.end[c], value);
    }
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
  layers_.reserve(builtin_layers().size() + options.extra_layers.size());
  for (const LayerSpec& spec : builtin_layers()) add_layer(spec);
  for (const LayerSpec& spec : options.extra_layers) add_layer(spec);
  set_min_cell({-n_ / 2, -n_ / 2});
}

std::size_t ElevationMap::add_layer(const LayerSpec& spec) {
  validate_layer_spec(spec);
  if (find_layer(spec.name)) throw InputError("map layer '" + spec.name + "': the map already has a layer of that name");
  Layer& layer = layers_.emplace_back();
  layer.spec = spec;
  // Only the layer's own type: a float layer's NaN has no integer value, and
  // converting it would be undefined (validate_layer_spec checked the range
  // for the integer types).
  switch (spec.type) {
    case LayerType::f32: layer.reset_f32 = static_cast<float>(spec.reset_value); break;
    case LayerType::u16: layer.reset_u16 = static_cast<std::uint16_t>(spec.reset_value); break;
    case LayerType::u8: layer.reset_u8 = static_cast<std::uint8_t>(spec.reset_value); break;
  }
  fill_with_reset(layer);
  return layers_.size() - 1;
}

void ElevationMap::fill_with_reset(Layer& layer) {
  const auto cells = static_cast<std::size_t>(n_) * static_cast<std::size_t>(n_);
  switch (layer.spec.type) {
    case LayerType::f32: layer.f32.assign(cells, layer.reset_f32); break;
    case LayerType::u16: layer.u16.assign(cells, layer.reset_u16); break;
    case LayerType::u8: layer.u8.assign(cells, layer.reset_u8); break;
  }
}

std::optional<std::size_t> ElevationMap::find_layer(std::string_view name) const {
  for (std::size_t k = 0; k < layers_.size(); ++k) {
    if (layers_[k].spec.name == name) return k;
  }
  return std::nullopt;
}

void declare_layer_once(GridOptions& grid, const LayerSpec& spec) {
  for (const LayerSpec& layer : grid.extra_layers) {
    if (layer.name == spec.name) return;
  }
  grid.extra_layers.push_back(spec);
}

std::string ElevationMap::layer_names() const {
  std::string names;
  for (const Layer& layer : layers_) names += (names.empty() ? "" : ", ") + layer.spec.name;
  return names;
}

std::size_t ElevationMap::checked_layer(std::string_view name, LayerType type) const {
  const auto index = find_layer(name);
  if (!index) {
    throw InputError("map layer '" + std::string(name) + "' does not exist; the map has " + layer_names());
  }
  if (layers_[*index].spec.type != type) {
    throw InputError("map layer '" + std::string(name) + "' holds " + layer_type_name(layers_[*index].spec.type) +
                     ", not " + layer_type_name(type));
  }
  return *index;
}

void* ElevationMap::layer_bytes(std::size_t index) {
  Layer& layer = layers_[index];
  switch (layer.spec.type) {
    case LayerType::f32: return layer.f32.data();
    case LayerType::u16: return layer.u16.data();
    case LayerType::u8: break;
  }
  return layer.u8.data();
}

const void* ElevationMap::layer_bytes(std::size_t index) const {
  return const_cast<ElevationMap*>(this)->layer_bytes(index);
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

Eigen::Vector2d ElevationMap::cell_center(CellIndex cell) const { return stridemap::cell_center(cell, cell_size_m_); }

void ElevationMap::clear() {
  for (Layer& layer : layers_) fill_with_reset(layer);
}

void ElevationMap::reset_rows(std::size_t begin_row, std::size_t end_row) {
  // Layer by layer: one fill each rather than a type switch per slot.
  const std::size_t begin = begin_row * static_cast<std::size_t>(n_), end = end_row * static_cast<std::size_t>(n_);
  for (Layer& layer : layers_) {
    switch (layer.spec.type) {
      case LayerType::f32: std::fill(layer.f32.begin() + begin, layer.f32.begin() + end, layer.reset_f32); break;
      case LayerType::u16: std::fill(layer.u16.begin() + begin, layer.u16.begin() + end, layer.reset_u16); break;
      case LayerType::u8: std::fill(layer.u8.begin() + begin, layer.u8.begin() + end, layer.reset_u8); break;
    }
  }
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
  // |dx|, |dy| < n: the new corner's slots follow from the old ones by one
  // addition and one correction.
  const int sx = static_cast<int>(dx), sy = static_cast<int>(dy);
  const int new_slot_x = wrapped(min_slot_x_, sx < 0 ? sx + n_ : sx, n_);
  const int new_slot_y = wrapped(min_slot_y_, sy < 0 ? sy + n_ : sy, n_);
  std::size_t reset = 0;
  const auto n = static_cast<std::size_t>(n_);
  // Rows (constant x) that leave along x: their slots become the new rows,
  // one fill per layer for each run of them.
  const Runs rows = runs_from(sx > 0 ? min_slot_x_ : new_slot_x, std::abs(sx), n_);
  for (int r = 0; r < rows.count; ++r) {
    reset_rows(rows.begin[r], rows.end[r]);
    reset += (rows.end[r] - rows.begin[r]) * n;
  }
  // Columns that leave along y, in the rows both windows cover (the others
  // were reset above).
  if (sy != 0) {
    const Runs columns = runs_from(sy > 0 ? min_slot_y_ : new_slot_y, std::abs(sy), n_);
    const Runs kept = runs_from(sx > 0 ? new_slot_x : min_slot_x_, n_ - std::abs(sx), n_);
    for (Layer& layer : layers_) {
      switch (layer.spec.type) {
        case LayerType::f32: reset_columns(layer.f32, layer.reset_f32, n, kept, columns); break;
        case LayerType::u16: reset_columns(layer.u16, layer.reset_u16, n, kept, columns); break;
        case LayerType::u8: reset_columns(layer.u8, layer.reset_u8, n, kept, columns); break;
      }
    }
    reset += static_cast<std::size_t>(n_ - std::abs(sx)) * static_cast<std::size_t>(std::abs(sy));
  }
  min_cell_ = new_min;
  min_slot_x_ = new_slot_x;
  min_slot_y_ = new_slot_y;
  return reset;
}

}  // namespace stridemap
