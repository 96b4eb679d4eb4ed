#pragma once
// Not API: the step the library's AVX2 packing loops share (TerrainMapper's
// packed pass, the URG model's conversion). A block of four beams keeps
// some lanes; the kept ones are moved to the front of each stream by one
// permute and stored at the packed count, so the packed arrays come out
// as the scalar loop writes them. x86-64 only; each caller is itself
// target("avx2") and chosen at run time.
#include <cstddef>
#include <cstdint>

#include <immintrin.h>

namespace stridemap::detail {

/// For each mask of kept 64-bit lanes, the 32-bit lane indices that bring
/// the kept lanes to the front in their order.
alignas(32) inline constexpr std::int32_t kKeptLanesFront[16][8] = {
    {0, 1, 2, 3, 4, 5, 6, 7}, {0, 1, 2, 3, 4, 5, 6, 7}, {2, 3, 0, 1, 4, 5, 6, 7}, {0, 1, 2, 3, 4, 5, 6, 7},
    {4, 5, 0, 1, 2, 3, 6, 7}, {0, 1, 4, 5, 2, 3, 6, 7}, {2, 3, 4, 5, 0, 1, 6, 7}, {0, 1, 2, 3, 4, 5, 6, 7},
    {6, 7, 0, 1, 2, 3, 4, 5}, {0, 1, 6, 7, 2, 3, 4, 5}, {2, 3, 6, 7, 0, 1, 4, 5}, {0, 1, 2, 3, 6, 7, 4, 5},
    {4, 5, 6, 7, 0, 1, 2, 3}, {0, 1, 4, 5, 6, 7, 2, 3}, {2, 3, 4, 5, 6, 7, 0, 1}, {0, 1, 2, 3, 4, 5, 6, 7}};

/// Stores the lanes of the four streams that `mask` (a movemask) keeps at
/// out_*[count] and advances count by their number. All four lanes are
/// written: the ones beyond the kept are overwritten by the next block or
/// left beyond the count, so each output needs 4 doubles of room past it.
__attribute__((target("avx2"))) inline void store_kept_lanes(unsigned mask, __m256d a, __m256d b, __m256d c,
                                                              __m256d d, double* out_a, double* out_b,
                                                              double* out_c, double* out_d, std::size_t& count) {
  const __m256i front = _mm256_load_si256(reinterpret_cast<const __m256i*>(kKeptLanesFront[mask]));
  _mm256_storeu_pd(out_a + count, _mm256_castps_pd(_mm256_permutevar8x32_ps(_mm256_castpd_ps(a), front)));
  _mm256_storeu_pd(out_b + count, _mm256_castps_pd(_mm256_permutevar8x32_ps(_mm256_castpd_ps(b), front)));
  _mm256_storeu_pd(out_c + count, _mm256_castps_pd(_mm256_permutevar8x32_ps(_mm256_castpd_ps(c), front)));
  _mm256_storeu_pd(out_d + count, _mm256_castps_pd(_mm256_permutevar8x32_ps(_mm256_castpd_ps(d), front)));
  count += static_cast<std::size_t>(__builtin_popcount(mask));
}

}  // namespace stridemap::detail
