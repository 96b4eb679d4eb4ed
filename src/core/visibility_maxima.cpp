// The visibility clean-up's bounds (core/visibility_clearing.hpp): the
// highest known elevation of each row and column of the window, kept from
// the mapper's changed rows scan by scan (or taken from the whole map), and
// the tables of their range maxima that bound what a beam's walk can meet.
#include <algorithm>
#include <bit>
#include <cstring>
#include <limits>

#include "stridemap/core/visibility_clearing.hpp"

#if defined(__SSE__)
#include <xmmintrin.h>
#endif
// Where the CPU has AVX, the pass over the window takes eight cells a
// vector instead of four (chosen at run time; a maximum rounds nothing, so
// the result is the same either way).
#if defined(__x86_64__) && defined(__GNUC__)
#include <immintrin.h>
#define STRIDEMAP_AVX_PASS 1
#endif

#include "stridemap/core/terrain_mapper.hpp"
#include "visibility_screen.hpp"

namespace stridemap {

namespace {

constexpr float kNoElevation = -std::numeric_limits<float>::infinity();

// `v > m ? v : m` never takes a NaN (unknown) as the maximum.
inline float known_max(float m, float v) { return v > m ? v : m; }

// take_row()'s columns j..n-1 one by one, m the highest known value so far.
inline float take_rest(const float* __restrict row, float* __restrict columns, std::int32_t* __restrict holder,
                       std::int32_t row_slot, std::size_t j, std::size_t n, float m) {
  for (; j < n; ++j) {
    if (row[j] > columns[j]) {
      columns[j] = row[j];
      holder[j] = row_slot;
    }
    m = known_max(m, row[j]);
  }
  return m;
}

// Raises columns[j] to row[j] for j < n, naming slot row `row_slot` in
// holder[j] where it raised a column, and returns the row's highest known
// value (-inf when none is known): the pass over the window, once a scan,
// one vector maximum per four cells and per row and column each.
// MAXPS(v, m) is `v > m ? v : m`, so a NaN (unknown) v is never taken, and
// CMPGTPS(v, m) tells the lanes it took.
float take_row(const float* __restrict row, float* __restrict columns, std::int32_t* __restrict holder,
               std::int32_t row_slot, std::size_t n) {
  std::size_t j = 0;
  float m = kNoElevation;
#if defined(__SSE__)
  __m128 a = _mm_set1_ps(kNoElevation), b = a;
  const auto raise = [&](const __m128 v, std::size_t at) {
    const __m128 c = _mm_loadu_ps(columns + at);
    _mm_storeu_ps(columns + at, _mm_max_ps(v, c));
    // Most cells written are no higher than their column's bound.
    for (unsigned higher = static_cast<unsigned>(_mm_movemask_ps(_mm_cmpgt_ps(v, c))); higher != 0;
         higher &= higher - 1) {
      holder[at + static_cast<std::size_t>(std::countr_zero(higher))] = row_slot;
    }
  };
  for (; j + 8 <= n; j += 8) {
    const __m128 u = _mm_loadu_ps(row + j), v = _mm_loadu_ps(row + j + 4);
    raise(u, j);
    raise(v, j + 4);
    a = _mm_max_ps(u, a);
    b = _mm_max_ps(v, b);
  }
  alignas(16) float lanes[4];
  _mm_store_ps(lanes, _mm_max_ps(a, b));
  for (const float v : lanes) m = known_max(m, v);
#endif
  return take_rest(row, columns, holder, row_slot, j, n, m);
}

#if defined(STRIDEMAP_AVX_PASS)
__attribute__((target("avx"))) float take_row_avx(const float* __restrict row, float* __restrict columns,
                                                  std::int32_t* __restrict holder, std::int32_t row_slot,
                                                  std::size_t n) {
  std::size_t j = 0;
  __m256 a = _mm256_set1_ps(kNoElevation);
  for (; j + 8 <= n; j += 8) {
    const __m256 u = _mm256_loadu_ps(row + j), c = _mm256_loadu_ps(columns + j);
    _mm256_storeu_ps(columns + j, _mm256_max_ps(u, c));
    // Most cells written are no higher than their column's bound.
    for (unsigned higher = static_cast<unsigned>(_mm256_movemask_ps(_mm256_cmp_ps(u, c, _CMP_GT_OQ))); higher != 0;
         higher &= higher - 1) {
      holder[j + static_cast<std::size_t>(std::countr_zero(higher))] = row_slot;
    }
    a = _mm256_max_ps(u, a);
  }
  alignas(32) float lanes[8];
  _mm256_store_ps(lanes, a);
  float m = kNoElevation;
  for (const float v : lanes) m = known_max(m, v);
  return take_rest(row, columns, holder, row_slot, j, n, m);
}

bool cpu_has_avx() {
  static const bool has = __builtin_cpu_supports("avx");
  return has;
}
#endif

// here[s] = max(below[s], below[s + half]) for s < count (no NaN in either).
void halves_max(const float* below, std::size_t half, float* here, std::size_t count) {
  std::size_t s = 0;
#if defined(__SSE__)
  for (; s + 4 <= count; s += 4) {
    _mm_storeu_ps(here + s, _mm_max_ps(_mm_loadu_ps(below + s + half), _mm_loadu_ps(below + s)));
  }
#endif
  for (; s < count; ++s) here[s] = std::max(below[s], below[s + half]);
}

}  // namespace

void VisibilityClearing::take_maxima(const ElevationMap& map) {
  // One pass over the elevation layer in slot order: rows and columns by slot.
  const auto n = static_cast<std::size_t>(n_);
  const float* elevation = map.elevation_data();
  float* columns = slot_column_max_.data();
  std::fill(columns, columns + n, kNoElevation);
  auto pass = take_row;
#if defined(STRIDEMAP_AVX_PASS)
  if (cpu_has_avx()) pass = take_row_avx;
#endif
  std::int32_t* holder = column_holder_.data();
  for (std::size_t i = 0; i < n; ++i) {
    slot_row_max_[i] = pass(elevation + i * n, columns, holder, static_cast<std::int32_t>(i), n);
  }
  maxima_corner_ = map.min_cell();
}

bool VisibilityClearing::update_maxima(const TerrainMapper& mapper) {
  // Called before start(): cleared_ and stats_ are the last scan's, corner_
  // its corner. Returns false, changing nothing that the whole pass would
  // not set again, when taking the whole map is the cheaper way.
  const ElevationMap& map = mapper.map();
  const std::int64_t n = n_;
  const auto nn = static_cast<std::size_t>(n);
  const CellIndex now = map.min_cell(), was = maxima_corner_;
  const std::int64_t dx = now.x - was.x, dy = now.y - was.y;
  if (dx >= n || -dx >= n || dy >= n || -dy >= n) return false;
  const ChangedRows& rows = mapper.changed_rows();
  // The changed cells of window rows, for the cost and the raise below.
  const CellBox& b = rows.bounds();
  const std::int64_t first_x = std::max(b.min.x, now.x), last_x = std::min(b.max.x, now.x + n - 1);
  std::int64_t written = 0;
  if (!rows.empty()) {
    std::int64_t lo = 0, hi = 0;
    for (std::int64_t x = first_x; x <= last_x; ++x) {
      if (rows.span(x, lo, hi)) written += std::max<std::int64_t>(0, std::min(hi, now.y + n - 1) - std::max(lo, now.y) + 1);
    }
  }
  if (written > n * n / 4) return false;

  float* row_max = slot_row_max_.data();
  float* column_max = slot_column_max_.data();
  std::uint8_t* retake_row = retake_row_.data();
  std::uint8_t* retake_column = retake_column_.data();
  std::int32_t* column_holder = column_holder_.data();
  std::fill(retake_row, retake_row + nn, 0);
  std::fill(retake_column, retake_column + nn, 0);
  std::size_t retaken_rows = 0, retaken_columns = 0;
  const auto mark = [](std::uint8_t& flag, std::size_t& count) {
    count += flag == 0;
    flag = 1;
  };
  // The last scan's clears: a row or column whose highest value was a
  // cleared cell's (or lower) may now be lower.
  for (const ClearedCell& c : cleared_) {
    const std::size_t sx = visibility::wrap_index(c.cell.x, n), sy = visibility::wrap_index(c.cell.y, n);
    if (!(row_max[sx] > c.elevation_m)) mark(retake_row[sx], retaken_rows);
    if (!(column_max[sy] > c.elevation_m)) mark(retake_column[sy], retaken_columns);
  }
  // A window move reset the cells that left (their slots are the entering
  // cells', unknown): rows that left are empty, and a column (row) whose
  // highest value was no higher than the rows (columns) that left may have
  // lost it.
  const auto leave = [&](std::int64_t from, std::int64_t step, float* lost, float* other, std::uint8_t* retake,
                         std::size_t& count) {
    if (step == 0) return;
    float highest = kNoElevation;
    const std::int64_t cells = step > 0 ? step : -step;
    const std::int64_t start = step > 0 ? from : from + n + step;  // global index of the first that left
    for (std::int64_t k = 0; k < cells; ++k) {
      float& m = lost[visibility::wrap_index(start + k, n)];
      highest = known_max(highest, m);
      m = kNoElevation;
    }
    if (!(highest > kNoElevation)) return;
    for (std::size_t s = 0; s < nn; ++s) {
      if (other[s] > kNoElevation && !(other[s] > highest)) mark(retake[s], count);
    }
  };
  // Rows that left: only a column whose highest cell lay in one of them
  // (its holder) may have lost it; a column taken from rows that stayed
  // holds its bound still. (A column held by a row that left and by one
  // that stayed at the same height is taken again all the same.)
  if (dx != 0) {
    const std::int64_t cells = dx > 0 ? dx : -dx;
    const std::int64_t first_left = dx > 0 ? was.x : was.x + n + dx;  // global index of the first that left
    const auto first_slot = static_cast<std::int64_t>(visibility::wrap_index(first_left, n));
    for (std::int64_t k = 0; k < cells; ++k) row_max[visibility::wrap_index(first_left + k, n)] = kNoElevation;
    for (std::size_t s = 0; s < nn; ++s) {
      if (!(column_max[s] > kNoElevation)) continue;
      const std::int64_t from_first = column_holder[s] - first_slot;
      if ((from_first < 0 ? from_first + n : from_first) < cells) mark(retake_column[s], retaken_columns);
    }
  }
  leave(was.y, dy, column_max, row_max, retake_row, retaken_rows);
  // A column is taken again cell by cell across the rows: past a quarter of
  // them the whole pass is cheaper.
  if (retaken_columns > nn / 4) return false;

  // The cells written since: rows and columns raised to them.
  const float* elevation = map.elevation_data();
  auto pass = take_row;
#if defined(STRIDEMAP_AVX_PASS)
  if (cpu_has_avx()) pass = take_row_avx;
#endif
  if (written > 0) {
    std::int64_t lo = 0, hi = 0;
    for (std::int64_t x = first_x; x <= last_x; ++x) {
      if (!rows.span(x, lo, hi)) continue;
      lo = std::max(lo, now.y);
      hi = std::min(hi, now.y + n - 1);
      if (lo > hi) continue;
      const std::size_t sx = visibility::wrap_index(x, n), s0 = visibility::wrap_index(lo, n);
      const auto count = static_cast<std::size_t>(hi - lo + 1);
      const std::size_t part = std::min(count, nn - s0);  // up to the slots' wrap, then from slot 0
      const float* row = elevation + sx * nn;
      const auto named = static_cast<std::int32_t>(sx);
      float m = pass(row + s0, column_max + s0, column_holder + s0, named, part);
      if (part < count) m = known_max(m, pass(row, column_max, column_holder, named, count - part));
      row_max[sx] = known_max(row_max[sx], m);
    }
  }
  // Rows and columns that may have lost their highest cell, from the map.
  if (retaken_rows > 0) {
    for (std::size_t sx = 0; sx < nn; ++sx) {
      if (retake_row[sx]) {
        row_max[sx] = pass(elevation + sx * nn, column_max, column_holder, static_cast<std::int32_t>(sx), nn);
      }
    }
  }
  if (retaken_columns > 0) {
    for (std::size_t sy = 0; sy < nn; ++sy) {
      if (!retake_column[sy]) continue;
      float m = kNoElevation;
      std::int32_t held_by = 0;
      for (std::size_t sx = 0; sx < nn; ++sx) {
        const float v = elevation[sx * nn + sy];
        if (v > m) {
          m = v;
          held_by = static_cast<std::int32_t>(sx);
        }
      }
      column_max[sy] = m;
      column_holder[sy] = held_by;
    }
  }
  maxima_corner_ = now;
  return true;
}

void VisibilityClearing::build_tables() {
  // Level 0 in the window's order from its corner (the look-ups are then
  // free of the slots' wrap); higher levels: the maximum of two halves.
  const auto n = static_cast<std::size_t>(n_);
  const auto x0 = static_cast<std::size_t>(slot_x0_), y0 = static_cast<std::size_t>(slot_y0_);
  // The same maxima for the same corner: the tables stand as they are.
  if (tables_valid_ && tables_corner_ == corner_ &&
      std::memcmp(tables_rows_.data(), slot_row_max_.data(), n * sizeof(float)) == 0 &&
      std::memcmp(tables_columns_.data(), slot_column_max_.data(), n * sizeof(float)) == 0) {
    return;
  }
  tables_valid_ = true;
  tables_corner_ = corner_;
  std::copy(slot_row_max_.begin(), slot_row_max_.end(), tables_rows_.begin());
  std::copy(slot_column_max_.begin(), slot_column_max_.end(), tables_columns_.begin());
  std::copy(slot_row_max_.begin() + static_cast<std::ptrdiff_t>(x0), slot_row_max_.end(), row_max_.begin());
  std::copy(slot_row_max_.begin(), slot_row_max_.begin() + static_cast<std::ptrdiff_t>(x0),
            row_max_.begin() + static_cast<std::ptrdiff_t>(n - x0));
  std::copy(slot_column_max_.begin() + static_cast<std::ptrdiff_t>(y0), slot_column_max_.end(), column_max_.begin());
  std::copy(slot_column_max_.begin(), slot_column_max_.begin() + static_cast<std::ptrdiff_t>(y0),
            column_max_.begin() + static_cast<std::ptrdiff_t>(n - y0));
  for (float* table : {row_max_.data(), column_max_.data()}) {
    for (std::size_t level = 1, half = 1; (half << 1) <= n; ++level, half <<= 1) {
      halves_max(table + (level - 1) * n, half, table + level * n, n - (half << 1) + 1);
    }
  }
  window_top_ = range_max(row_max_, 0, n_ - 1);
}

}  // namespace stridemap
