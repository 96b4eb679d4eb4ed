#include "stridemap/core/foothold_changes.hpp"

#include <algorithm>
#include <bit>
#include <cmath>
#include <cstring>

#include "foothold_cells.hpp"

#if defined(__x86_64__) && defined(__GNUC__) && !defined(__clang__) && defined(__linux__) && \
    !defined(STRIDEMAP_NO_AVX2_COPIES)
#define STRIDEMAP_CHANGES_AVX2 1
#include <immintrin.h>
#endif

namespace stridemap {
namespace {

// The maximal runs of set bits along a row given in chunks of up to 64
// columns: the passes below first gather a chunk's cells as bits (a loop
// without branches), then mark each run once, however many chunks it spans.
// A chunk's cells flagged one byte each (0 or 1, up to 64 of them, with
// room for 8 more) as bits: a byte loop vectorises where a shift and an OR
// per cell would not, and eight bytes become eight bits by one multiply
// (byte b lands in bit 56 + b; the other products fall below bit 56 at
// distinct places, or past bit 63, so none carries into those eight).
std::uint64_t bits_of_flags(std::uint8_t* flags, int count) {
  std::memset(flags + count, 0, 8);
  std::uint64_t bits = 0;
  for (int k = 0; k < count; k += 8) {
    std::uint64_t eight;
    std::memcpy(&eight, flags + k, sizeof eight);
    bits |= (eight * 0x0102040810204080ull) >> 56 << k;
  }
  return bits;
}

struct RowRuns {
  bool in_run = false;
  std::int64_t run = 0;  ///< the open run's first column

  /// `bits` (bit k: column y + k; none at or past `count`); mark(first,
  /// last) for each run that ends within the chunk.
  template <class Mark>
  void add(std::uint64_t bits, int count, std::int64_t y, Mark&& mark) {
    for (int k = 0; k < count;) {
      const std::uint64_t ahead = bits >> k;
      if (in_run) {
        const int ones = std::countr_one(ahead);
        if (k + ones >= count) return;  // it runs on into the next chunk
        mark(run, y + k + ones - 1);
        in_run = false;
        k += ones;
      } else {
        if (ahead == 0) return;
        k += std::countr_zero(ahead);
        run = y + k;
        in_run = true;
      }
    }
  }
  /// The row ends after column `last`.
  template <class Mark>
  void end(std::int64_t last, Mark&& mark) {
    if (in_run) mark(run, last);
    in_run = false;
  }
};

/// What see_changes() compares a chunk of a row's cells by (contiguous in
/// storage, from slot s0).
struct CellCompare {
  const float* elevation;
  const std::uint8_t* state;
  const float* certainty;
  float* seen_elevation;
  float* seen_certainty;
  std::int32_t* seen_edge2;
  double full_certainty;
};

/// Per cell k of a chunk: its elevation or known-ness changed; its
/// known-ness did (the edge distance is NaN exactly where the cell is
/// unknown); it entered the window unknown and is known now (no edge
/// distance to show yet); its score is to be redone (its known-ness or its
/// certainty factor changed).
struct ChunkChanges {
  std::uint64_t changed = 0, flipped = 0, unseen_known = 0, scores = 0;
};

// The seen elevations and certainties become the current ones.
void compare_chunk(const CellCompare& c, std::size_t s0, int count, ChunkChanges& out) {
  std::uint64_t certainty_changed = 0;
  for (int k = 0; k < count; ++k) {
    const std::size_t s = s0 + static_cast<std::size_t>(k);
    const float elevation_now = foothold::known_elevation(c.elevation, c.state, s);
    const float before = c.seen_elevation[s];
    c.seen_elevation[s] = elevation_now;
    const bool differs = !foothold::same_bits(elevation_now, before);
    const bool known_now = !std::isnan(elevation_now);
    out.changed |= static_cast<std::uint64_t>(differs) << k;
    out.flipped |= static_cast<std::uint64_t>(known_now == std::isnan(before)) << k;
    out.unseen_known |=
        static_cast<std::uint64_t>(differs && known_now && c.seen_edge2[s] == FootholdChanges::kEdgeUnknown) << k;
    certainty_changed |= static_cast<std::uint64_t>(!foothold::same_bits(c.certainty[s], c.seen_certainty[s])) << k;
  }
  // The same certainty, the same factor: most cells skip both divisions.
  out.scores |= out.flipped;
  for (std::uint64_t rest = certainty_changed; rest != 0; rest &= rest - 1) {
    const int k = std::countr_zero(rest);
    const std::size_t s = s0 + static_cast<std::size_t>(k);
    const float now = c.certainty[s], before = c.seen_certainty[s];
    // Both at or past full certainty: the same factor, 1, without dividing.
    const bool both_full = now >= c.full_certainty && before >= c.full_certainty;
    if (!both_full && !foothold::same_bits(foothold::certainty_factor(now, c.full_certainty),
                                           foothold::certainty_factor(before, c.full_certainty))) {
      out.scores |= std::uint64_t{1} << k;
    }
    c.seen_certainty[s] = now;
  }
}

#ifdef STRIDEMAP_CHANGES_AVX2
bool changes_avx2_available() {
  static const bool has = __builtin_cpu_supports("avx2");
  return has;
}

// Eight 32-bit lanes from p; with Partial, only those in the chunk (the
// others read as 0 and never fault).
template <bool Partial>
__attribute__((target("avx2"), always_inline)) inline __m256i chunk_lanes(const void* p, __m256i in_chunk) {
  const auto* at = static_cast<const int*>(p);
  if constexpr (Partial) return _mm256_maskload_epi32(at, in_chunk);
  return _mm256_loadu_si256(reinterpret_cast<const __m256i*>(at));
}
// Bit k: lane k's mask set.
__attribute__((target("avx2"), always_inline)) inline std::uint64_t lane_bits(__m256i m) {
  return static_cast<unsigned>(_mm256_movemask_ps(_mm256_castsi256_ps(m)));
}

// certainty_factor()'s clamp of a quotient, as std::clamp compares: NaN
// and -0 pass through unchanged.
__attribute__((target("avx2"), always_inline)) inline __m256i factor_of(__m256d quotient) {
  const __m256d zero = _mm256_setzero_pd(), one = _mm256_set1_pd(1.0);
  const __m256d above = _mm256_blendv_pd(quotient, one, _mm256_cmp_pd(one, quotient, _CMP_LT_OQ));
  return _mm256_castpd_si256(_mm256_blendv_pd(above, zero, _mm256_cmp_pd(quotient, zero, _CMP_LT_OQ)));
}

// Bit k: lane k's certainty factor the same, now and before.
__attribute__((target("avx2"), always_inline)) inline std::uint64_t factors_same(__m128 now, __m128 before,
                                                                                 __m256d full_certainty) {
  const __m256i a = factor_of(_mm256_div_pd(_mm256_cvtps_pd(now), full_certainty));
  const __m256i b = factor_of(_mm256_div_pd(_mm256_cvtps_pd(before), full_certainty));
  return static_cast<unsigned>(_mm256_movemask_pd(_mm256_castsi256_pd(_mm256_cmpeq_epi64(a, b))));
}

// Lanes of the cells that are not known (foothold::known()): the unknown
// state, or an elevation with every exponent bit set (not finite).
template <bool Partial>
__attribute__((target("avx2"), always_inline)) inline __m256i unknown_lanes(const CellCompare& c, std::size_t s,
                                                                            int lanes, __m256i elevation) {
  const __m256i exponent = _mm256_set1_epi32(0x7f800000);
  const __m256i unknown_state = _mm256_set1_epi32(static_cast<int>(CellState::unknown));
  std::uint64_t states = 0;
  if (!Partial) {
    std::memcpy(&states, c.state + s, sizeof states);
  } else if (s + static_cast<std::size_t>(lanes) >= 8) {
    // The eight bytes that end with the chunk's last: none past the layer.
    std::memcpy(&states, c.state + s + static_cast<std::size_t>(lanes) - 8, sizeof states);
    states >>= 8 * (8 - lanes);
  } else {
    for (int b = 0; b < lanes; ++b) states |= std::uint64_t{c.state[s + static_cast<std::size_t>(b)]} << (8 * b);
  }
  const __m256i state = _mm256_cvtepu8_epi32(_mm_cvtsi64_si128(static_cast<long long>(states)));
  return _mm256_or_si256(_mm256_cmpeq_epi32(state, unknown_state),
                         _mm256_cmpeq_epi32(_mm256_and_si256(elevation, exponent), exponent));
}

template <bool Partial>
__attribute__((target("avx2"), always_inline)) inline void store_lanes(void* p, __m256i in_chunk, __m256i v) {
  if constexpr (Partial) {
    _mm256_maskstore_epi32(static_cast<int*>(p), in_chunk, v);
  } else {
    _mm256_storeu_si256(static_cast<__m256i*>(p), v);
  }
}

// compare_chunk() eight cells a lane each, where the CPU has AVX2 (chosen
// at run time): the scalar loop's compares, branch-free, are ~80
// instructions a cell. Every test is on bits (a float compare would make
// NaN unequal to itself and -0 equal to 0), so the masks match the scalar
// loop's exactly. The cells past the last eight take masked loads and
// stores rather than the scalar loop: chunks are short, their tails a
// large share of the cells.
template <bool Partial>
__attribute__((target("avx2"), always_inline)) inline void compare_eight(const CellCompare& c, std::size_t s, int k,
                                                                         int lanes, ChunkChanges& out) {
  const __m256i exponent = _mm256_set1_epi32(0x7f800000);
  const __m256i magnitude = _mm256_set1_epi32(0x7fffffff);
  const __m256i nan = _mm256_set1_epi32(std::bit_cast<std::int32_t>(foothold::kNaN));
  const __m256i edge_unknown = _mm256_set1_epi32(FootholdChanges::kEdgeUnknown);
  const __m256i in_chunk = _mm256_cmpgt_epi32(_mm256_set1_epi32(lanes), _mm256_setr_epi32(0, 1, 2, 3, 4, 5, 6, 7));
  const __m256i elevation = chunk_lanes<Partial>(c.elevation + s, in_chunk);
  const __m256i unknown = unknown_lanes<Partial>(c, s, lanes, elevation);
  const __m256i now = _mm256_blendv_epi8(elevation, nan, unknown);
  const __m256i before = chunk_lanes<Partial>(c.seen_elevation + s, in_chunk);
  if (Partial) {
    _mm256_maskstore_epi32(reinterpret_cast<int*>(c.seen_elevation + s), in_chunk, now);
  } else {
    _mm256_storeu_si256(reinterpret_cast<__m256i*>(c.seen_elevation + s), now);
  }
  const __m256i same = _mm256_cmpeq_epi32(now, before);
  const __m256i before_nan = _mm256_cmpgt_epi32(_mm256_and_si256(before, magnitude), exponent);
  const __m256i unseen =
      _mm256_andnot_si256(_mm256_or_si256(same, unknown),
                          _mm256_cmpeq_epi32(chunk_lanes<Partial>(c.seen_edge2 + s, in_chunk), edge_unknown));
  // The certainty factors, four lanes of doubles at a time, divided and
  // clamped as certainty_factor() does: the same roundings, the same bits.
  const __m256i certainty = chunk_lanes<Partial>(c.certainty + s, in_chunk);
  const __m256i seen_certainty = chunk_lanes<Partial>(c.seen_certainty + s, in_chunk);
  if (Partial) {
    _mm256_maskstore_epi32(reinterpret_cast<int*>(c.seen_certainty + s), in_chunk, certainty);
  } else {
    _mm256_storeu_si256(reinterpret_cast<__m256i*>(c.seen_certainty + s), certainty);
  }
  const __m256d full = _mm256_set1_pd(c.full_certainty);
  const __m256 now_f = _mm256_castsi256_ps(certainty), before_f = _mm256_castsi256_ps(seen_certainty);
  const std::uint64_t factor_changed =
      ~(factors_same(_mm256_castps256_ps128(now_f), _mm256_castps256_ps128(before_f), full) |
        factors_same(_mm256_extractf128_ps(now_f, 1), _mm256_extractf128_ps(before_f, 1), full) << 4);
  const std::uint64_t valid = Partial ? (std::uint64_t{1} << lanes) - 1 : 0xff;
  out.changed |= (~lane_bits(same) & valid) << k;
  // Known now where it was NaN, or unknown now where it was not.
  const __m256i flipped = _mm256_xor_si256(unknown, before_nan);
  out.flipped |= (lane_bits(flipped) & valid) << k;
  out.unseen_known |= (lane_bits(unseen) & valid) << k;
  out.scores |= ((lane_bits(flipped) | factor_changed) & valid) << k;
}

__attribute__((target("avx2"))) ChunkChanges compare_chunk_avx2(const CellCompare& c, std::size_t s0, int count) {
  ChunkChanges out;
  int k = 0;
  for (; k + 8 <= count; k += 8) compare_eight<false>(c, s0 + static_cast<std::size_t>(k), k, 8, out);
  if (k < count) compare_eight<true>(c, s0 + static_cast<std::size_t>(k), k, count - k, out);
  return out;
}

// see_all()'s pass over a chunk, eight cells a lane each where the CPU has
// AVX2: the seen values become the current ones; with `mark`, every edge
// distance is to be searched for. Returns the known cells' bits.
template <bool Partial>
__attribute__((target("avx2"), always_inline)) inline std::uint64_t see_eight(const CellCompare& c, std::size_t s,
                                                                              int lanes, bool mark) {
  const __m256i nan = _mm256_set1_epi32(std::bit_cast<std::int32_t>(foothold::kNaN));
  const __m256i in_chunk = _mm256_cmpgt_epi32(_mm256_set1_epi32(lanes), _mm256_setr_epi32(0, 1, 2, 3, 4, 5, 6, 7));
  const __m256i elevation = chunk_lanes<Partial>(c.elevation + s, in_chunk);
  const __m256i unknown = unknown_lanes<Partial>(c, s, lanes, elevation);
  store_lanes<Partial>(c.seen_elevation + s, in_chunk, _mm256_blendv_epi8(elevation, nan, unknown));
  store_lanes<Partial>(c.seen_certainty + s, in_chunk, chunk_lanes<Partial>(c.certainty + s, in_chunk));
  if (!mark) return 0;
  store_lanes<Partial>(c.seen_edge2 + s, in_chunk, _mm256_set1_epi32(FootholdChanges::kEdgeUnknown));
  const std::uint64_t valid = Partial ? (std::uint64_t{1} << lanes) - 1 : 0xff;
  return ~lane_bits(unknown) & valid;
}

__attribute__((target("avx2"))) std::uint64_t see_chunk_avx2(const CellCompare& c, std::size_t s0, int count,
                                                             bool mark) {
  std::uint64_t known = 0;
  int k = 0;
  for (; k + 8 <= count; k += 8) known |= see_eight<false>(c, s0 + static_cast<std::size_t>(k), 8, mark) << k;
  if (k < count) known |= see_eight<true>(c, s0 + static_cast<std::size_t>(k), count - k, mark) << k;
  return known;
}

// see_left()'s flags of a chunk as bits, eight cells a lane each where the
// CPU has AVX2: known (a seen elevation not NaN) and an edge (a seen
// squared edge distance of 0).
__attribute__((target("avx2"))) void left_chunk_avx2(const float* elevation, const std::int32_t* edge2, int count,
                                                     std::uint64_t& known, std::uint64_t& edge) {
  const __m256i exponent = _mm256_set1_epi32(0x7f800000);
  const __m256i magnitude = _mm256_set1_epi32(0x7fffffff);
  const __m256i lane = _mm256_setr_epi32(0, 1, 2, 3, 4, 5, 6, 7);
  known = edge = 0;
  for (int k = 0; k < count; k += 8) {
    const __m256i in_chunk = _mm256_cmpgt_epi32(_mm256_set1_epi32(count - k), lane);
    const __m256i e = _mm256_maskload_epi32(reinterpret_cast<const int*>(elevation + k), in_chunk);
    const __m256i d = _mm256_maskload_epi32(edge2 + k, in_chunk);
    const __m256i nan = _mm256_cmpgt_epi32(_mm256_and_si256(e, magnitude), exponent);
    known |= lane_bits(_mm256_andnot_si256(nan, in_chunk)) << k;
    edge |= lane_bits(_mm256_and_si256(_mm256_cmpeq_epi32(d, _mm256_setzero_si256()), in_chunk)) << k;
  }
}
#endif

}  // namespace

FootholdChanges::FootholdChanges(int cells_per_side, std::int32_t none2, double full_certainty_in)
    : n(cells_per_side), full_certainty(full_certainty_in) {
  const auto cells = static_cast<std::size_t>(n);
  pending.resize(n);
  seen_elevation.assign(cells * cells, foothold::kNaN);
  seen_certainty.assign(cells * cells, 0.0f);
  seen_edge2.assign(cells * cells, none2);
  row_slot.assign(cells, 0);
  col_slot.assign(cells, 0);
  mark_words = (cells + 63) / 64;
  geometry_mark.assign(cells * mark_words, 0);
  score_mark.assign(cells * mark_words, 0);
  for (std::vector<RowSpan>* rows : {&geometry_rows, &score_rows, &flips, &unseen_edge_rows}) {
    rows->assign(cells, RowSpan{n, -1});
  }
  raised.reserve(cells * cells);  // a cell is raised at most once a refresh
}

void FootholdChanges::set_slots(const ElevationMap& map) {
  const auto cells = static_cast<std::size_t>(n);
  const std::size_t corner = map.slot(map.min_cell());
  const std::size_t row0 = corner / cells, col0 = corner % cells;
  for (std::size_t i = 0; i < cells; ++i) {
    const std::size_t r = row0 + i;
    row_slot[i] = (r >= cells ? r - cells : r) * cells;
    const std::size_t c = col0 + i;
    col_slot[i] = c >= cells ? c - cells : c;
  }
}

// The run grown by the footprint's disc, row by row.
void FootholdChanges::mark_geometry(const FootholdStencil& stencil, std::int64_t i, std::int64_t j0, std::int64_t j1) {
  const std::int64_t f = stencil.foot_cells, side = n;
  const int* widths = stencil.foot_widths.data() + f;  // by row offset, -f..f
  std::uint64_t* marks = geometry_mark.data();
  RowSpan* hulls = geometry_rows.data();
  const std::size_t words = mark_words;
  const std::int64_t first = std::max(-f, -i), last = std::min(f, side - 1 - i);
  for (std::int64_t d = first; d <= last; ++d) {
    const std::int64_t w = widths[d < 0 ? -d : d];
    if (w < 0) continue;
    const auto lo = static_cast<int>(std::max<std::int64_t>(j0 - w, 0));
    const auto hi = static_cast<int>(std::min<std::int64_t>(j1 + w, side - 1));
    if (lo > hi) continue;
    const auto x = static_cast<std::size_t>(i + d);
    set_bits(marks + x * words, static_cast<std::size_t>(lo), static_cast<std::size_t>(hi));
    RowSpan& r = hulls[x];
    r.lo = std::min(r.lo, lo);
    r.hi = std::max(r.hi, hi);
  }
}

void FootholdChanges::mark_geometry_word(const FootholdStencil& stencil, std::int64_t i, std::size_t word,
                                         std::uint64_t bits) {
  if (bits == 0) return;
  const std::int64_t f = stencil.foot_cells, side = n;
  const int* widths = stencil.foot_widths.data() + f;  // by row offset, -f..f
  // The bits widened by w columns either way: within the word, and what
  // spills into the words below and above it.
  std::uint64_t within[64], below[64], above[64];
  within[0] = bits;
  below[0] = above[0] = 0;
  for (std::int64_t w = 1; w <= f; ++w) {
    within[w] = within[w - 1] | bits << w | bits >> w;
    below[w] = below[w - 1] | bits << (64 - w);
    above[w] = above[w - 1] | bits >> (64 - w);
  }
  // Columns at or past n are not cells: the last word keeps only those below.
  const auto last_word = static_cast<std::size_t>(side - 1) / 64;
  const std::uint64_t last_mask = ~std::uint64_t{0} >> (63 - (side - 1) % 64);
  const auto in_window = [&](std::size_t w, std::uint64_t m) { return w == last_word ? m & last_mask : m; };
  const auto first_column = static_cast<int>(word * 64);
  const int first_bit = first_column + std::countr_zero(bits), last_bit = first_column + 63 - std::countl_zero(bits);
  const auto last_cell = static_cast<int>(side - 1);
  const std::int64_t first = std::max(-f, -i), last = std::min(f, side - 1 - i);
  for (std::int64_t d = first; d <= last; ++d) {
    const int w = widths[d < 0 ? -d : d];
    if (w < 0) continue;
    std::uint64_t* row = geometry_mark.data() + static_cast<std::size_t>(i + d) * mark_words;
    // The cells' own columns lie in the window: `here` is never empty.
    const std::uint64_t here = in_window(word, within[w]);
    const std::uint64_t low = word > 0 ? below[w] : 0;
    const std::uint64_t high = word < last_word ? in_window(word + 1, above[w]) : 0;
    row[word] |= here;
    if (low != 0) row[word - 1] |= low;
    if (high != 0) row[word + 1] |= high;
    // The run's columns widened by w, within the window: what the words'
    // bits span, without finding it in them.
    RowSpan& r = geometry_rows[static_cast<std::size_t>(i + d)];
    r.lo = std::min(r.lo, std::max(first_bit - w, 0));
    r.hi = std::max(r.hi, std::min(last_bit + w, last_cell));
  }
}

// A neighbour's footprint lost the known ones among them, and the edge
// distances within the search radius of one that was an edge may grow.
void FootholdChanges::see_left(const FootholdStencil& stencil, const ElevationMap& map, const CellBox& b,
                               CellIndex corner) {
  const std::int64_t foot_cells = stencil.foot_cells, edge_cells = stencil.edge_cells;
  const auto side = static_cast<std::size_t>(n);
  const auto clamp = [&](std::int64_t v) { return static_cast<int>(std::clamp<std::int64_t>(v, 0, n - 1)); };
#ifdef STRIDEMAP_CHANGES_AVX2
  const bool avx2 = changes_avx2_available();
#endif
  for (std::int64_t x = b.min.x; x <= b.max.x; ++x) {
    const std::int64_t i = x - corner.x;
    if (i < -foot_cells - edge_cells || i > n - 1 + foot_cells + edge_cells) continue;  // reaches no window cell
    const auto mark_run = [&](std::int64_t first, std::int64_t last) {
      mark_geometry(stencil, i, first - corner.y, last - corner.y);
    };
    RowRuns known_runs;
    RowSpan& flip = flips[static_cast<std::size_t>(clamp(i))];
    // Slots along the row step by one and wrap: map.slot()'s two modulos
    // once a row, not once a cell.
    const std::size_t first = map.slot({x, b.min.y});
    const std::size_t row = first - first % side;
    std::size_t col = first - row;
    for (std::int64_t y = b.min.y; y <= b.max.y;) {
      const auto count = static_cast<int>(
          std::min<std::int64_t>({b.max.y - y + 1, static_cast<std::int64_t>(side - col), std::int64_t{64}}));
      const float* elevation = seen_elevation.data() + row + col;
      const std::int32_t* edge2 = seen_edge2.data() + row + col;
      std::uint64_t known_bits = 0, edge_bits = 0;
#ifdef STRIDEMAP_CHANGES_AVX2
      if (avx2) {
        left_chunk_avx2(elevation, edge2, count, known_bits, edge_bits);
      } else
#endif
      {
        std::uint8_t known[64 + 8], edge[64 + 8];
        for (int k = 0; k < count; ++k) {
          known[k] = !std::isnan(elevation[k]);
          edge[k] = edge2[k] == 0;  // it was an edge
        }
        known_bits = bits_of_flags(known, count);
        edge_bits = bits_of_flags(edge, count);
      }
      if (edge_bits != 0) {
        flip.lo = std::min(flip.lo, clamp(y + std::countr_zero(edge_bits) - corner.y));
        flip.hi = std::max(flip.hi, clamp(y + 63 - std::countl_zero(edge_bits) - corner.y));
      }
      known_runs.add(known_bits, count, y, mark_run);
      y += count;
      col += static_cast<std::size_t>(count);
      if (col == side) col = 0;
    }
    known_runs.end(b.max.y, mark_run);
  }
}

// Compared with what the last refresh saw: a changed elevation or
// known-ness redoes the plane fits around the cell; a changed certainty
// factor, its score only. A chunk of a row's cells (contiguous in storage,
// within one word of marks) is compared first, into bits, then marked.
void FootholdChanges::see_changes(const FootholdStencil& stencil, const ElevationMap& map, const CellBox& now) {
  if (pending.empty()) return;
  const float* elevation = map.elevation_data();
  const std::uint8_t* state = map.state_data();
  const float* certainty = map.certainty_data();
  const CellIndex corner = now.min;
  const auto side = static_cast<std::int64_t>(n);
  const CellBox rows = pending.bounds().intersected(stable);
  const bool by_words = stencil.foot_cells < 64;
  const CellCompare compare{elevation,         state,         certainty, seen_elevation.data(), seen_certainty.data(),
                            seen_edge2.data(), full_certainty};
#ifdef STRIDEMAP_CHANGES_AVX2
  const bool avx2 = changes_avx2_available();
#endif
  std::int64_t lo = 0, hi = 0;
  for (std::int64_t x = rows.min.x; !rows.empty() && x <= rows.max.x; ++x) {
    if (!pending.span(x, lo, hi)) continue;
    lo = std::max(lo, stable.min.y);
    hi = std::min(hi, stable.max.y);
    const auto i = static_cast<std::size_t>(x - corner.x);
    const std::size_t row = row_slot[i];
    const auto mark_run = [&](std::int64_t first, std::int64_t last) {
      mark_geometry(stencil, static_cast<std::int64_t>(i), first, last);
    };
    RowRuns changed_runs;
    RowSpan& scored = score_rows[i];
    RowSpan& unseen = unseen_edge_rows[i];
    std::uint64_t* marks = score_mark.data() + i * mark_words;
    const std::int64_t j_end = hi - corner.y;
    for (std::int64_t j = lo - corner.y; j <= j_end;) {
      const std::size_t first = col_slot[static_cast<std::size_t>(j)];
      const auto count = static_cast<int>(
          std::min<std::int64_t>({j_end - j + 1, side - static_cast<std::int64_t>(first), 64 - j % 64}));
      const std::size_t s0 = row + first;
      ChunkChanges bits;
#ifdef STRIDEMAP_CHANGES_AVX2
      if (avx2) {
        bits = compare_chunk_avx2(compare, s0, count);
      } else {
        compare_chunk(compare, s0, count, bits);
      }
#else
      compare_chunk(compare, s0, count, bits);
#endif
      const std::uint64_t changed = bits.changed, unseen_known = bits.unseen_known;
      const std::uint64_t scores = bits.scores;
      if (scores != 0) {
        marks[j / 64] |= scores << (j % 64);
        scored.lo = std::min(scored.lo, static_cast<int>(j + std::countr_zero(scores)));
        scored.hi = std::max(scored.hi, static_cast<int>(j + 63 - std::countl_zero(scores)));
      }
      if (unseen_known != 0) {
        unseen.lo = std::min(unseen.lo, static_cast<int>(j + std::countr_zero(unseen_known)));
        unseen.hi = std::max(unseen.hi, static_cast<int>(j + 63 - std::countl_zero(unseen_known)));
      }
      if (by_words) {
        if (changed != 0) {
          mark_geometry_word(stencil, static_cast<std::int64_t>(i), static_cast<std::size_t>(j / 64),
                             changed << (j % 64));
        }
      } else {
        changed_runs.add(changed, count, j, mark_run);
      }
      j += count;
    }
    changed_runs.end(j_end, mark_run);
  }
}

// With `mark`, a known cell redoes the plane fits around it and its score
// (cells that entered the window were unknown to the last refresh).
void FootholdChanges::see_all(const FootholdStencil& stencil, const ElevationMap& map, const LocalBox& b, bool mark) {
  const float* elevation = map.elevation_data();
  const std::uint8_t* state = map.state_data();
  const float* certainty = map.certainty_data();
  const auto side = static_cast<std::int64_t>(n);
  const bool by_words = stencil.foot_cells < 64;
#ifdef STRIDEMAP_CHANGES_AVX2
  const CellCompare compare{elevation,         state,         certainty, seen_elevation.data(), seen_certainty.data(),
                            seen_edge2.data(), full_certainty};
  const bool avx2 = changes_avx2_available();
#endif
  for (std::int64_t i = b.i0; i <= b.i1; ++i) {
    const std::size_t row = row_slot[static_cast<std::size_t>(i)];
    const auto mark_run = [&](std::int64_t first, std::int64_t last) { mark_geometry(stencil, i, first, last); };
    RowRuns known_runs;
    RowSpan& scored = score_rows[static_cast<std::size_t>(i)];
    RowSpan& unseen = unseen_edge_rows[static_cast<std::size_t>(i)];
    std::uint64_t* marks = score_mark.data() + static_cast<std::size_t>(i) * mark_words;
    // Chunks contiguous in storage and within one word of marks.
    for (std::int64_t j = b.j0; j <= b.j1;) {
      const std::size_t first = col_slot[static_cast<std::size_t>(j)];
      const auto count = static_cast<int>(
          std::min<std::int64_t>({b.j1 - j + 1, side - static_cast<std::int64_t>(first), 64 - j % 64}));
      const std::size_t s0 = row + first;
      std::uint64_t known_bits = 0;
#ifdef STRIDEMAP_CHANGES_AVX2
      if (avx2) {
        known_bits = see_chunk_avx2(compare, s0, count, mark);
      } else
#endif
      {
        if (!mark) {
          for (std::size_t s = s0; s < s0 + static_cast<std::size_t>(count); ++s) {
            seen_elevation[s] = foothold::known_elevation(elevation, state, s);
            seen_certainty[s] = certainty[s];
          }
        } else {
          for (int k = 0; k < count; ++k) {
            const std::size_t s = s0 + static_cast<std::size_t>(k);
            const float elevation_now = foothold::known_elevation(elevation, state, s);
            seen_elevation[s] = elevation_now;
            seen_certainty[s] = certainty[s];
            // Its edge distance is searched for when it is known (then or later).
            seen_edge2[s] = kEdgeUnknown;
            known_bits |= static_cast<std::uint64_t>(!std::isnan(elevation_now)) << k;
          }
        }
      }
      if (!mark) {
        j += count;
        continue;
      }
      if (known_bits != 0) {
        // Known cells: their scores, and their edge distances searched for.
        marks[j / 64] |= known_bits << (j % 64);
        const auto lo = static_cast<int>(j + std::countr_zero(known_bits));
        const auto hi = static_cast<int>(j + 63 - std::countl_zero(known_bits));
        scored.lo = std::min(scored.lo, lo);
        scored.hi = std::max(scored.hi, hi);
        unseen.lo = std::min(unseen.lo, lo);
        unseen.hi = std::max(unseen.hi, hi);
      }
      if (by_words) {
        if (known_bits != 0) mark_geometry_word(stencil, i, static_cast<std::size_t>(j / 64), known_bits << (j % 64));
      } else {
        known_runs.add(known_bits, count, j, mark_run);
      }
      j += count;
    }
    known_runs.end(b.j1, mark_run);
  }
}

}  // namespace stridemap
