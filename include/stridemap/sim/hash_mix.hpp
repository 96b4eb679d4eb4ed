#pragma once
// A bijective 64-bit mixer (the finaliser of splitmix64): nearby inputs give
// unrelated outputs. Used to derive per-scan seeds, per-place textures and
// noise that depends on an index alone, without storing anything.
#include <cmath>
#include <cstdint>
#include <numbers>

namespace stridemap {

inline std::uint64_t mix64(std::uint64_t x) {
  x += 0x9E3779B97F4A7C15ULL;
  x = (x ^ (x >> 30)) * 0xBF58476D1CE4E5B9ULL;
  x = (x ^ (x >> 27)) * 0x94D049BB133111EBULL;
  return x ^ (x >> 31);
}

/// A standard normal number from a hash (Box-Muller on two uniforms drawn
/// from it): the same key always gives the same number.
inline double hashed_standard_normal(std::uint64_t key) {
  const std::uint64_t a = mix64(key);
  const std::uint64_t b = mix64(a);
  // Uniform in (0, 1) from the top 53 bits; never 0, so the logarithm is finite.
  const double u1 = (static_cast<double>(a >> 11) + 0.5) * 0x1.0p-53;
  const double u2 = static_cast<double>(b >> 11) * 0x1.0p-53;
  return std::sqrt(-2.0 * std::log(u1)) * std::cos(2.0 * std::numbers::pi * u2);
}

}  // namespace stridemap
