#include "stridemap/core/foothold_edge_search.hpp"

#include <algorithm>
#include <bit>
#include <cstring>

#include "foothold_cells.hpp"

#if defined(__x86_64__) && defined(__GNUC__) && !defined(__clang__) && defined(__linux__) && \
    !defined(STRIDEMAP_NO_AVX2_COPIES)
#define STRIDEMAP_EDGE_AVX2 1
#include <immintrin.h>
#endif

namespace stridemap {

namespace {

// Eight cells a block: one AVX2 instruction, two SSE2 ones.
constexpr int kBlock = FootholdEdgeSearch::kBlock;
using Lanes = std::int32_t __attribute__((vector_size(kBlock * sizeof(std::int32_t))));

#ifdef STRIDEMAP_EDGE_AVX2
bool edge_avx2_available() {
  static const bool has = __builtin_cpu_supports("avx2");
  return has;
}

// The settling of a run of cells, eight a lane each where the CPU has AVX2
// (chosen at run time): the scalar loop's compare and store, ~12
// instructions a cell, is most of what a settled cell costs. Bit k: cell k's
// distance (the least of found[k] and none2) differs from seen[k], which
// becomes it. found may be read up to a block past the run (the rows of
// minima are padded by a block); seen, only within it.
__attribute__((target("avx2"))) std::uint64_t settle_avx2(std::int32_t* seen, const std::int32_t* found, int count,
                                                          std::int32_t none2) {
  const __m256i cap = _mm256_set1_epi32(none2);
  const __m256i lane = _mm256_setr_epi32(0, 1, 2, 3, 4, 5, 6, 7);
  std::uint64_t changed = 0;
  for (int k = 0; k < count; k += kBlock) {
    const __m256i b = _mm256_min_epi32(_mm256_loadu_si256(reinterpret_cast<const __m256i*>(found + k)), cap);
    auto* at = reinterpret_cast<__m256i*>(seen + k);
    __m256i before;
    if (count - k >= kBlock) {
      before = _mm256_loadu_si256(at);
      _mm256_storeu_si256(at, b);
    } else {
      const __m256i in_run = _mm256_cmpgt_epi32(_mm256_set1_epi32(count - k), lane);
      before = _mm256_maskload_epi32(seen + k, in_run);
      _mm256_maskstore_epi32(seen + k, in_run, b);
    }
    const auto same = static_cast<unsigned>(_mm256_movemask_ps(_mm256_castsi256_ps(_mm256_cmpeq_epi32(b, before))));
    changed |= static_cast<std::uint64_t>(~same & 0xffu) << k;
  }
  // The lanes past the run compared with 0s: their bits are not the run's.
  return count == 64 ? changed : changed & ((std::uint64_t{1} << count) - 1);
}

// raise_edges()'s pass over a run of a disc row, eight cells a lane each
// where the CPU has AVX2: each squared distance lowered to the new edge's
// where that is less. Bit k: cell k (dy = dy0 + k, at seen[k]) lowered;
// count <= 64.
__attribute__((target("avx2"))) std::uint64_t lower_run_avx2(std::int32_t* seen, int count, std::int32_t dx2, int dy0) {
  const __m256i lane = _mm256_setr_epi32(0, 1, 2, 3, 4, 5, 6, 7);
  std::uint64_t lowered = 0;
  for (int k = 0; k < count; k += kBlock) {
    const __m256i dy = _mm256_add_epi32(_mm256_set1_epi32(dy0 + k), lane);
    const __m256i d2 = _mm256_add_epi32(_mm256_set1_epi32(dx2), _mm256_mullo_epi32(dy, dy));
    const __m256i in_run = _mm256_cmpgt_epi32(_mm256_set1_epi32(count - k), lane);
    const __m256i before = _mm256_maskload_epi32(seen + k, in_run);
    const __m256i lower = _mm256_and_si256(_mm256_cmpgt_epi32(before, d2), in_run);
    _mm256_maskstore_epi32(seen + k, lower, d2);
    lowered |= static_cast<std::uint64_t>(static_cast<unsigned>(_mm256_movemask_ps(_mm256_castsi256_ps(lower)))) << k;
  }
  return lowered;
}
#endif

}  // namespace

FootholdEdgeSearch::FootholdEdgeSearch(int cells_per_side) {
  const auto n = static_cast<std::size_t>(cells_per_side);
  const RowSpan none{cells_per_side, -1};
  edge_rows.assign(n, none);
  distance_rows.assign(n, none);
  stride = n + kBlock;
  distance2.assign(n * stride, 0);
  best2.assign(2 * (n + kBlock), 0);
  offset2.assign(2 * n + 3, 0);
  // A row's columns from -2n to 3n + 2 * kBlock: the search radius is at
  // most n, the shifts reach at most 2n + 1 and a block runs on by kBlock.
  row_a.assign(5 * n + 2 * kBlock + 2, 0);
  row_b.assign(5 * n + 2 * kBlock + 2, 0);
  merged.assign(n, none);
  merged_rows.assign(n, none);
}

// Both passes take minima over shifted copies of a row a block of columns
// at a time, the block's minimum in a register: a loop per shifted copy
// would pay its set-up and tail once a copy, more than the minima
// themselves on the short spans a refresh searches. A block may run past a
// span's end into the rows' padding; what it computes there is not read.
STRIDEMAP_FOOTHOLD_CLONES std::size_t search_edge_distances(FootholdEdgeSearch& search, FootholdChanges& changes,
                                                            const FootholdStencil& stencil, const float* step,
                                                            float max_step, bool all) {
  const int n_cells = changes.n;
  const int r = static_cast<int>(stencil.edge_cells);
  const std::int32_t none2 = r * r + 1;
  // Far beyond any r * r + r * r, and no overflow when two of them are added.
  constexpr std::int32_t kFar = 1 << 29;
  const auto n = static_cast<std::size_t>(n_cells);
  const std::size_t stride = search.stride;
  std::size_t cells = 0;
  // The along-row distances a row must supply: its columns wherever a row
  // within r of it has cells to redo.
  std::fill(search.distance_rows.begin(), search.distance_rows.end(), RowSpan{n_cells, -1});
  for (int x = 0; x < n_cells; ++x) {
    const RowSpan e = search.edge_rows[static_cast<std::size_t>(x)];
    if (e.lo > e.hi) continue;
    for (int k = std::max(0, x - r); k <= std::min(n_cells - 1, x + r); ++k) {
      RowSpan& d = search.distance_rows[static_cast<std::size_t>(k)];
      d.lo = std::min(d.lo, e.lo);
      d.hi = std::max(d.hi, e.hi);
    }
  }
  // Per row: the squared distance along the row to the nearest edge within
  // r (kFar beyond). Distances in cells first, by shifts of 1, 2, 4, ...
  // (each the least of a cell's distance and its neighbours' s away plus
  // s): a walk to the nearest edge, t <= r cells away, is t's binary digits
  // in one direction, and any other walk is no shorter than where it ends,
  // so a distance <= r is exact and one above r stands for none.
  int reach = 0, levels = 0;  // reach = 2^levels - 1 >= r
  while (reach < r) reach = 2 * reach + 1, ++levels;
  const std::int32_t none = r + 1;  // a cell without an edge; any walk from it stays above r
  std::int32_t* from = search.row_a.data() + 2 * n;
  std::int32_t* to = search.row_b.data() + 2 * n;
  for (int x = 0; x < n_cells; ++x) {
    const RowSpan need = search.distance_rows[static_cast<std::size_t>(x)];
    if (need.lo > need.hi) continue;
    const int lo = std::max(need.lo - reach, 0), hi = std::min(need.hi + reach + kBlock - 1, n_cells - 1);
    std::fill(from + need.lo - reach, from + lo, none);
    std::fill(from + hi + 1, from + need.hi + reach + kBlock, none);
    // The window's columns lo..hi are at most two runs of the storage row
    // (the ring wraps once).
    const float* row = step + changes.row_slot[static_cast<std::size_t>(x)];
    for (int y = lo; y <= hi;) {
      const std::size_t first = changes.col_slot[static_cast<std::size_t>(y)];
      const int end = std::min(hi, y + static_cast<int>(n - first) - 1);
      const float* run = row + first;
      for (int k = y; k <= end; ++k) from[k] = run[k - y] > max_step ? 0 : none;
      y = end + 1;
    }
    // Each level's columns reach as far beyond need as the shifts after it.
    int rest = reach;
    for (int level = 0, shift = 1; level < levels; ++level, shift *= 2) {
      rest -= shift;
      for (int y = need.lo - rest; y <= need.hi + rest; y += kBlock) {
        Lanes here, left, right;
        std::memcpy(&here, from + y, sizeof here);
        std::memcpy(&left, from + y - shift, sizeof left);
        std::memcpy(&right, from + y + shift, sizeof right);
        left = right < left ? right : left;
        left += shift;
        here = left < here ? left : here;
        std::memcpy(to + y, &here, sizeof here);
      }
      std::swap(from, to);
    }
    std::int32_t* out = search.distance2.data() + static_cast<std::size_t>(x) * stride;
    for (int y = need.lo; y <= need.hi; y += kBlock) {
      Lanes d;
      std::memcpy(&d, from + y, sizeof d);
      d = d < none ? d : none;
      const Lanes far = Lanes{} + kFar;
      d = d < none ? d * d : far;
      std::memcpy(out + y, &d, sizeof d);
    }
  }
  // The cells of row x's span e take their distances from `best` (by
  // column), marking the score of each whose distance changed (`all`: of
  // each); returns the cells. A run of columns contiguous in storage and
  // within one word of marks gathers its changes as bits, set with one OR
  // and widening the hull once: a third of the cells change, at random, so
  // a branch per cell would mispredict.
#ifdef STRIDEMAP_EDGE_AVX2
  const bool use_avx2 = edge_avx2_available();
#endif
  const auto settle = [&](int x, RowSpan e, const std::int32_t* best) -> std::size_t {
    if (e.lo > e.hi) return 0;
    std::int32_t* seen_row = changes.seen_edge2.data() + changes.row_slot[static_cast<std::size_t>(x)];
    std::uint64_t* marks = changes.score_mark.data() + static_cast<std::size_t>(x) * changes.mark_words;
    RowSpan& marked = changes.score_rows[static_cast<std::size_t>(x)];
    for (int y = e.lo; y <= e.hi;) {
      const std::size_t first = changes.col_slot[static_cast<std::size_t>(y)];
      const int count = std::min({e.hi - y + 1, static_cast<int>(n - first), 64 - y % 64});
      std::int32_t* seen = seen_row + first;
      const std::int32_t* found = best + y;
      std::uint64_t changed_bits = 0;
#ifdef STRIDEMAP_EDGE_AVX2
      if (use_avx2) {
        changed_bits = settle_avx2(seen, found, count, none2);
        if (all) changed_bits = count == 64 ? ~std::uint64_t{0} : (std::uint64_t{1} << count) - 1;
      } else
#endif
      {
        for (int k = 0; k < count; ++k) {
          const std::int32_t b = std::min(found[k], none2);
          const bool changed = b != seen[k] || all;
          seen[k] = b;
          changed_bits |= static_cast<std::uint64_t>(changed) << k;
        }
      }
      if (changed_bits != 0) {
        marks[y / 64] |= changed_bits << (y % 64);
        marked.lo = std::min(marked.lo, y + std::countr_zero(changed_bits));
        marked.hi = std::max(marked.hi, y + 63 - std::countl_zero(changed_bits));
      }
      y += count;
    }
    return static_cast<std::size_t>(e.hi - e.lo + 1);
  };
  // min over the rows within r of dx^2 + (along-row distance)^2: exact
  // within the search disc (the nearest edge in Euclidean distance is the
  // nearest along its own row). Two rows at once, which share all but two
  // of the rows they read; a row outside one's disc (its columns may be
  // stale there) adds kFar or more to it.
  std::int32_t* offset2 = search.offset2.data() + n + 1;  // -(r + 1)..r + 1
  for (int d = -r - 1; d <= r + 1; ++d) offset2[d] = d >= -r && d <= r ? d * d : kFar;
  std::int32_t* best0 = search.best2.data();
  std::int32_t* best1 = best0 + n + kBlock;
  for (int x = 0; x < n_cells; x += 2) {
    const RowSpan e0 = search.edge_rows[static_cast<std::size_t>(x)];
    const RowSpan e1 = x + 1 < n_cells ? search.edge_rows[static_cast<std::size_t>(x) + 1] : RowSpan{n_cells, -1};
    const int lo = std::min(e0.lo, e1.lo), hi = std::max(e0.hi, e1.hi);
    if (lo > hi) continue;
    const int k0 = std::max(0, x - r), k1 = std::min(n_cells - 1, x + 1 + r);
    for (int y = lo; y <= hi; y += kBlock) {
      const std::int32_t* at = search.distance2.data() + static_cast<std::size_t>(k0) * stride + y;
      Lanes least0, least1;
      std::memcpy(&least0, at, sizeof least0);
      least1 = least0 + offset2[k0 - x - 1];
      least0 += offset2[k0 - x];
      for (int k = k0 + 1; k <= k1; ++k) {
        at += stride;
        Lanes v;
        std::memcpy(&v, at, sizeof v);
        const Lanes v0 = v + offset2[k - x], v1 = v + offset2[k - x - 1];
        least0 = v0 < least0 ? v0 : least0;
        least1 = v1 < least1 ? v1 : least1;
      }
      std::memcpy(best0 + y, &least0, sizeof least0);
      std::memcpy(best1 + y, &least1, sizeof least1);
    }
    cells += settle(x, e0, best0) + settle(x + 1, e1, best1);
  }
  return cells;
}

// Cells that became edges are cheap one by one (raise_edges(), a pass over
// the search disc each), but a cluster of them costs less searched for as
// one region. Whichever costs less by the rough counts below (about ten
// instructions a disc cell raised, eighty a cell searched with AVX2;
// callgrind, the benchmark's walks) is taken: the values are the same.
void search_or_raise_edges(FootholdEdgeSearch& search, FootholdChanges& changes, const FootholdStencil& stencil) {
  if (changes.raised.empty()) return;
  const int n = changes.n;
  const auto area = [](const std::vector<RowSpan>& rows) {
    std::size_t cells = 0;
    for (const RowSpan& r : rows) cells += r.lo <= r.hi ? static_cast<std::size_t>(r.hi - r.lo + 1) : 0;
    return cells;
  };
  search.merged = changes.flips;
  for (const std::int32_t cell : changes.raised) {
    RowSpan& m = search.merged[static_cast<std::size_t>(cell / n)];
    m.lo = std::min(m.lo, cell % n);
    m.hi = std::max(m.hi, cell % n);
  }
  grow_rows(search.merged, search.merged_rows, stencil.edge_widths);
  const std::size_t extra = area(search.merged_rows) - area(search.edge_rows);
  if (extra * 8 < changes.raised.size() * stencil.edge_disc_cells) {
    search.edge_rows.swap(search.merged_rows);
    changes.raised.clear();
  }
}

// A cell that became an edge can only shorten the edge distances within
// the search radius: each becomes the smaller of what it was and the
// distance to the new edge, which is what the search would find (the
// edges that went are searched for before, in search_edge_distances()). A
// cell not yet known (kEdgeUnknown) is searched for when it is.
void raise_edges(FootholdChanges& changes, const FootholdStencil& stencil) {
  const int r = static_cast<int>(stencil.edge_cells);
  const int n = changes.n;
#ifdef STRIDEMAP_EDGE_AVX2
  const bool use_avx2 = edge_avx2_available();
#endif
  for (const std::int32_t cell : changes.raised) {
    const int ei = cell / n, ej = cell % n;
    for (int dx = std::max(-r, -ei); dx <= std::min(r, n - 1 - ei); ++dx) {
      const int w = stencil.edge_widths[static_cast<std::size_t>(dx + r)];
      std::int32_t* row = changes.seen_edge2.data() + changes.row_slot[static_cast<std::size_t>(ei + dx)];
      const int dy0 = std::max(-w, -ej), dy1 = std::min(w, n - 1 - ej);
      changes.widen_scores(ei + dx, ej + dy0, ej + dy1);
      // The disc row's columns are at most two runs of the storage row (the
      // ring wraps once).
      for (int dy = dy0; dy <= dy1;) {
        const std::size_t first = changes.col_slot[static_cast<std::size_t>(ej + dy)];
        const int run_end = std::min(dy1, dy + static_cast<int>(static_cast<std::size_t>(n) - first) - 1);
        std::int32_t* seen = row + first;
#ifdef STRIDEMAP_EDGE_AVX2
        if (use_avx2) {
          while (dy <= run_end) {
            const int count = std::min(64, run_end - dy + 1);
            const std::uint64_t lowered = lower_run_avx2(seen, count, dx * dx, dy);
            if (lowered != 0) changes.mark_scores(ei + dx, ej + dy, lowered);
            seen += count;
            dy += count;
          }
          continue;
        }
#endif
        for (const int run_start = dy; dy <= run_end; ++dy) {
          const std::int32_t d2 = dx * dx + dy * dy;
          std::int32_t& seen_d2 = seen[dy - run_start];
          if (d2 < seen_d2) {
            seen_d2 = d2;
            changes.mark_score(ei + dx, ej + dy);
          }
        }
      }
    }
  }
  changes.raised.clear();
}

}  // namespace stridemap
