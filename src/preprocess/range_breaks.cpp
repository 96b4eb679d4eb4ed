#include "range_breaks.hpp"

#include <cstring>
#include <limits>

#if defined(__SSE2__)
#include <emmintrin.h>
#endif
// Where the CPU has AVX2, four pairs a vector, chosen at run time (as the
// URG model's conversion; STRIDEMAP_NO_AVX2_COPIES leaves it out).
#if defined(__x86_64__) && defined(__GNUC__) && !defined(__clang__) && defined(__linux__) && \
    !defined(STRIDEMAP_NO_AVX2_COPIES)
#define STRIDEMAP_BREAKS_AVX2 1
#include <immintrin.h>
#endif

namespace stridemap::detail {
namespace {

// The scalar test, for the pairs the vectors leave (a tail, a beam whose
// sigma_r comes from the URG spec).
void mark_scalar(const PlanarScan& scan, const RangeRatioBand& band, double noise_sigmas, const RangeSigmaModel& sigma,
                 std::size_t first, std::size_t end, std::uint8_t* out) {
  const double* range = scan.range_m.data();
  const double* error = scan.range_error_m.data();
  for (std::size_t i = first; i < end; ++i) {
    const double previous = range[i - 1], next = range[i];
    const bool joined = usable_range(previous) && usable_range(next) &&
                        ranges_on_one_surface(previous, next, noise_sigmas * sigma.sigma_m(previous, error[i - 1]), band);
    out[i] = static_cast<std::uint8_t>(!joined);
  }
}

// The vectors below: no FMA, so every product and sum rounds as in the
// scalar test. A NaN range fails the band's comparisons; the minimum and
// maximum of the pair reject the other unusable ranges. A pair whose first
// beam has no Delta r of its own (not finite and positive) goes scalar.

#if defined(__SSE2__)
std::size_t mark_sse2(const PlanarScan& scan, const RangeRatioBand& band, double noise_sigmas,
                      const RangeSigmaModel& sigma, std::uint8_t* out) {
  const std::size_t n = scan.size();
  const double* range = scan.range_m.data();
  const double* error = scan.range_error_m.data();
  const __m128d lower = _mm_set1_pd(band.lower_factor), upper = _mm_set1_pd(band.upper_factor);
  const __m128d max = _mm_set1_pd(std::numeric_limits<double>::max()), zero = _mm_setzero_pd();
  const __m128d per_error = _mm_set1_pd(sigma.sigma_per_range_error), sigmas = _mm_set1_pd(noise_sigmas);
  std::size_t i = 1;
  for (; i + 2 <= n; i += 2) {
    const __m128d previous = _mm_loadu_pd(range + i - 1), next = _mm_loadu_pd(range + i);
    const __m128d previous_error = _mm_loadu_pd(error + i - 1);
    if (_mm_movemask_pd(_mm_and_pd(_mm_cmpgt_pd(previous_error, zero), _mm_cmple_pd(previous_error, max))) != 3) {
      mark_scalar(scan, band, noise_sigmas, sigma, i, i + 2, out);
      continue;
    }
    const __m128d tolerance = _mm_mul_pd(sigmas, _mm_mul_pd(per_error, previous_error));
    __m128d joined = _mm_and_pd(_mm_cmpgt_pd(_mm_min_pd(previous, next), zero),
                                _mm_cmple_pd(_mm_max_pd(previous, next), max));
    joined = _mm_and_pd(joined, _mm_cmpgt_pd(next, _mm_sub_pd(_mm_mul_pd(lower, previous), tolerance)));
    joined = _mm_and_pd(joined, _mm_cmplt_pd(next, _mm_add_pd(_mm_mul_pd(upper, previous), tolerance)));
    const int mask = ~_mm_movemask_pd(joined);
    out[i] = static_cast<std::uint8_t>(mask & 1);
    out[i + 1] = static_cast<std::uint8_t>((mask >> 1) & 1);
  }
  return i;
}
#endif

#ifdef STRIDEMAP_BREAKS_AVX2
__attribute__((target("avx2"))) std::size_t mark_avx2(const PlanarScan& scan, const RangeRatioBand& band,
                                                      double noise_sigmas, const RangeSigmaModel& sigma,
                                                      std::uint8_t* out) {
  // The four flags of a mask's clear bits, one byte each (little endian).
  static constexpr std::uint32_t kFlags[16] = {
      0x01010101, 0x01010100, 0x01010001, 0x01010000, 0x01000101, 0x01000100, 0x01000001, 0x01000000,
      0x00010101, 0x00010100, 0x00010001, 0x00010000, 0x00000101, 0x00000100, 0x00000001, 0x00000000};
  const std::size_t n = scan.size();
  const double* range = scan.range_m.data();
  const double* error = scan.range_error_m.data();
  const __m256d lower = _mm256_set1_pd(band.lower_factor), upper = _mm256_set1_pd(band.upper_factor);
  const __m256d max = _mm256_set1_pd(std::numeric_limits<double>::max()), zero = _mm256_setzero_pd();
  const __m256d per_error = _mm256_set1_pd(sigma.sigma_per_range_error), sigmas = _mm256_set1_pd(noise_sigmas);
  std::size_t i = 1;
  for (; i + 4 <= n; i += 4) {
    const __m256d previous = _mm256_loadu_pd(range + i - 1), next = _mm256_loadu_pd(range + i);
    const __m256d previous_error = _mm256_loadu_pd(error + i - 1);
    const __m256d error_ok =
        _mm256_and_pd(_mm256_cmp_pd(previous_error, zero, _CMP_GT_OQ), _mm256_cmp_pd(previous_error, max, _CMP_LE_OQ));
    if (_mm256_movemask_pd(error_ok) != 15) {
      mark_scalar(scan, band, noise_sigmas, sigma, i, i + 4, out);
      continue;
    }
    const __m256d tolerance = _mm256_mul_pd(sigmas, _mm256_mul_pd(per_error, previous_error));
    __m256d joined = _mm256_and_pd(_mm256_cmp_pd(_mm256_min_pd(previous, next), zero, _CMP_GT_OQ),
                                   _mm256_cmp_pd(_mm256_max_pd(previous, next), max, _CMP_LE_OQ));
    joined = _mm256_and_pd(
        joined, _mm256_cmp_pd(next, _mm256_sub_pd(_mm256_mul_pd(lower, previous), tolerance), _CMP_GT_OQ));
    joined = _mm256_and_pd(
        joined, _mm256_cmp_pd(next, _mm256_add_pd(_mm256_mul_pd(upper, previous), tolerance), _CMP_LT_OQ));
    std::memcpy(out + i, &kFlags[_mm256_movemask_pd(joined)], 4);
  }
  return i;
}
#endif

bool same_bits(double a, double b) { return std::memcmp(&a, &b, sizeof a) == 0; }

}  // namespace

bool made_with(const RangeBreaks& known, std::size_t beams, const RangeRatioBand& band, double noise_sigmas,
               const RangeSigmaModel& sigma) {
  return known.valid && known.breaks.size() == beams && same_bits(known.band.lower_factor, band.lower_factor) &&
         same_bits(known.band.upper_factor, band.upper_factor) && same_bits(known.noise_sigmas, noise_sigmas) &&
         same_bits(known.sigma.sigma_per_range_error, sigma.sigma_per_range_error) &&
         known.sigma.always_use_urg_spec == sigma.always_use_urg_spec;
}

void mark_range_breaks(const PlanarScan& scan, const RangeRatioBand& band, double noise_sigmas,
                       const RangeSigmaModel& sigma, std::vector<std::uint8_t>& breaks) {
  const std::size_t n = scan.size();
  breaks.resize(n);
  if (n == 0) return;
  std::uint8_t* out = breaks.data();
  out[0] = 1;
  std::size_t i = 1;
  if (!sigma.always_use_urg_spec) {
#ifdef STRIDEMAP_BREAKS_AVX2
    static const bool has_avx2 = __builtin_cpu_supports("avx2");
    if (has_avx2) i = mark_avx2(scan, band, noise_sigmas, sigma, out);
#endif
#if defined(__SSE2__)
    if (i == 1) i = mark_sse2(scan, band, noise_sigmas, sigma, out);
#endif
  }
  mark_scalar(scan, band, noise_sigmas, sigma, i, n, out);
}

}  // namespace stridemap::detail
