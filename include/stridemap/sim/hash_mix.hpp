#pragma once
// A bijective 64-bit mixer (the finaliser of splitmix64): nearby inputs give
// unrelated outputs. Used to derive per-scan seeds and per-place textures
// without storing anything.
#include <cstdint>

namespace stridemap {

inline std::uint64_t mix64(std::uint64_t x) {
  x += 0x9E3779B97F4A7C15ULL;
  x = (x ^ (x >> 30)) * 0xBF58476D1CE4E5B9ULL;
  x = (x ^ (x >> 27)) * 0x94D049BB133111EBULL;
  return x ^ (x >> 31);
}

}  // namespace stridemap
