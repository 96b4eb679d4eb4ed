#pragma once
// The visibility clean-up's screen (core/visibility_clearing.hpp): a fan's
// traced beams, four at a time in AVX2 lanes, through the tests
// VisibilityClearing::trace_valid() makes before a walk, so that only the
// beams that need a walk are taken one by one. Private to the core library.
#include <cstddef>
#include <cstdint>

namespace stridemap::visibility {

/// Index mod n in 0..n-1, as the grid's slots take it.
inline std::size_t wrap_index(std::int64_t x, std::int64_t n) {
  const std::int64_t m = x % n;
  return static_cast<std::size_t>(m < 0 ? m + n : m);
}

/// trace_fan() takes a fan's traced beams this many at a time: screened
/// together, then walked in their order.
inline constexpr std::size_t kScreenBeams = 128;

// The traced beams of one batch as trace_valid() takes them, padded to a
// whole number of vectors.
struct ScreenBatch {
  alignas(32) double dx_m[kScreenBeams];
  alignas(32) double dy_m[kScreenBeams];
  alignas(32) double dz_m[kScreenBeams];
  alignas(32) double range2[kScreenBeams];
  alignas(32) double range_error_m[kScreenBeams];
  alignas(32) double height_error_m[kScreenBeams];
  // What the screen found, per vector of 4 (bit b: beam b): settled, its
  // walk not needed; left, for trace_valid() to take from the start.
  std::uint8_t settled[kScreenBeams / 4];
  std::uint8_t left[kScreenBeams / 4];
  // For the rest, the walk's arguments as trace_valid() would pass them
  // (t_last: where a rising beam's walk ends, before the stop).
  alignas(32) double dx_cells[kScreenBeams];
  alignas(32) double dy_cells[kScreenBeams];
  alignas(32) double inverse_dx[kScreenBeams];  // 1 / dx_cells, 1 / dy_cells
  alignas(32) double inverse_dy[kScreenBeams];
  alignas(32) double margin_m[kScreenBeams];
  alignas(32) double t_stop[kScreenBeams];
  alignas(32) double t_skip[kScreenBeams];
  alignas(32) double t_last[kScreenBeams];
  // Where each walk of a vector with bit b of `started` set begins, found
  // here four at a time: its cell, window-local, and the cell's slot row
  // (times n) and column (whole numbers as doubles), each axis's next
  // boundary and crossing, and the walk's first t_in, what the walk's own
  // start (Axis, skip_to() and the slots) would find. A lane whose skip
  // would need the search's correction steps, or whose cell lies too far
  // outside the window for one wrap of the slots, is left to the walk.
  std::uint8_t started[kScreenBeams / 4];
  alignas(32) double start_i[kScreenBeams];
  alignas(32) double start_j[kScreenBeams];
  alignas(32) double start_row[kScreenBeams];
  alignas(32) double start_column[kScreenBeams];
  alignas(32) double boundary_x[kScreenBeams];
  alignas(32) double boundary_y[kScreenBeams];
  alignas(32) double next_x[kScreenBeams];
  alignas(32) double next_y[kScreenBeams];
  alignas(32) double t_in[kScreenBeams];
};

// What the screen needs of the scan and the fan's origin.
struct ScreenScan {
  double z0 = 0.0, ox = 0.0, oy = 0.0, inverse_cell = 1.0;
  double uncertainty_factor = 0.0, relief_m = 0.0, one_abs_z0 = 0.0, top = 0.0;
  double corner_x = 0.0, corner_y = 0.0, last_index = 0.0;
  double origin_cell_x = 0.0, origin_cell_y = 0.0;  // floor(ox), floor(oy)
  double slot_x0 = 0.0, slot_y0 = 0.0;              // the corner's slot row and column
  int n = 0;
  const float* row_max = nullptr;
  const float* column_max = nullptr;
};

/// Whether this build and CPU run the screen (an AVX2 copy, chosen at run
/// time); without it a fan is traced beam by beam.
bool screen_available();

/// Settles, four beams a vector, every beam of the batch that trace_valid()
/// would end before its walk: the same tests on the same values, operation
/// for operation, so a beam is settled here exactly when it would end there
/// (the tables do not change during the scan), and the rest get the very
/// walk arguments it would pass. Beams whose stop lies beyond the hit are
/// left to trace_valid(): their places along the beam may lie beyond where
/// the index arithmetic here is exact. Only where screen_available().
void screen(const ScreenScan& scan, ScreenBatch& batch, std::size_t count);

}  // namespace stridemap::visibility
