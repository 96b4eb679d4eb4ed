#pragma once
// What the foothold parts (core/foothold.hpp) agree on about one cell: when
// it counts as known, and when a value counts as unchanged. Private to the
// core library.
#include <algorithm>
#include <bit>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <limits>

#include "stridemap/core/grid_map.hpp"

namespace stridemap::foothold {

inline constexpr float kNaN = std::numeric_limits<float>::quiet_NaN();

/// Known: a state other than unknown and a finite elevation.
inline bool known(const float* elevation, const std::uint8_t* state, std::size_t s) {
  return state[s] != static_cast<std::uint8_t>(CellState::unknown) && std::isfinite(elevation[s]);
}

/// The elevation where known, NaN where not.
inline float known_elevation(const float* elevation, const std::uint8_t* state, std::size_t s) {
  return known(elevation, state, s) ? elevation[s] : kNaN;
}

// Bits, not ==, so that NaN equals NaN and a changed sign of zero counts:
// the incremental values must match a full recompute bit for bit.
inline bool same_bits(float a, float b) { return std::bit_cast<std::uint32_t>(a) == std::bit_cast<std::uint32_t>(b); }
inline bool same_bits(double a, double b) { return std::bit_cast<std::uint64_t>(a) == std::bit_cast<std::uint64_t>(b); }

/// The score's certainty factor; a change of it (not of the certainty)
/// is what redoes a score.
inline double certainty_factor(float certainty, double full_certainty) {
  return std::clamp(static_cast<double>(certainty) / full_certainty, 0.0, 1.0);
}

}  // namespace stridemap::foothold

// Where the CPU has AVX2, the foothold loops that vectorise run a copy
// built for it (wider lanes, integer min), chosen when the library loads.
// No FMA is enabled: every operation rounds as in the baseline copy.
#if defined(__x86_64__) && defined(__GNUC__) && !defined(__clang__) && defined(__linux__) && \
    !defined(STRIDEMAP_NO_AVX2_COPIES)
#define STRIDEMAP_FOOTHOLD_CLONES __attribute__((target_clones("avx2", "default")))
#else
#define STRIDEMAP_FOOTHOLD_CLONES
#endif

namespace stridemap::foothold {

}  // namespace stridemap::foothold
