// The sort-free weighted median of WeightedMedianFill for radius 1 and 2
// (8 and 24 neighbours), eight lanes a vector. With exact sums the weighted
// quantile q is the smallest value v whose weight of values at or below v
// reaches q of the total, in any order of addition; ties share that weight,
// and with no zero (+0 against -0) and no NaN among the values equal values
// have equal bits, so the result is the sorted walk's (weighted_median_fill.cpp).
//
// A window's neighbours sit in the lanes in visiting order (rows di = -w..w,
// in each dj = -w..w, the centre left out), 8 or 24 lanes: 1 or 3 vectors
// made by blending unaligned row loads, no gather per neighbour. An unknown
// neighbour is a lane with value +inf and weight 0: it adds nothing below any
// value and is never the smallest value that reaches a quantile unless a
// known +inf is. Known cells and zeros or NaN come from per-cell row bits.
#include "fill_exact_windows.hpp"

#include <bit>
#include <cstring>
#include <limits>

// x86-64's baseline (SSE2) holds four floats a vector; where the CPU has
// AVX2 a copy built for it runs (eight lanes a vector), chosen at run time.
// Not target_clones: the baseline copy needs other code for its
// comparisons (bits_where_at_most). No FMA is enabled: every operation
// rounds as in the baseline copy.
#if defined(__x86_64__) && defined(__GNUC__) && !defined(__clang__) && !defined(STRIDEMAP_NO_AVX2_COPIES)
#define STRIDEMAP_FILL_AVX2 1
#endif

#if defined(__clang__)
#define STRIDEMAP_SHUFFLE8(a, ...) __builtin_shufflevector(a, a, __VA_ARGS__)
#else
#define STRIDEMAP_SHUFFLE8(a, ...) __builtin_shuffle(a, Lanes8{__VA_ARGS__})
#endif

namespace stridemap::fill_detail {
namespace {

using Floats8 = float __attribute__((vector_size(32)));
using Lanes8 = std::int32_t __attribute__((vector_size(32)));

#define STRIDEMAP_INLINE inline __attribute__((always_inline))

STRIDEMAP_INLINE Floats8 load8(const float* at) {
  Floats8 v;
  std::memcpy(&v, at, sizeof v);
  return v;
}

// Lane k from b where bit k of Mask is set, else from a: a blend with a
// constant. With 32-byte vectors one blend instruction (a shuffle of the
// two vectors); otherwise by bits (a general shuffle of eight lanes goes
// through memory without AVX).
template <unsigned Mask, bool kWide>
STRIDEMAP_INLINE Floats8 select8(Floats8 a, Floats8 b) {
  constexpr auto lane = [](unsigned k) { return static_cast<std::int32_t>(Mask & (1u << k) ? k + 8 : k); };
  if constexpr (kWide) {
#if defined(__clang__)
    return __builtin_shufflevector(a, b, lane(0), lane(1), lane(2), lane(3), lane(4), lane(5), lane(6), lane(7));
#else
    return __builtin_shuffle(a, b, Lanes8{lane(0), lane(1), lane(2), lane(3), lane(4), lane(5), lane(6), lane(7)});
#endif
  } else {
    const Lanes8 take_b = {Mask & 1 ? -1 : 0,  Mask & 2 ? -1 : 0,  Mask & 4 ? -1 : 0,  Mask & 8 ? -1 : 0,
                           Mask & 16 ? -1 : 0, Mask & 32 ? -1 : 0, Mask & 64 ? -1 : 0, Mask & 128 ? -1 : 0};
    return reinterpret_cast<Floats8>((reinterpret_cast<Lanes8>(a) & ~take_b) |
                                     (reinterpret_cast<Lanes8>(b) & take_b));
  }
}

// The two comparisons of the kernel producing masks. GCC compares eight
// lanes one at a time where the target has no 32-byte vectors (SSE2), so
// there the halves are compared as four-lane vectors.
using Floats4 = float __attribute__((vector_size(16)));
using Lanes4 = std::int32_t __attribute__((vector_size(16)));

// (x <= v) & bits: `bits` where x <= v, else zero.
template <bool kWide>
STRIDEMAP_INLINE Floats8 bits_where_at_most(Floats8 x, Floats8 v, Lanes8 bits) {
  if constexpr (kWide) {
    return reinterpret_cast<Floats8>(reinterpret_cast<Lanes8>(x <= v) & bits);
  } else {
    Floats4 xh[2], vh[2];
    Lanes4 bh[2], out[2];
    std::memcpy(xh, &x, sizeof xh);
    std::memcpy(vh, &v, sizeof vh);
    std::memcpy(bh, &bits, sizeof bh);
    for (int h = 0; h < 2; ++h) out[h] = reinterpret_cast<Lanes4>(xh[h] <= vh[h]) & bh[h];
    Floats8 r;
    std::memcpy(&r, out, sizeof r);
    return r;
  }
}

// below >= threshold ? v : otherwise, lane by lane.
template <bool kWide>
STRIDEMAP_INLINE Floats8 where_at_least(Floats8 below, float threshold, Floats8 v, Floats8 otherwise) {
  if constexpr (kWide) {
    return below >= threshold ? v : otherwise;
  } else {
    Floats4 bh[2], vh[2], oh[2], out[2];
    std::memcpy(bh, &below, sizeof bh);
    std::memcpy(vh, &v, sizeof vh);
    std::memcpy(oh, &otherwise, sizeof oh);
    for (int h = 0; h < 2; ++h) {
      const Lanes4 m = reinterpret_cast<Lanes4>(bh[h] >= threshold);
      out[h] = reinterpret_cast<Floats4>((reinterpret_cast<Lanes4>(vh[h]) & m) | (reinterpret_cast<Lanes4>(oh[h]) & ~m));
    }
    Floats8 r;
    std::memcpy(&r, out, sizeof r);
    return r;
  }
}

// The window's cells of padded array `a` around cell q, in visiting order.
template <int W, bool kWide>
STRIDEMAP_INLINE void gather(const float* a, std::size_t q, std::size_t p, Floats8* out) {
  if constexpr (W == 1) {
    const float *r0 = a + q - p, *r1 = a + q, *r2 = a + q + p;
    const Floats8 x = select8<0x08, kWide>(load8(r0 - 1), load8(r1 - 4));
    const Floats8 y = select8<0xe0, kWide>(load8(r1 - 3), load8(r2 - 6));
    out[0] = select8<0xf0, kWide>(x, y);
  } else {
    const float *r0 = a + q - 2 * p, *r1 = a + q - p, *r2 = a + q, *r3 = a + q + p, *r4 = a + q + 2 * p;
    out[0] = select8<0xe0, kWide>(load8(r0 - 2), load8(r1 - 7));
    const Floats8 x = select8<0x0c, kWide>(load8(r1 + 1), load8(r2 - 4));
    const Floats8 y = select8<0xc0, kWide>(load8(r2 - 3), load8(r3 - 8));
    out[1] = select8<0xf0, kWide>(x, y);
    out[2] = select8<0xf8, kWide>(load8(r3), load8(r4 - 5));
  }
}

STRIDEMAP_INLINE float lane_sum(Floats8 x) {
  x += STRIDEMAP_SHUFFLE8(x, 4, 5, 6, 7, 0, 1, 2, 3);
  x += STRIDEMAP_SHUFFLE8(x, 2, 3, 0, 1, 6, 7, 4, 5);
  return x[0] + x[1];
}

STRIDEMAP_INLINE Floats8 min8(Floats8 a, Floats8 b) { return a < b ? a : b; }

STRIDEMAP_INLINE float lane_min(Floats8 x) {
  x = min8(x, STRIDEMAP_SHUFFLE8(x, 4, 5, 6, 7, 0, 1, 2, 3));
  x = min8(x, STRIDEMAP_SHUFFLE8(x, 2, 3, 0, 1, 6, 7, 4, 5));
  return x[0] < x[1] ? x[0] : x[1];
}

// quadrant_of in weighted_median_fill.cpp, the same split of the window.
constexpr int quadrant(int di, int dj) {
  if (di > 0 && dj >= 0) return 0;
  if (di <= 0 && dj > 0) return 1;
  if (di < 0 && dj <= 0) return 2;
  return 3;
}

// Bits of the window's known pattern (bit (di + w) * (2w + 1) + dj + w) in
// each quadrant.
template <int W>
constexpr std::uint32_t quadrant_bits(int q) {
  std::uint32_t bits = 0;
  for (int di = -W; di <= W; ++di) {
    for (int dj = -W; dj <= W; ++dj) {
      if ((di != 0 || dj != 0) && quadrant(di, dj) == q) bits |= 1u << ((di + W) * (2 * W + 1) + dj + W);
    }
  }
  return bits;
}

// A column is below n < 2^31: its top bit flags a window holding a zero or NaN.
constexpr std::uint32_t kSpecialColumn = 1u << 31;

// The row's unknown cells that pass the admission tests (enough known
// neighbours in enough quadrants), listed in in.columns; their count.
template <int W>
STRIDEMAP_INLINE std::size_t admit_row(const WindowInput& in, std::size_t row_start) {
  constexpr int kSide = 2 * W + 1;
  constexpr std::uint32_t kField = (1u << kSide) - 1;
  constexpr std::uint32_t kQuadrant[4] = {quadrant_bits<W>(0), quadrant_bits<W>(1), quadrant_bits<W>(2),
                                          quadrant_bits<W>(3)};
  const std::size_t p = in.pitch, n = in.n;
  // The row's unknown cells listed first, without a branch: measured or
  // not is as random as the map, a loop over the list is not.
  std::size_t unknown = 0;
  for (std::size_t j = 0; j < n; j += 8) {
    const unsigned in_row = n - j >= 8 ? 0xffu : (1u << (n - j)) - 1;  // columns past n are not listed
    unknown = append_set_flags(~flags_of_bytes(in.known + row_start + j) & in_row, static_cast<std::uint32_t>(j),
                               in.columns, unknown);
  }
  // The admission tests (enough known neighbours in enough quadrants),
  // the passing cells kept in the same list (never ahead of the reading),
  // each with a flag (kSpecialColumn) for a zero or NaN in its window.
  std::size_t admitted = 0;
  for (std::size_t u = 0; u < unknown; ++u) {
    const std::size_t j = in.columns[u];
    const std::size_t q = row_start + j;
    std::uint32_t known = 0, rows = 0;
    for (int di = -W; di <= W; ++di) {
      const std::uint32_t row = in.row_bits[q + static_cast<std::size_t>(di) * p];
      known |= (row & kField) << ((di + W) * kSide);
      rows |= row;
    }
    const int count = std::popcount(known);
    const int quadrants = ((known & kQuadrant[0]) != 0) + ((known & kQuadrant[1]) != 0) +
                          ((known & kQuadrant[2]) != 0) + ((known & kQuadrant[3]) != 0);
    in.columns[admitted] = static_cast<std::uint32_t>(j) | ((rows >> kSpecialShift) != 0 ? kSpecialColumn : 0u);
    admitted += ((count >= in.min_known) & (quadrants >= in.min_quadrants)) ? 1 : 0;
  }
  return admitted;
}

// The second pass for one window: its quartiles from the weights below each
// lane's value; the median into in.result, or the window listed for the
// sorted walk when a zero or NaN is in it. The walks listed so far.
template <int kBlocks, bool kWide>
STRIDEMAP_INLINE std::size_t take_quantiles(const WindowInput& in, std::size_t i, std::uint32_t column, float total,
                                            const Floats8* values, const Floats8* below_values, std::size_t walks) {
  constexpr float kInf = std::numeric_limits<float>::infinity();
  const std::size_t j = column & ~kSpecialColumn;
  const bool special = (column & kSpecialColumn) != 0;
  const bool positive = total > 0.0f;
  // A zero or NaN among the values: the sorted walk decides (the
  // result below is not used).
  const std::size_t local = i * in.n + j;
  in.walk_cells[walks] = static_cast<std::uint32_t>(local);
  in.walk_totals[walks] = total;
  walks += (positive & special) ? 1 : 0;
  const float at_quarter = 0.25f * total, at_half = 0.5f * total, at_three_quarters = 0.75f * total;
  const Floats8 none = {kInf, kInf, kInf, kInf, kInf, kInf, kInf, kInf};
  Floats8 lq = none, lh = none, l3 = none;
  for (int b = 0; b < kBlocks; ++b) {
    const Floats8 below = below_values[b], v = values[b];
    lq = min8(lq, where_at_least<kWide>(below, at_quarter, v, none));
    lh = min8(lh, where_at_least<kWide>(below, at_half, v, none));
    l3 = min8(l3, where_at_least<kWide>(below, at_three_quarters, v, none));
  }
  const float half = lane_min(lh);
  const bool steep = in.test_spread & (lane_min(l3) - lane_min(lq) > in.spread);
  // result holds NaN (leave unknown) until a value is found.
  const std::size_t slot = in.slot[local];
  in.result[slot] = (positive & !special & !steep) ? half : in.result[slot];
  return walks;
}

// kWide: built for a target with 32-byte vectors (AVX2, no FMA: every
// operation rounds as in the baseline build).
template <int W, bool kWide>
STRIDEMAP_INLINE std::size_t fill_exact_windows(const WindowInput& in) {
  constexpr int kBlocks = W == 1 ? 1 : 3;
  const std::size_t p = in.pitch, n = in.n;
  const float nf = in.near_factor;
  // The near factor on the lanes of the 8 nearest neighbours, 1 elsewhere
  // (certainty * 1.0f is the certainty: the far weight as always).
  Floats8 factor[kBlocks];
  if constexpr (W == 1) {
    factor[0] = Floats8{nf, nf, nf, nf, nf, nf, nf, nf};
  } else {
    factor[0] = Floats8{1, 1, 1, 1, 1, 1, nf, nf};
    factor[1] = Floats8{nf, 1, 1, nf, nf, 1, 1, nf};
    factor[2] = Floats8{nf, nf, 1, 1, 1, 1, 1, 1};
  }
  std::size_t walks = 0;
  alignas(32) float values[8 * kBlocks], weights[8 * kBlocks];
  // A chunk of windows between the two passes below (6 kB at radius 2).
  constexpr std::size_t kChunk = 32;
  Floats8 chunk_values[kChunk][kBlocks], chunk_below[kChunk][kBlocks];
  float totals[kChunk];
  for (std::size_t i = 0; i < n; ++i) {
    const std::size_t row_start = (i + in.margin) * p + in.margin;
    const std::size_t admitted = admit_row<W>(in, row_start);
    // The medians in chunks, each in two passes without a branch: first
    // the weights below every lane's value, then the quantiles. The second
    // pass's chain of dependent steps (threshold, minimum across lanes,
    // spread) then overlaps from one window to the next instead of holding
    // up the first pass's independent work.
    for (std::size_t chunk = 0; chunk < admitted; chunk += kChunk) {
      const std::size_t chunk_size = admitted - chunk < kChunk ? admitted - chunk : kChunk;
      for (std::size_t c = 0; c < chunk_size; ++c) {
        const std::size_t j = in.columns[chunk + c] & ~kSpecialColumn;
        const std::size_t q = row_start + j;
        Floats8 v[kBlocks], wt[kBlocks];
        gather<W, kWide>(in.value, q, p, v);
        gather<W, kWide>(in.weight, q, p, wt);
        Floats8 sum = {};
        for (int b = 0; b < kBlocks; ++b) {
          wt[b] *= factor[b];
          sum += wt[b];
        }
        // Whole sixteenths below 2^24 of them: exact in any order, the
        // value the sorted walk's sum in visiting order has.
        totals[c] = lane_sum(sum);
        std::memcpy(values, v, sizeof values);
        std::memcpy(weights, wt, sizeof weights);
        // Each compared neighbour below is broadcast from memory (a load);
        // without this barrier GCC takes it from the registers with two
        // shuffles each, on the one port the comparisons also need.
#if defined(__GNUC__)
        __asm__ __volatile__("" : : "r"(values), "r"(weights) : "memory");
#endif
        // The weight at or below each lane's value, for all lanes at once,
        // one compared neighbour at a time; two partial sums a vector
        // (exact sums: any order), so that the additions do not wait on
        // each other.
        Floats8 below[kBlocks] = {}, below_odd[kBlocks] = {};
#pragma GCC unroll 24
        for (int m = 0; m < 8 * kBlocks; m += 2) {
          const float x0 = values[m], x1 = values[m + 1];
          const std::int32_t y0 = std::bit_cast<std::int32_t>(weights[m]);
          const std::int32_t y1 = std::bit_cast<std::int32_t>(weights[m + 1]);
          const Floats8 value0 = {x0, x0, x0, x0, x0, x0, x0, x0}, value1 = {x1, x1, x1, x1, x1, x1, x1, x1};
          const Lanes8 weight0 = {y0, y0, y0, y0, y0, y0, y0, y0}, weight1 = {y1, y1, y1, y1, y1, y1, y1, y1};
          for (int b = 0; b < kBlocks; ++b) {
            below[b] += bits_where_at_most<kWide>(value0, v[b], weight0);
            below_odd[b] += bits_where_at_most<kWide>(value1, v[b], weight1);
          }
        }
        for (int b = 0; b < kBlocks; ++b) {
          chunk_values[c][b] = v[b];
          chunk_below[c][b] = below[b] + below_odd[b];
        }
      }
      for (std::size_t c = 0; c < chunk_size; ++c) {
        walks = take_quantiles<kBlocks, kWide>(in, i, in.columns[chunk + c], totals[c], chunk_values[c], chunk_below[c],
                                               walks);
      }
    }
  }
  return walks;
}

#if defined(STRIDEMAP_FILL_AVX2)
__attribute__((target("avx2,popcnt"))) std::size_t radius1_avx2(const WindowInput& in) {
  return fill_exact_windows<1, true>(in);
}
__attribute__((target("avx2,popcnt"))) std::size_t radius2_avx2(const WindowInput& in) {
  return fill_exact_windows<2, true>(in);
}
#endif

#if defined(STRIDEMAP_FILL_AVX2)
// Whether this CPU runs the AVX2 copy (asked once).
bool use_avx2() {
  // popcnt (the admission's count) comes with every AVX2 CPU; asked anyway.
  static const bool avx2 = __builtin_cpu_supports("avx2") && __builtin_cpu_supports("popcnt");
  return avx2;
}
#endif

}  // namespace

std::size_t fill_exact_windows_radius1(const WindowInput& in) {
#if defined(STRIDEMAP_FILL_AVX2)
  if (use_avx2()) return radius1_avx2(in);
#endif
  return fill_exact_windows<1, false>(in);
}
std::size_t fill_exact_windows_radius2(const WindowInput& in) {
#if defined(STRIDEMAP_FILL_AVX2)
  if (use_avx2()) return radius2_avx2(in);
#endif
  return fill_exact_windows<2, false>(in);
}

}  // namespace stridemap::fill_detail

