#pragma once
// WeightedMedianFill's sort-free path for windows of radius 1 and 2 when
// every sum of weights is exact (internal to src/core; see
// weighted_median_fill.cpp for when that holds).
#include <array>
#include <bit>
#include <cstddef>
#include <cstdint>
#include <cstring>

namespace stridemap::fill_detail {

// Bits of WindowInput::row_bits: the known cells among the 2w + 1 cells of
// a row centred on a padded cell (bit w + dj), and the same for known cells
// whose value is a zero or NaN, shifted up by kSpecialShift.
inline constexpr unsigned kSpecialShift = 8;

// For each set of 8 flags (a bit each), the indices of the set ones in
// order (32-bit entries: one vector load, no widening) and how many there are (no popcnt instruction in
// x86-64's baseline: std::popcount is a call there).
struct SetFlags {
  alignas(32) std::array<std::array<std::uint32_t, 8>, 256> indices{};
  std::array<std::uint8_t, 256> count{};
};
inline constexpr SetFlags kSetFlags = [] {
  SetFlags table;
  for (unsigned flags = 0; flags < 256; ++flags) {
    unsigned at = 0;
    for (unsigned k = 0; k < 8; ++k) {
      if (flags & (1u << k)) table.indices[flags][at++] = k;
    }
    table.count[flags] = static_cast<std::uint8_t>(at);
  }
  return table;
}();

/// Appends first + k to list[count..] for each set bit k of `flags` (8
/// bits), in order; returns the new count. Always writes 8 entries (the list
/// has room for 8 past its last one): a few vector operations for 8 cells,
/// no branch per cell (which cells are set is as random as the map).
inline std::size_t append_set_flags(unsigned flags, std::uint32_t first, std::uint32_t* list, std::size_t count) {
  using Entries8 = std::uint32_t __attribute__((vector_size(32)));
  Entries8 entries;
  std::memcpy(&entries, kSetFlags.indices[flags & 0xffu].data(), sizeof entries);
  entries += first;
  std::memcpy(list + count, &entries, sizeof entries);
  return count + kSetFlags.count[flags & 0xffu];
}

/// Bit k set where byte k of at[0..8) is nonzero, for bytes that are 0 or 1
/// (one multiplication gathers them: byte k lands on bit 56 + k).
inline unsigned flags_of_bytes(const std::uint8_t* at) {
  std::uint64_t bytes;
  std::memcpy(&bytes, at, sizeof bytes);
  if constexpr (std::endian::native == std::endian::big) bytes = __builtin_bswap64(bytes);
  return static_cast<unsigned>((bytes * 0x0102040810204080ull) >> 56);
}

struct WindowInput {
  // The padded copy (pitch cells a row, `margin` unknown cells around the
  // n x n map): values (+inf where unknown), weights (0 where unknown) and
  // row bits. The arrays have 8 cells of room past the end.
  const float* value;
  const float* weight;
  const std::uint16_t* row_bits;
  const std::uint8_t* known;  // 1 where known, else 0; 8 cells of room past the end
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
  std::uint32_t* columns;   // scratch, n + 8 entries
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
