#include "visibility_screen.hpp"

#include <limits>

// The screen is an AVX2 copy chosen at run time (GCC and clang on x86-64);
// elsewhere a fan is traced beam by beam and screen() is never called.
#if defined(__x86_64__) && defined(__GNUC__) && !defined(STRIDEMAP_NO_AVX2_COPIES)
#define STRIDEMAP_VISIBILITY_SCREEN 1
#include <immintrin.h>
#endif

namespace stridemap::visibility {

#if defined(STRIDEMAP_VISIBILITY_SCREEN)
namespace {

#define STRIDEMAP_AVX2_INLINE __attribute__((target("avx2"), always_inline)) inline

bool cpu_has_avx2() {
  static const bool has = __builtin_cpu_supports("avx2");
  return has;
}

STRIDEMAP_AVX2_INLINE __m256d lt4(__m256d a, __m256d b) { return _mm256_cmp_pd(a, b, _CMP_LT_OQ); }
// !(a < b), true for a NaN as the scalar test is.
STRIDEMAP_AVX2_INLINE __m256d not_lt4(__m256d a, __m256d b) { return _mm256_cmp_pd(a, b, _CMP_NLT_UQ); }
STRIDEMAP_AVX2_INLINE __m256d abs4(__m256d v) { return _mm256_andnot_pd(_mm256_set1_pd(-0.0), v); }

// trace_valid()'s clearance(), lane by lane: (z0 + margin) - (bound + slack).
STRIDEMAP_AVX2_INLINE __m256d clearance4(__m256d z0_margin, __m256d slack_sum, __m256d bound) {
  const __m256d slack = _mm256_mul_pd(_mm256_set1_pd(1e-9), _mm256_add_pd(slack_sum, abs4(bound)));
  return _mm256_sub_pd(z0_margin, _mm256_add_pd(bound, slack));
}

// range_max() on four ranges 0 <= lo <= hi < n: floor(log2(len)) read
// from the exponent of len as a float (exact below 2^24).
STRIDEMAP_AVX2_INLINE __m128 range_max4(const float* table, __m128i lo, __m128i hi, __m128i n) {
  const __m128i one = _mm_set1_epi32(1);
  const __m128i len = _mm_add_epi32(_mm_sub_epi32(hi, lo), one);
  const __m128i level =
      _mm_sub_epi32(_mm_srli_epi32(_mm_castps_si128(_mm_cvtepi32_ps(len)), 23), _mm_set1_epi32(127));
  const __m128i base = _mm_mullo_epi32(level, n);
  const __m128i first = _mm_add_epi32(base, lo);
  const __m128i second = _mm_add_epi32(base, _mm_add_epi32(_mm_sub_epi32(hi, _mm_sllv_epi32(one, level)), one));
  const __m128 a = _mm_i32gather_ps(table, first, 4), b = _mm_i32gather_ps(table, second, 4);
  return _mm_max_ps(b, a);  // a < b ? b : a
}

// trace_valid()'s bound(t0, t1), lane by lane. The indices are worked in
// doubles: whole numbers below 2^53 there (the caller sees to it), so
// every step is exact, as the scalar int64 steps are.
STRIDEMAP_AVX2_INLINE __m256d bound4(const ScreenScan& c, __m256d dx, __m256d dy, __m256d t0, __m256d t1) {
  const __m256d zero = _mm256_setzero_pd(), one = _mm256_set1_pd(1.0), last = _mm256_set1_pd(c.last_index);
  const __m256d ox = _mm256_set1_pd(c.ox), oy = _mm256_set1_pd(c.oy);
  const __m256d x0 = _mm256_add_pd(ox, _mm256_mul_pd(dx, t0)), x1 = _mm256_add_pd(ox, _mm256_mul_pd(dx, t1));
  const __m256d y0 = _mm256_add_pd(oy, _mm256_mul_pd(dy, t0)), y1 = _mm256_add_pd(oy, _mm256_mul_pd(dy, t1));
  const __m256d back_x = lt4(dx, zero), back_y = lt4(dy, zero);
  const __m256d cx = _mm256_set1_pd(c.corner_x), cy = _mm256_set1_pd(c.corner_y);
  __m256d lo_i = _mm256_max_pd(
      _mm256_sub_pd(_mm256_sub_pd(_mm256_floor_pd(_mm256_blendv_pd(x0, x1, back_x)), one), cx), zero);
  __m256d hi_i = _mm256_min_pd(
      _mm256_sub_pd(_mm256_add_pd(_mm256_floor_pd(_mm256_blendv_pd(x1, x0, back_x)), one), cx), last);
  __m256d lo_j = _mm256_max_pd(
      _mm256_sub_pd(_mm256_sub_pd(_mm256_floor_pd(_mm256_blendv_pd(y0, y1, back_y)), one), cy), zero);
  __m256d hi_j = _mm256_min_pd(
      _mm256_sub_pd(_mm256_add_pd(_mm256_floor_pd(_mm256_blendv_pd(y1, y0, back_y)), one), cy), last);
  const __m256d inside =
      _mm256_and_pd(_mm256_cmp_pd(lo_i, hi_i, _CMP_LE_OQ), _mm256_cmp_pd(lo_j, hi_j, _CMP_LE_OQ));
  // Lanes with no range look up row and column 0, their value unused.
  lo_i = _mm256_and_pd(lo_i, inside);
  hi_i = _mm256_and_pd(hi_i, inside);
  lo_j = _mm256_and_pd(lo_j, inside);
  hi_j = _mm256_and_pd(hi_j, inside);
  const __m128i n = _mm_set1_epi32(c.n);
  const __m128 rows = range_max4(c.row_max, _mm256_cvttpd_epi32(lo_i), _mm256_cvttpd_epi32(hi_i), n);
  const __m128 columns = range_max4(c.column_max, _mm256_cvttpd_epi32(lo_j), _mm256_cvttpd_epi32(hi_j), n);
  const __m256d both = _mm256_cvtps_pd(_mm_min_ps(columns, rows));  // std::min(rows, columns)
  return _mm256_blendv_pd(_mm256_set1_pd(-std::numeric_limits<double>::infinity()), both, inside);
}

// Four beams of the screen: what narrow_walk() and the tests before it
// hold, lane by lane.
struct ScreenLanes {
  __m256d dz, falling, slack_sum, z0_margin, t_stop, dx, dy, margin;
  __m256d settled, left, fall, rise, level, t_skip, t_last, top;
};

// trace_valid()'s tests before narrow_walk()'s rounds.
STRIDEMAP_AVX2_INLINE void screen_start(const ScreenScan& c, const ScreenBatch& b, std::size_t k, ScreenLanes& l) {
  const __m256d zero = _mm256_setzero_pd(), one = _mm256_set1_pd(1.0), sign = _mm256_set1_pd(-0.0);
  const __m256d max_index = _mm256_set1_pd(1e15);
  const __m256d dz = _mm256_load_pd(b.dz_m + k), range_error = _mm256_load_pd(b.range_error_m + k);
  const __m256d margin = _mm256_add_pd(
      _mm256_mul_pd(_mm256_set1_pd(c.uncertainty_factor), _mm256_load_pd(b.height_error_m + k)),
      _mm256_set1_pd(c.relief_m));
  l.dz = dz;
  l.margin = margin;
  l.slack_sum = _mm256_add_pd(_mm256_add_pd(_mm256_set1_pd(c.one_abs_z0), abs4(dz)), abs4(margin));
  l.z0_margin = _mm256_add_pd(_mm256_set1_pd(c.z0), margin);
  const __m256d falling = lt4(dz, zero), rising = _mm256_cmp_pd(dz, zero, _CMP_GT_OQ);
  l.falling = falling;
  l.top = _mm256_set1_pd(c.top);
  const __m256d top_clearance = clearance4(l.z0_margin, l.slack_sum, l.top);
  // The window's highest cell.
  __m256d settled = _mm256_blendv_pd(not_lt4(top_clearance, zero),
                                     _mm256_and_pd(_mm256_cmp_pd(range_error, zero, _CMP_GE_OQ),
                                                   not_lt4(top_clearance, _mm256_xor_pd(dz, sign))),
                                     falling);
  const __m256d t_stop = _mm256_sub_pd(one, _mm256_div_pd(range_error, _mm256_sqrt_pd(_mm256_load_pd(b.range2 + k))));
  l.t_stop = t_stop;
  settled = _mm256_or_pd(settled, _mm256_cmp_pd(t_stop, zero, _CMP_NGT_UQ));
  const __m256d inverse_cell = _mm256_set1_pd(c.inverse_cell);
  l.dx = _mm256_mul_pd(_mm256_load_pd(b.dx_m + k), inverse_cell);
  l.dy = _mm256_mul_pd(_mm256_load_pd(b.dy_m + k), inverse_cell);
  settled = _mm256_or_pd(settled, _mm256_or_pd(not_lt4(abs4(_mm256_add_pd(_mm256_set1_pd(c.ox), l.dx)), max_index),
                                               not_lt4(abs4(_mm256_add_pd(_mm256_set1_pd(c.oy), l.dy)), max_index)));
  // narrow_walk(): falling, rising and level lanes side by side.
  const __m256d open = _mm256_andnot_pd(settled, _mm256_cmp_pd(t_stop, one, _CMP_LE_OQ));
  l.left = _mm256_andnot_pd(_mm256_or_pd(settled, open), _mm256_castsi256_pd(_mm256_set1_epi64x(-1)));
  l.fall = _mm256_and_pd(open, falling);
  l.rise = _mm256_and_pd(open, rising);
  l.level = _mm256_andnot_pd(_mm256_or_pd(falling, rising), open);
  // c / -dz and -c / dz are both -(c / dz) exactly: one division for the
  // start of a falling beam's walk and the end of a rising one's.
  l.t_skip = _mm256_xor_pd(_mm256_div_pd(top_clearance, dz), sign);
  l.t_last = l.t_skip;
  l.settled = _mm256_or_pd(settled, _mm256_and_pd(l.fall, not_lt4(l.t_skip, t_stop)));
  l.fall = _mm256_and_pd(l.fall, lt4(l.t_skip, t_stop));
}

STRIDEMAP_AVX2_INLINE bool screen_active(const ScreenLanes& l) {
  const __m256d active = _mm256_or_pd(_mm256_or_pd(l.fall, l.rise), l.level);
  return !_mm256_testz_pd(active, active);
}

// One of narrow_walk()'s rounds; nothing changes in lanes already done.
STRIDEMAP_AVX2_INLINE void screen_round(const ScreenScan& c, ScreenLanes& l) {
  const __m256d zero = _mm256_setzero_pd(), sign = _mm256_set1_pd(-0.0);
  const __m256d active = _mm256_or_pd(_mm256_or_pd(l.fall, l.rise), l.level);
  const __m256d t0 = _mm256_and_pd(_mm256_blendv_pd(l.t_skip, zero, lt4(l.t_skip, zero)), l.fall);
  const __m256d t1 =
      _mm256_blendv_pd(l.t_stop, _mm256_blendv_pd(l.t_last, l.t_stop, lt4(l.t_stop, l.t_last)), l.rise);
  const __m256d lower = bound4(c, l.dx, l.dy, t0, t1);
  const __m256d none =
      _mm256_cmp_pd(lower, _mm256_set1_pd(-std::numeric_limits<double>::infinity()), _CMP_NGT_UQ);
  __m256d settled = _mm256_or_pd(l.settled, _mm256_and_pd(active, none));
  const __m256d lower_clearance = clearance4(l.z0_margin, l.slack_sum, lower);
  settled = _mm256_or_pd(settled, _mm256_andnot_pd(none, _mm256_and_pd(l.level, not_lt4(lower_clearance, zero))));
  l.level = zero;
  // A lower bound than the last moves the walk's ends on.
  const __m256d lower_top = _mm256_andnot_pd(none, lt4(lower, l.top));
  __m256d fall = _mm256_and_pd(l.fall, lower_top), rise = _mm256_and_pd(l.rise, lower_top);
  l.top = _mm256_blendv_pd(l.top, lower, _mm256_or_pd(fall, rise));
  const __m256d t_moved = _mm256_xor_pd(_mm256_div_pd(lower_clearance, l.dz), sign);
  l.t_skip = _mm256_blendv_pd(l.t_skip, t_moved, fall);
  settled = _mm256_or_pd(settled, _mm256_and_pd(fall, not_lt4(l.t_skip, l.t_stop)));
  l.fall = _mm256_and_pd(fall, lt4(l.t_skip, l.t_stop));
  settled = _mm256_or_pd(settled, _mm256_and_pd(rise, not_lt4(lower_clearance, zero)));
  l.rise = _mm256_and_pd(rise, lt4(lower_clearance, zero));
  l.t_last = _mm256_blendv_pd(l.t_last, t_moved, l.rise);
  l.settled = settled;
}

// The walk's arguments of a vector with a lane to walk.
STRIDEMAP_AVX2_INLINE void screen_store(const ScreenLanes& l, ScreenBatch& b, std::size_t k) {
  _mm256_store_pd(b.dx_cells + k, l.dx);
  _mm256_store_pd(b.dy_cells + k, l.dy);
  // The walk's divisions, four at a time here rather than one by one on its way in.
  _mm256_store_pd(b.inverse_dx + k, _mm256_div_pd(_mm256_set1_pd(1.0), l.dx));
  _mm256_store_pd(b.inverse_dy + k, _mm256_div_pd(_mm256_set1_pd(1.0), l.dy));
  _mm256_store_pd(b.margin_m + k, l.margin);
  _mm256_store_pd(b.t_stop + k, l.t_stop);
  _mm256_store_pd(b.t_skip + k, _mm256_blendv_pd(_mm256_set1_pd(-1.0), l.t_skip, l.falling));
  _mm256_store_pd(b.t_last + k, l.t_last);
}

// One axis of a walk's start, lane by lane: Axis's constructor and then
// skip_to(t) where t > 0, with the search taken as settled by its first
// guess. `exact` is cleared in lanes where a correction step would follow.
struct AxisStart {
  __m256d index, boundary, next, before;
};

STRIDEMAP_AVX2_INLINE AxisStart axis_start4(__m256d o, __m256d origin_index, __m256d d, __m256d inverse_d,
                                            __m256d t, __m256d skip, __m256d& exact) {
  const __m256d zero = _mm256_setzero_pd(), one = _mm256_set1_pd(1.0);
  const __m256d infinity = _mm256_set1_pd(std::numeric_limits<double>::infinity());
  const __m256d forward = _mm256_cmp_pd(d, zero, _CMP_GT_OQ);
  const __m256d s = _mm256_blendv_pd(_mm256_set1_pd(-1.0), one, forward);
  const __m256d moves =
      _mm256_and_pd(_mm256_cmp_pd(d, zero, _CMP_NEQ_UQ), lt4(abs4(inverse_d), infinity));
  const __m256d boundary = _mm256_add_pd(origin_index, _mm256_and_pd(forward, one));
  const __m256d next = _mm256_blendv_pd(infinity, _mm256_mul_pd(_mm256_sub_pd(boundary, o), inverse_d), moves);
  // skip_to(): only where the axis moves and its next crossing is <= t.
  const __m256d skipping = _mm256_and_pd(_mm256_and_pd(skip, moves), _mm256_cmp_pd(next, t, _CMP_LE_OQ));
  const __m256d at = _mm256_add_pd(o, _mm256_mul_pd(t, d));
  const __m256d nearest = _mm256_add_pd(boundary, s);
  const __m256d up = _mm256_add_pd(_mm256_floor_pd(at), one);
  const __m256d down = _mm256_sub_pd(_mm256_xor_pd(_mm256_floor_pd(_mm256_xor_pd(at, _mm256_set1_pd(-0.0))),
                                                   _mm256_set1_pd(-0.0)),
                                     one);
  __m256d target = _mm256_blendv_pd(down, up, forward);
  target = _mm256_blendv_pd(target, nearest, lt4(_mm256_mul_pd(_mm256_sub_pd(target, nearest), s), zero));
  const __m256d before = _mm256_mul_pd(_mm256_sub_pd(_mm256_sub_pd(target, s), o), inverse_d);
  const __m256d after = _mm256_mul_pd(_mm256_sub_pd(target, o), inverse_d);
  // The search would step back while before > t, on while after <= t.
  const __m256d settled = _mm256_and_pd(_mm256_cmp_pd(before, t, _CMP_NGT_UQ), _mm256_cmp_pd(after, t, _CMP_NLE_UQ));
  exact = _mm256_andnot_pd(_mm256_andnot_pd(settled, skipping), exact);
  AxisStart a;
  a.index = _mm256_blendv_pd(origin_index, _mm256_add_pd(origin_index, _mm256_sub_pd(target, boundary)), skipping);
  a.boundary = _mm256_blendv_pd(boundary, target, skipping);
  a.next = _mm256_blendv_pd(next, after, skipping);
  a.before = _mm256_blendv_pd(_mm256_set1_pd(-std::numeric_limits<double>::infinity()), before, skipping);
  return a;
}

// The slot of a window index counted from the corner's slot, x (a whole
// number) in 0..2n-1: x - n past n-1. Other lanes are cleared in `exact`
// (the walk takes the remainder for them).
STRIDEMAP_AVX2_INLINE __m256d slot4(__m256d x, __m256d n, __m256d& exact) {
  const __m256d in_range = _mm256_and_pd(_mm256_cmp_pd(x, _mm256_setzero_pd(), _CMP_GE_OQ),
                                         lt4(x, _mm256_add_pd(n, n)));
  exact = _mm256_and_pd(exact, in_range);
  return _mm256_blendv_pd(x, _mm256_sub_pd(x, n), _mm256_cmp_pd(x, n, _CMP_GE_OQ));
}

// The start of the walks of one vector's lanes, from the values just
// stored for them.
STRIDEMAP_AVX2_INLINE void screen_walk_start(const ScreenScan& c, ScreenBatch& b, std::size_t k) {
  const __m256d t = _mm256_load_pd(b.t_skip + k);
  const __m256d skip = _mm256_cmp_pd(t, _mm256_setzero_pd(), _CMP_GT_OQ);
  __m256d exact = _mm256_castsi256_pd(_mm256_set1_epi64x(-1));
  const AxisStart x = axis_start4(_mm256_set1_pd(c.ox), _mm256_set1_pd(c.origin_cell_x), _mm256_load_pd(b.dx_cells + k),
                                  _mm256_load_pd(b.inverse_dx + k), t, skip, exact);
  const AxisStart y = axis_start4(_mm256_set1_pd(c.oy), _mm256_set1_pd(c.origin_cell_y), _mm256_load_pd(b.dy_cells + k),
                                  _mm256_load_pd(b.inverse_dy + k), t, skip, exact);
  // std::max(0.0, std::max(before_x, before_y)) where skipping, else 0.
  const __m256d t_in = _mm256_and_pd(_mm256_max_pd(_mm256_max_pd(y.before, x.before), _mm256_setzero_pd()), skip);
  const __m256d n = _mm256_set1_pd(static_cast<double>(c.n));
  const __m256d i = _mm256_sub_pd(x.index, _mm256_set1_pd(c.corner_x));
  const __m256d j = _mm256_sub_pd(y.index, _mm256_set1_pd(c.corner_y));
  const __m256d row = slot4(_mm256_add_pd(_mm256_set1_pd(c.slot_x0), i), n, exact);
  const __m256d column = slot4(_mm256_add_pd(_mm256_set1_pd(c.slot_y0), j), n, exact);
  _mm256_store_pd(b.start_i + k, i);
  _mm256_store_pd(b.start_j + k, j);
  _mm256_store_pd(b.start_row + k, _mm256_mul_pd(row, n));
  _mm256_store_pd(b.start_column + k, column);
  _mm256_store_pd(b.boundary_x + k, x.boundary);
  _mm256_store_pd(b.boundary_y + k, y.boundary);
  _mm256_store_pd(b.next_x + k, x.next);
  _mm256_store_pd(b.next_y + k, y.next);
  _mm256_store_pd(b.t_in + k, t_in);
  b.started[k / 4] = static_cast<std::uint8_t>(_mm256_movemask_pd(exact));
}

__attribute__((target("avx2"))) void screen_avx2(const ScreenScan& c, ScreenBatch& b, std::size_t count) {
  for (std::size_t k = 0; k < count; k += 4) {
    ScreenLanes l;
    screen_start(c, b, k, l);
    for (int round = 0; round < 4 && screen_active(l); ++round) screen_round(c, l);
    const int settled = _mm256_movemask_pd(l.settled), left = _mm256_movemask_pd(l.left);
    b.settled[k / 4] = static_cast<std::uint8_t>(settled);
    b.left[k / 4] = static_cast<std::uint8_t>(left);
    // Most vectors are settled whole: nothing of theirs is read again.
    if ((settled | left) != 15) {
      screen_store(l, b, k);
      screen_walk_start(c, b, k);
    }
  }
}

}  // namespace

bool screen_available() { return cpu_has_avx2(); }

void screen(const ScreenScan& scan, ScreenBatch& batch, std::size_t count) { screen_avx2(scan, batch, count); }

#else

bool screen_available() { return false; }

// Never called (screen_available() is false): every beam left to the walk's own tests.
void screen(const ScreenScan&, ScreenBatch& batch, std::size_t count) {
  for (std::size_t v = 0; v < count; v += 4) {
    batch.settled[v / 4] = 0;
    batch.left[v / 4] = 15;
    batch.started[v / 4] = 0;
  }
}

#endif

}  // namespace stridemap::visibility
