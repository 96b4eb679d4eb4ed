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
                   double& max_sigma, double& max_range) {
  for (std::size_t i = first; i < end; ++i) {
    max_range = std::max(max_range, range[i]);
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

Verdict within_scalar(const double* x, const double* y, std::size_t begin, std::size_t end, double nx, double ny,
                      double rho, double inside_m, double outside_m, bool& unsure) {
  for (std::size_t i = begin; i < end; ++i) {
    const double residual = std::abs(x[i] * nx + y[i] * ny - rho);
    if (residual > outside_m) return Verdict::outside;
    unsure = unsure || !(residual <= inside_m);
  }
  return unsure ? Verdict::unsure : Verdict::inside;
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
                                                        double* y, double& max_sigma, double& max_range) {
  const __m256d per_error = _mm256_set1_pd(sigma.sigma_per_range_error), zero = _mm256_setzero_pd();
  const __m256d largest = _mm256_set1_pd(std::numeric_limits<double>::max());
  __m256d max = _mm256_set1_pd(max_sigma), farthest = _mm256_set1_pd(max_range);
  std::size_t i = first;
  for (; i + 4 <= end; i += 4) {
    const __m256d r = _mm256_loadu_pd(range + i);
    farthest = _mm256_max_pd(r, farthest);
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
  _mm256_storeu_pd(lanes, farthest);
  max_range = std::max(std::max(lanes[0], lanes[1]), std::max(lanes[2], lanes[3]));
  return i;
}

// The lanes' maximum and minimum, in every lane.
__attribute__((target("avx2"))) inline __m256d lanes_max(__m256d v) {
  v = _mm256_max_pd(v, _mm256_permute_pd(v, 0b0101));
  return _mm256_max_pd(v, _mm256_permute2f128_pd(v, v, 1));
}
__attribute__((target("avx2"))) inline __m256d lanes_min(__m256d v) {
  v = _mm256_min_pd(v, _mm256_permute_pd(v, 0b0101));
  return _mm256_min_pd(v, _mm256_permute2f128_pd(v, v, 1));
}

struct FarthestLanes {
  __m256d best, second, best_index;
};

// Each lane keeps its first largest cross product, the beam's index and
// the largest of the others; lanes in `skip` are held below any cross product.
__attribute__((target("avx2"))) inline void farthest_block(const double* x, const double* y, __m256d vax, __m256d vay,
                                                           __m256d vdx, __m256d vdy, __m256d index, __m256d skip,
                                                           FarthestLanes& lanes) {
  __m256d cross = _mm256_andnot_pd(
      _mm256_set1_pd(-0.0), _mm256_sub_pd(_mm256_mul_pd(_mm256_sub_pd(_mm256_loadu_pd(x), vax), vdy),
                                          _mm256_mul_pd(_mm256_sub_pd(_mm256_loadu_pd(y), vay), vdx)));
  cross = _mm256_blendv_pd(cross, _mm256_set1_pd(-2.0), skip);
  const __m256d greater = _mm256_cmp_pd(cross, lanes.best, _CMP_GT_OQ);
  // A NaN cross makes min() hand back the lane's best: a runner-up too
  // large, which the caller tolerates.
  lanes.second = _mm256_max_pd(_mm256_min_pd(cross, lanes.best), lanes.second);
  lanes.best = _mm256_blendv_pd(lanes.best, cross, greater);
  lanes.best_index = _mm256_blendv_pd(lanes.best_index, index, greater);
}

// The piece's last points are a block ending at `end`, its lanes already
// seen skipped.
__attribute__((target("avx2"))) void farthest_avx2(const double* x, const double* y, std::size_t begin,
                                                   std::size_t end, double ax, double ay, double dx, double dy,
                                                   ChordFarthest& far) {
  const __m256d vax = _mm256_set1_pd(ax), vay = _mm256_set1_pd(ay);
  const __m256d vdx = _mm256_set1_pd(dx), vdy = _mm256_set1_pd(dy);
  const __m256d none = _mm256_set1_pd(-1.0), four = _mm256_set1_pd(4.0);
  FarthestLanes lanes{none, none, none};
  __m256d index = _mm256_add_pd(_mm256_setr_pd(0.0, 1.0, 2.0, 3.0), _mm256_set1_pd(static_cast<double>(begin)));
  std::size_t i = begin;
  for (; i + 4 <= end; i += 4) {
    farthest_block(x + i, y + i, vax, vay, vdx, vdy, index, _mm256_setzero_pd(), lanes);
    index = _mm256_add_pd(index, four);
  }
  if (i < end) {
    const std::size_t back = 4 - (end - i);
    index = _mm256_sub_pd(index, _mm256_set1_pd(static_cast<double>(back)));
    const __m256d skip = _mm256_cmp_pd(index, _mm256_set1_pd(static_cast<double>(i)), _CMP_LT_OQ);
    farthest_block(x + end - 4, y + end - 4, vax, vay, vdx, vdy, index, skip, lanes);
  }
  // Lanes without a cross product above -1 hold -1 and index -1; among
  // equal maxima the earliest beam wins.
  const __m256d top = lanes_max(lanes.best);
  const __m256d at_top =
      _mm256_and_pd(_mm256_cmp_pd(lanes.best, top, _CMP_EQ_OQ), _mm256_cmp_pd(lanes.best, none, _CMP_GT_OQ));
  const __m256d winner = lanes_min(
      _mm256_blendv_pd(_mm256_set1_pd(std::numeric_limits<double>::infinity()), lanes.best_index, at_top));
  const __m256d others = _mm256_blendv_pd(lanes.best, none, _mm256_cmp_pd(lanes.best_index, winner, _CMP_EQ_OQ));
  far.runner_up = _mm256_cvtsd_f64(lanes_max(_mm256_max_pd(lanes.second, others)));
  if (_mm256_movemask_pd(at_top) == 0) return;
  far.cross = _mm256_cvtsd_f64(top);
  far.index = static_cast<std::size_t>(_mm256_cvtsd_f64(winner));
}

__attribute__((target("avx2"))) std::size_t within_avx2(const double* x, const double* y, std::size_t begin,
                                                        std::size_t end, double nx, double ny, double rho,
                                                        double inside_m, double outside_m, bool& outside,
                                                        bool& unsure) {
  const __m256d vnx = _mm256_set1_pd(nx), vny = _mm256_set1_pd(ny), vrho = _mm256_set1_pd(rho);
  const __m256d inside = _mm256_set1_pd(inside_m), beyond = _mm256_set1_pd(outside_m);
  const __m256d sign = _mm256_set1_pd(-0.0);
  __m256d doubt = _mm256_setzero_pd();
  std::size_t i = begin;
  for (; i + 4 <= end; i += 4) {
    const __m256d residual = _mm256_andnot_pd(
        sign, _mm256_sub_pd(_mm256_add_pd(_mm256_mul_pd(_mm256_loadu_pd(x + i), vnx),
                                          _mm256_mul_pd(_mm256_loadu_pd(y + i), vny)),
                            vrho));
    if (_mm256_movemask_pd(_mm256_cmp_pd(residual, beyond, _CMP_GT_OQ)) != 0) {
      outside = true;
      return i;
    }
    doubt = _mm256_or_pd(doubt, _mm256_cmp_pd(residual, inside, _CMP_NLE_UQ));
  }
  unsure = unsure || _mm256_movemask_pd(doubt) != 0;
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
                      std::size_t first, std::size_t last, const RangeSigmaModel& sigma, double* x, double* y,
                      double& max_range_m) {
  double max_sigma = 0.0;
  max_range_m = 0.0;
  std::size_t i = first;
#ifdef STRIDEMAP_LINES_AVX2
  if (has_avx2()) i = points_avx2(range, range_error, cos, sin, first, last + 1, sigma, x, y, max_sigma, max_range_m);
#endif
  points_scalar(range, range_error, cos, sin, i, last + 1, sigma, x, y, max_sigma, max_range_m);
  return max_sigma;
}

Verdict residuals_within(const double* x, const double* y, std::size_t first, std::size_t last, double nx, double ny,
                         double rho, double inside_m, double outside_m) {
  bool unsure = false;
  std::size_t i = first;
#ifdef STRIDEMAP_LINES_AVX2
  if (has_avx2()) {
    bool outside = false;
    i = within_avx2(x, y, first, last + 1, nx, ny, rho, inside_m, outside_m, outside, unsure);
    if (outside) return Verdict::outside;
  }
#endif
  return within_scalar(x, y, i, last + 1, nx, ny, rho, inside_m, outside_m, unsure);
}

ChordFarthest farthest_from_chord(const double* x, const double* y, std::size_t begin, std::size_t end, double ax,
                                  double ay, double dx, double dy) {
  ChordFarthest far;
#ifdef STRIDEMAP_LINES_AVX2
  if (end - begin >= 4 && has_avx2()) {
    farthest_avx2(x, y, begin, end, ax, ay, dx, dy, far);
    return far;
  }
#endif
  farthest_scalar(x, y, begin, end, ax, ay, dx, dy, far);
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
