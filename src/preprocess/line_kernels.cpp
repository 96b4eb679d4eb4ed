#include "line_kernels.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

// As range_breaks.cpp: AVX2 copies where GCC on Linux x86-64 can choose
// them at run time (STRIDEMAP_NO_AVX2_COPIES leaves them out).
#if defined(__x86_64__) && defined(__GNUC__) && !defined(__clang__) && defined(__linux__) && \
    !defined(STRIDEMAP_NO_AVX2_COPIES)
#define STRIDEMAP_LINES_AVX2 1
#include <immintrin.h>
#endif

namespace stridemap::detail {
namespace {

void points_scalar(const double* range, const double* range_error, const double* cos, const double* sin,
                   std::size_t first, std::size_t end, const RangeSigmaModel& sigma, double* x, double* y,
                   double& max_sigma) {
  for (std::size_t i = first; i < end; ++i) {
    x[i] = range[i] * cos[i];
    y[i] = range[i] * sin[i];
    max_sigma = std::max(max_sigma, sigma.sigma_m(range[i], range_error[i]));
  }
}

void farthest_scalar(const double* x, const double* y, std::size_t begin, std::size_t end, double ax, double ay,
                     double dx, double dy, ChordFarthest& far) {
  for (std::size_t i = begin; i < end; ++i) {
    const double cross = std::abs((x[i] - ax) * dy - (y[i] - ay) * dx);
    if (cross > far.cross) {
      far.runner_up = far.cross;
      far.cross = cross;
      far.index = i;
    } else {
      far.runner_up = std::max(far.runner_up, cross);
    }
  }
}

bool extent_scalar(const double* x, const double* y, std::size_t begin, std::size_t end, double nx, double ny,
                   double rho, double limit_m, LineExtent& extent) {
  for (std::size_t i = begin; i < end; ++i) {
    const double residual = std::abs(x[i] * nx + y[i] * ny - rho);
    if (residual > limit_m) return false;
    extent.max_residual_m = std::max(extent.max_residual_m, residual);
    const double along = -x[i] * ny + y[i] * nx;
    extent.along_min_m = std::min(extent.along_min_m, along);
    extent.along_max_m = std::max(extent.along_max_m, along);
  }
  return true;
}

#ifdef STRIDEMAP_LINES_AVX2
bool has_avx2() {
  static const bool has = __builtin_cpu_supports("avx2");
  return has;
}

// Maxima and minima in any order equal those taken in beam order but for
// the sign of a zero (the first of +0 and -0 wins there) and for a NaN
// (std::max keeps what it has): the vector's maximum and minimum take the
// new value as first operand, which hands back the second on a NaN, and the
// callers redo a result of zero in beam order.
__attribute__((target("avx2"))) std::size_t points_avx2(const double* range, const double* range_error,
                                                        const double* cos, const double* sin, std::size_t first,
                                                        std::size_t end, const RangeSigmaModel& sigma, double* x,
                                                        double* y, double& max_sigma) {
  const __m256d per_error = _mm256_set1_pd(sigma.sigma_per_range_error), zero = _mm256_setzero_pd();
  const __m256d largest = _mm256_set1_pd(std::numeric_limits<double>::max());
  __m256d max = _mm256_set1_pd(max_sigma);
  std::size_t i = first;
  for (; i + 4 <= end; i += 4) {
    const __m256d r = _mm256_loadu_pd(range + i);
    _mm256_storeu_pd(x + i, _mm256_mul_pd(r, _mm256_loadu_pd(cos + i)));
    _mm256_storeu_pd(y + i, _mm256_mul_pd(r, _mm256_loadu_pd(sin + i)));
    const __m256d error = _mm256_loadu_pd(range_error + i);
    const __m256d own = _mm256_and_pd(_mm256_cmp_pd(error, zero, _CMP_GT_OQ), _mm256_cmp_pd(error, largest, _CMP_LE_OQ));
    if (sigma.always_use_urg_spec || _mm256_movemask_pd(own) != 15) {
      double block = 0.0;
      for (std::size_t k = i; k < i + 4; ++k) block = std::max(block, sigma.sigma_m(range[k], range_error[k]));
      max = _mm256_max_pd(_mm256_set1_pd(block), max);
      continue;
    }
    max = _mm256_max_pd(_mm256_mul_pd(per_error, error), max);
  }
  double lanes[4];
  _mm256_storeu_pd(lanes, max);
  max_sigma = std::max(std::max(lanes[0], lanes[1]), std::max(lanes[2], lanes[3]));
  return i;
}

__attribute__((target("avx2"))) std::size_t farthest_avx2(const double* x, const double* y, std::size_t begin,
                                                          std::size_t end, double ax, double ay, double dx,
                                                          double dy, ChordFarthest& far) {
  const __m256d vax = _mm256_set1_pd(ax), vay = _mm256_set1_pd(ay);
  const __m256d vdx = _mm256_set1_pd(dx), vdy = _mm256_set1_pd(dy), sign = _mm256_set1_pd(-0.0);
  __m256d best = _mm256_set1_pd(-1.0), second = best, best_index = best;
  __m256d index = _mm256_setr_pd(0.0, 1.0, 2.0, 3.0);
  index = _mm256_add_pd(index, _mm256_set1_pd(static_cast<double>(begin)));
  const __m256d four = _mm256_set1_pd(4.0);
  std::size_t i = begin;
  for (; i + 4 <= end; i += 4) {
    const __m256d cross = _mm256_andnot_pd(
        sign, _mm256_sub_pd(_mm256_mul_pd(_mm256_sub_pd(_mm256_loadu_pd(x + i), vax), vdy),
                            _mm256_mul_pd(_mm256_sub_pd(_mm256_loadu_pd(y + i), vay), vdx)));
    const __m256d greater = _mm256_cmp_pd(cross, best, _CMP_GT_OQ);
    // A NaN cross makes min() hand back the lane's best: a runner-up too
    // large, which the caller tolerates.
    second = _mm256_max_pd(_mm256_min_pd(cross, best), second);
    best = _mm256_blendv_pd(best, cross, greater);
    best_index = _mm256_blendv_pd(best_index, index, greater);
    index = _mm256_add_pd(index, four);
  }
  if (i == begin) return i;
  double bests[4], seconds[4], indices[4];
  _mm256_storeu_pd(bests, best);
  _mm256_storeu_pd(seconds, second);
  _mm256_storeu_pd(indices, best_index);
  // The lanes' first maxima; among equal ones the earliest beam wins.
  int winner = -1;
  for (int k = 0; k < 4; ++k) {
    if (!(bests[k] > -1.0)) continue;
    if (winner < 0 || bests[k] > bests[winner] || (bests[k] == bests[winner] && indices[k] < indices[winner])) winner = k;
  }
  for (int k = 0; k < 4; ++k) {
    far.runner_up = std::max(far.runner_up, seconds[k]);
    if (k != winner) far.runner_up = std::max(far.runner_up, bests[k]);
  }
  if (winner >= 0) {
    far.cross = bests[winner];
    far.index = static_cast<std::size_t>(indices[winner]);
  }
  return i;
}

__attribute__((target("avx2"))) std::size_t extent_avx2(const double* x, const double* y, std::size_t begin,
                                                        std::size_t end, double nx, double ny, double rho,
                                                        double limit_m, LineExtent& extent, bool& within) {
  const __m256d vnx = _mm256_set1_pd(nx), vny = _mm256_set1_pd(ny), vrho = _mm256_set1_pd(rho);
  const __m256d limit = _mm256_set1_pd(limit_m), sign = _mm256_set1_pd(-0.0);
  __m256d max_residual = _mm256_set1_pd(extent.max_residual_m);
  __m256d low = _mm256_set1_pd(extent.along_min_m), high = _mm256_set1_pd(extent.along_max_m);
  within = true;
  std::size_t i = begin;
  for (; i + 4 <= end; i += 4) {
    const __m256d px = _mm256_loadu_pd(x + i), py = _mm256_loadu_pd(y + i);
    const __m256d residual = _mm256_andnot_pd(
        sign, _mm256_sub_pd(_mm256_add_pd(_mm256_mul_pd(px, vnx), _mm256_mul_pd(py, vny)), vrho));
    if (_mm256_movemask_pd(_mm256_cmp_pd(residual, limit, _CMP_GT_OQ)) != 0) {
      within = false;
      return i;
    }
    max_residual = _mm256_max_pd(residual, max_residual);
    const __m256d along = _mm256_add_pd(_mm256_mul_pd(_mm256_xor_pd(px, sign), vny), _mm256_mul_pd(py, vnx));
    low = _mm256_min_pd(along, low);
    high = _mm256_max_pd(along, high);
  }
  double m[4], l[4], h[4];
  _mm256_storeu_pd(m, max_residual);
  _mm256_storeu_pd(l, low);
  _mm256_storeu_pd(h, high);
  extent.max_residual_m = std::max(std::max(m[0], m[1]), std::max(m[2], m[3]));
  extent.along_min_m = std::min(std::min(l[0], l[1]), std::min(l[2], l[3]));
  extent.along_max_m = std::max(std::max(h[0], h[1]), std::max(h[2], h[3]));
  return i;
}
#endif

}  // namespace

double cluster_points(const double* range, const double* range_error, const double* cos, const double* sin,
                      std::size_t first, std::size_t last, const RangeSigmaModel& sigma, double* x, double* y) {
  double max_sigma = 0.0;
  std::size_t i = first;
#ifdef STRIDEMAP_LINES_AVX2
  if (has_avx2()) i = points_avx2(range, range_error, cos, sin, first, last + 1, sigma, x, y, max_sigma);
#endif
  points_scalar(range, range_error, cos, sin, i, last + 1, sigma, x, y, max_sigma);
  return max_sigma;
}

ChordFarthest farthest_from_chord(const double* x, const double* y, std::size_t begin, std::size_t end, double ax,
                                  double ay, double dx, double dy) {
  ChordFarthest far;
  std::size_t i = begin;
#ifdef STRIDEMAP_LINES_AVX2
  if (has_avx2()) i = farthest_avx2(x, y, begin, end, ax, ay, dx, dy, far);
#endif
  farthest_scalar(x, y, i, end, ax, ay, dx, dy, far);
  return far;
}

bool line_extent(const double* x, const double* y, std::size_t first, std::size_t last, double nx, double ny,
                 double rho, double limit_m, LineExtent& extent) {
  extent = {0.0, std::numeric_limits<double>::infinity(), -std::numeric_limits<double>::infinity()};
  std::size_t i = first;
#ifdef STRIDEMAP_LINES_AVX2
  if (has_avx2()) {
    bool within = true;
    i = extent_avx2(x, y, first, last + 1, nx, ny, rho, limit_m, extent, within);
    if (!within) return false;
  }
#endif
  if (!extent_scalar(x, y, i, last + 1, nx, ny, rho, limit_m, extent)) return false;
  // Which zero a maximum or minimum of zero is depends on the order.
  if (i != first && (extent.along_min_m == 0.0 || extent.along_max_m == 0.0)) {
    extent = {0.0, std::numeric_limits<double>::infinity(), -std::numeric_limits<double>::infinity()};
    return extent_scalar(x, y, first, last + 1, nx, ny, rho, limit_m, extent);
  }
  return true;
}

}  // namespace stridemap::detail
