#pragma once
// WeightedMedianFill's sort-free path for windows of radius 1 and 2 when
// every sum of weights is exact (internal to src/core; see
// weighted_median_fill.cpp for when that holds).
#include <cstddef>
#include <cstdint>

namespace stridemap::fill_detail {

// Bits of WindowInput::row_bits: the known cells among the 2w + 1 cells of
// a row centred on a padded cell (bit w + dj), and the same for known cells
// whose value is a zero or NaN, shifted up by kSpecialShift.
inline constexpr unsigned kSpecialShift = 8;

struct WindowInput {
  // The padded copy (pitch cells a row, `margin` unknown cells around the
  // n x n map): values (+inf where unknown), weights (0 where unknown) and
  // row bits. The arrays have 8 cells of room past the end.
  const float* value;
  const float* weight;
  const std::uint16_t* row_bits;
  std::size_t pitch;
  std::size_t margin;
  std::size_t n;
  float near_factor;
  int min_known;
  int min_quadrants;
  float spread;  // the quartile spread limit [m]
  bool test_spread;
  const std::size_t* slot;  // slot of local cell i * n + j
  float* result;            // per slot: the filled value where one is found
  std::uint32_t* columns;   // scratch, n entries
  // Out: the windows that passed the admission tests but hold a zero or a
  // NaN value (the sorted walk decides those), local cell i * n + j, and
  // their total weight.
  std::uint32_t* walk_cells;
  float* walk_totals;
};

/// Fills the unknown cells whose window (radius 1 or 2) passes the tests;
/// returns how many windows were left to the sorted walk (walk_cells).
std::size_t fill_exact_windows_radius1(const WindowInput& in);
std::size_t fill_exact_windows_radius2(const WindowInput& in);

}  // namespace stridemap::fill_detail
