#include "stridemap/core/weighted_median_fill.hpp"

#include <algorithm>
#include <array>
#include <bit>
#include <cmath>
#include <cstring>
#include <limits>
#include <string>
#include <type_traits>

#include "fill_exact_windows.hpp"
#include "stridemap/core/error.hpp"

// The plain loops over whole maps below (copy, flags, results) in a copy for
// AVX2 too, chosen at run time (GCC on x86-64): twice the cells a vector.
// Bit operations, comparisons and single products only, no FMA: every copy
// gives the same bits.
#if defined(__x86_64__) && defined(__GNUC__) && !defined(__clang__) && defined(__ELF__) && !defined(STRIDEMAP_NO_AVX2_COPIES)
#define STRIDEMAP_MAP_LOOPS __attribute__((target_clones("avx2", "default")))
#else
#define STRIDEMAP_MAP_LOOPS
#endif

namespace stridemap {
namespace {

constexpr int kMaxRadius = 7;
constexpr float kNaN = std::numeric_limits<float>::quiet_NaN();
constexpr float kInf = std::numeric_limits<float>::infinity();

int quadrant_of(int di, int dj) {
  if (di > 0 && dj >= 0) return 0;
  if (di <= 0 && dj > 0) return 1;
  if (di < 0 && dj <= 0) return 2;
  return 3;
}

}  // namespace

WeightedMedianFill::WeightedMedianFill(const FillOptions& options) : options_(options) {
  if (options.window_radius_cells < 1 || options.window_radius_cells > kMaxRadius) {
    throw InputError("fill options: window_radius_cells must be between 1 and " + std::to_string(kMaxRadius) +
                     ", got " + std::to_string(options.window_radius_cells));
  }
  if (options.min_known_neighbours < 1) {
    throw InputError("fill options: min_known_neighbours must be at least 1, got " +
                     std::to_string(options.min_known_neighbours));
  }
  if (options.min_quadrants < 1 || options.min_quadrants > 4) {
    throw InputError("fill options: min_quadrants must be between 1 and 4, got " +
                     std::to_string(options.min_quadrants));
  }
  if (!std::isfinite(options.max_quartile_spread_m)) {
    throw InputError("fill options: max_quartile_spread_m must be finite (<= 0 disables it)");
  }
  if (!std::isfinite(options.near_weight) || options.near_weight <= 0.0) {
    throw InputError("fill options: near_weight must be a positive number, got " +
                     std::to_string(options.near_weight));
  }
}

namespace {

// Four ranks per vector (GCC's vector extension: any target with 128-bit
// vectors, or plain code where there are none): a comparison gives -1 where
// true, and subtracting it counts. `values` has room for `Blocks` vectors.
using Floats = float __attribute__((vector_size(16)));
using Counts = std::int32_t __attribute__((vector_size(16)));
using Masks = std::uint32_t __attribute__((vector_size(16)));
template <std::size_t Blocks>
void count_ranks_fixed(const float* values, std::size_t count, std::uint32_t* ranks) {
  // A fixed number of blocks stays in registers; the blocks past the
  // candidates compare values nobody reads.
  Floats block_values[Blocks];
  Counts block_ranks[Blocks];
  std::memcpy(block_values, values, sizeof block_values);
  for (std::size_t b = 0; b < Blocks; ++b) block_ranks[b] = Counts{0, 0, 0, 0};
  for (std::size_t m = 0; m < count; ++m) {
    const float v = values[m];
    const Floats broadcast = {v, v, v, v};
    for (std::size_t b = 0; b < Blocks; ++b) block_ranks[b] -= broadcast < block_values[b];
  }
  std::memcpy(ranks, block_ranks, sizeof block_ranks);
}

// ranks[k] = how many of values[0..count) are smaller than values[k];
// `values` and `ranks` have room up to a multiple of 4 past `count` (and
// 24 at least: the default window's 24 neighbours).
void count_ranks(const float* values, std::size_t count, std::uint32_t* ranks) {
  if (count <= 8) return count_ranks_fixed<2>(values, count, ranks);
  if (count <= 24) return count_ranks_fixed<6>(values, count, ranks);
  for (std::size_t k = 0; k < count; ++k) ranks[k] = 0;
  for (std::size_t m = 0; m < count; ++m) {
    const float v = values[m];
    for (std::size_t k = 0; k < count; ++k) ranks[k] += v < values[k] ? 1u : 0u;
  }
}

// Sorts by value through ranks: a candidate's place is the number of
// smaller values, and it is written there. The ranks are counted for all
// candidates at once, one compared value at a time (no sum across a
// register per candidate).
// Returns false when two values are equal or one is NaN (two candidates
// share a place, or a place stays NaN): std::sort may order such values
// otherwise, and the order of the weights summed decides the float result,
// so the caller sorts those with std::sort as the fill always did. Distinct
// values have one sorted order. `values` holds the candidates' values.
template <typename Candidate>
bool sort_distinct(const Candidate* in, std::size_t count, const float* values, std::uint32_t* ranks,
                   Candidate* out) {
  count_ranks(values, count, ranks);
  if (count <= 64) {
    // The ranks are a permutation exactly when the values are distinct and
    // none is NaN (equal values share a rank; a NaN has rank 0 and leaves
    // the others fewer places than values): one bit per rank tells.
    std::uint64_t seen = 0;
    for (std::size_t k = 0; k < count; ++k) seen |= std::uint64_t{1} << ranks[k];
    if (seen != (count == 64 ? ~std::uint64_t{0} : (std::uint64_t{1} << count) - 1)) return false;
    for (std::size_t k = 0; k < count; ++k) out[ranks[k]] = in[k];
    return true;
  }
  for (std::size_t k = 0; k < count; ++k) out[k].value = std::numeric_limits<float>::quiet_NaN();
  for (std::size_t k = 0; k < count; ++k) out[ranks[k]] = in[k];
  for (std::size_t k = 0; k + 1 < count; ++k) {
    if (!(out[k].value < out[k + 1].value)) return false;
  }
  return count == 0 || !std::isnan(out[count - 1].value);
}

// One run of `count` consecutive slots of a storage row into the padded
// copy, without a branch per cell (measured or not is as random as the map):
// masks, not selects, which the compiler turns back into branches. The
// pointers do not overlap, so the loop runs on vectors.
STRIDEMAP_MAP_LOOPS void copy_run(const std::uint8_t* __restrict state, const float* __restrict elevation,
              const float* __restrict certainty, std::size_t first_slot, std::size_t count,
              std::uint8_t* __restrict known, std::uint32_t* __restrict known_mask, float* __restrict value,
              float* __restrict weight, std::size_t* __restrict slot) {
  const auto measured = static_cast<std::uint8_t>(CellState::measured);
  const auto inf_bits = std::bit_cast<std::uint32_t>(kInf);
  for (std::size_t k = 0; k < count; ++k) {
    const std::size_t s = first_slot + k;
    slot[k] = s;
    const std::uint32_t mask = 0u - static_cast<std::uint32_t>(state[s] == measured);
    known[k] = static_cast<std::uint8_t>(mask & 1u);
    known_mask[k] = mask;
    value[k] = std::bit_cast<float>((std::bit_cast<std::uint32_t>(elevation[s]) & mask) | (inf_bits & ~mask));
    weight[k] = std::bit_cast<float>(std::bit_cast<std::uint32_t>(certainty[s]) & mask);
  }
}

// bits[q] = cells[q + dj] << (dj + W) over dj = -W..W, for the cells whose
// row of 2W + 1 lies inside the array (a window's rows never cross the
// padded copy's row ends: its margin is at least W).
template <int W>
STRIDEMAP_MAP_LOOPS void row_bits_of(const std::uint16_t* __restrict cells, std::size_t count, std::uint16_t* __restrict bits) {
  for (std::size_t q = W; q + W < count; ++q) {
    std::uint32_t b = 0;
    for (int dj = -W; dj <= W; ++dj) b |= static_cast<std::uint32_t>(cells[q + static_cast<std::size_t>(dj)]) << (dj + W);
    bits[q] = static_cast<std::uint16_t>(b);
  }
}

// Per cell, known (bit 0) and a zero or NaN value (bit kSpecialShift);
// value is +inf where unknown, so a zero or NaN is a known one.
STRIDEMAP_MAP_LOOPS void cell_bits_of(const std::uint8_t* __restrict known, const float* __restrict value,
                                      std::size_t count, std::uint16_t* __restrict bits) {
  for (std::size_t q = 0; q < count; ++q) {
    const float v = value[q];
    bits[q] = static_cast<std::uint16_t>(known[q] | (((v == 0.0f) | (v != v)) << fill_detail::kSpecialShift));
  }
}

// Writes the fill's results: a cell not measured takes its result where
// there is one (state filled) and is flagged for a reset where there is
// none. Returns the number of filled cells. The arrays do not overlap.
STRIDEMAP_MAP_LOOPS std::size_t write_results(const float* __restrict result, std::size_t cells, float* __restrict elevation,
                          std::uint8_t* __restrict state, std::uint8_t* __restrict reset) {
  const auto measured = static_cast<std::uint8_t>(CellState::measured);
  const auto filled_state = static_cast<std::uint8_t>(CellState::filled);
  // Masks, not selects or bools, so that the loop runs on vectors.
  std::uint32_t filled = 0;
  for (std::size_t s = 0; s < cells; ++s) {
    const std::uint32_t not_measured = state[s] != measured ? 1u : 0u;
    const float r = result[s];
    const std::uint32_t has_value = r == r ? 1u : 0u;  // not NaN
    const std::uint32_t gets_value = not_measured & has_value;
    const std::uint32_t mask = 0u - gets_value;
    reset[s] = static_cast<std::uint8_t>(not_measured & (has_value ^ 1u));
    elevation[s] = std::bit_cast<float>((std::bit_cast<std::uint32_t>(r) & mask) |
                                        (std::bit_cast<std::uint32_t>(elevation[s]) & ~mask));
    state[s] = static_cast<std::uint8_t>((filled_state & mask) | (state[s] & ~mask));
    filled += gets_value;
  }
  return filled;
}

}  // namespace

std::size_t WeightedMedianFill::apply(ElevationMap& map) {
  prepare(map, options_.window_radius_cells);
  return fill_prepared(map);
}

void WeightedMedianFill::prepare(const ElevationMap& map, int margin) {
  const int n = map.cells_per_side();
  const auto cells = static_cast<std::size_t>(n) * static_cast<std::size_t>(n);
  const float* elevation = map.elevation_data();
  const float* certainty = map.certainty_data();
  const std::uint8_t* state = map.state_data();

  // The window unrolled from the circular buffer into local order with a
  // margin of unknown cells: a neighbour is a fixed offset, no modulo and
  // no bounds test per neighbour. Unknown cells have value +inf (never the
  // smallest value that reaches a quantile, fill_exact_windows.cpp) and
  // weight 0.
  const int p = n + 2 * margin;
  margin_ = static_cast<std::size_t>(margin);
  pitch_ = static_cast<std::size_t>(p);
  cells_per_side_ = static_cast<std::size_t>(n);
  const auto padded_cells = static_cast<std::size_t>(p) * static_cast<std::size_t>(p);
  // Room past the end for the row pass's last group of four cells and the
  // exact path's eight-lane loads. Only the margin is written here (unknown
  // cells); the runs below write the rest.
  known_.resize(padded_cells + 8);
  known_mask_.resize(padded_cells + 8);
  value_.resize(padded_cells + 8);
  weight_.resize(padded_cells + 8);
  slot_.resize(cells);
  const auto unknown_from = [this](std::size_t first, std::size_t count) {
    std::fill_n(known_.data() + first, count, std::uint8_t{0});
    std::fill_n(known_mask_.data() + first, count, 0u);
    std::fill_n(value_.data() + first, count, kInf);
    std::fill_n(weight_.data() + first, count, 0.0f);
  };
  const auto um = static_cast<std::size_t>(margin), un_cells = static_cast<std::size_t>(n);
  unknown_from(0, um * pitch_ + um);  // the top rows and the first row's left margin
  for (std::size_t i = 0; i + 1 < un_cells; ++i) {
    unknown_from((i + um) * pitch_ + um + un_cells, 2 * um);  // right margin, next row's left margin
  }
  const std::size_t tail = (un_cells - 1 + um) * pitch_ + um + un_cells;
  unknown_from(tail, padded_cells - tail);  // the last row's right margin and the bottom rows
  std::fill_n(known_.data() + padded_cells, 8, std::uint8_t{0});
  std::fill_n(known_mask_.data() + padded_cells, 8, 0u);
  std::fill_n(value_.data() + padded_cells, 8, kInf);
  std::fill_n(weight_.data() + padded_cells, 8, 0.0f);

  // Each row of the window is two runs of the storage row (the circular
  // buffer wraps at most once).
  const auto un = static_cast<std::size_t>(n);
  const std::size_t first_column = map.slot(map.cell_at_local(0, 0)) % un;
  for (std::size_t i = 0; i < un; ++i) {
    const std::size_t row = map.slot(map.cell_at_local(static_cast<int>(i), 0)) / un * un;
    const std::size_t q = (i + margin_) * pitch_ + margin_;
    const std::size_t head = un - first_column;  // columns first_column..n-1 first
    copy_run(state, elevation, certainty, row + first_column, head, known_.data() + q, known_mask_.data() + q,
             value_.data() + q, weight_.data() + q, slot_.data() + i * un);
    copy_run(state, elevation, certainty, row, first_column, known_.data() + q + head,
             known_mask_.data() + q + head, value_.data() + q + head, weight_.data() + q + head,
             slot_.data() + i * un + head);
  }
}

void WeightedMedianFill::forget(std::size_t local_cell, int n) {
  const std::size_t un = static_cast<std::size_t>(n);
  const std::size_t q = (local_cell / un + margin_) * pitch_ + local_cell % un + margin_;
  known_[q] = 0;
  known_mask_[q] = 0;
  value_[q] = kInf;
  weight_[q] = 0.0f;
}

bool WeightedMedianFill::window_sums_exact() const {
  // Each weight, with the near factor or without, a whole number of
  // sixteenths and a full window of them at most 2^24 sixteenths.
  // Certainties are whole multiples of the increment a in the mapper, so
  // this is the usual case.
  const int w = options_.window_radius_cells;
  const int window_neighbours = (2 * w + 1) * (2 * w + 1) - 1;
  const float sixteenths_limit = static_cast<float>((1 << 24) / window_neighbours);
  const auto near_factor = static_cast<float>(options_.near_weight);
  // whole_sixteenths over the padded copy (unknown cells weigh 0), four at
  // a time; weight_ has room for the last group.
  Masks inexact = {0, 0, 0, 0};
  const Floats limit = {sixteenths_limit, sixteenths_limit, sixteenths_limit, sixteenths_limit};
  const std::size_t padded_cells = pitch_ * pitch_;
  for (std::size_t q = 0; q < padded_cells; q += 4) {
    Floats far;
    std::memcpy(&far, weight_.data() + q, sizeof far);
    const Floats near = far * near_factor;
    for (const Floats sixteenths : {far * 16.0f, near * 16.0f}) {
      const Masks in_range = reinterpret_cast<Masks>(sixteenths >= 0.0f) & reinterpret_cast<Masks>(sixteenths <= limit);
      const Floats converted = reinterpret_cast<Floats>(reinterpret_cast<Masks>(sixteenths) & in_range);
      const Floats back = __builtin_convertvector(__builtin_convertvector(converted, Counts), Floats);
      inexact |= ~in_range | reinterpret_cast<Masks>(back != converted);
    }
  }
  return (inexact[0] | inexact[1] | inexact[2] | inexact[3]) == 0;
}

void WeightedMedianFill::list_neighbours() {
  // Rows di = -w..w, in each dj = -w..w: the sums of the weights keep their order.
  const int w = options_.window_radius_cells;
  const auto near_factor = static_cast<float>(options_.near_weight);
  neighbour_count_ = 0;
  for (int di = -w; di <= w; ++di) {
    for (int dj = -w; dj <= w; ++dj) {
      if (di == 0 && dj == 0) continue;
      // certainty * 1.0f is the certainty itself: the far weight as before.
      const bool near = std::max(std::abs(di), std::abs(dj)) == 1;
      neighbours_[neighbour_count_++] = {static_cast<std::ptrdiff_t>(di) * static_cast<std::ptrdiff_t>(pitch_) + dj,
                                         near ? near_factor : 1.0f, 1u << quadrant_of(di, dj)};
    }
  }
}

float WeightedMedianFill::sorted_walk(std::size_t centre, float total_weight) {
  // The known neighbours in visiting order (the order std::sort's result
  // and the float sums depend on), without branches: each is written at
  // the end and kept only when known.
  std::size_t kept = 0;
  for (std::size_t k = 0; k < neighbour_count_; ++k) {
    const Neighbour& nb = neighbours_[k];
    const std::size_t t = centre + static_cast<std::size_t>(nb.offset);
    gathered_[kept] = {value_[t], weight_[t] * nb.factor};
    scratch_[kept] = value_[t];
    kept += known_[t] != 0 ? 1 : 0;
  }
  if (!sort_distinct(gathered_.data(), kept, scratch_.data(), ranks_.data(), candidates_.data())) {
    std::copy(gathered_.begin(), gathered_.begin() + static_cast<std::ptrdiff_t>(kept), candidates_.begin());
    std::sort(candidates_.begin(), candidates_.begin() + static_cast<std::ptrdiff_t>(kept),
              [](const Candidate& a, const Candidate& b) { return a.value < b.value; });
  }
  // Weighted quantiles q: the smallest value at which the cumulative
  // weight reaches q of the total; the three in one pass over the same sums.
  const float at_quarter = 0.25f * total_weight, at_half = 0.5f * total_weight,
              at_three_quarters = 0.75f * total_weight;
  const float last = candidates_[kept - 1].value;
  float quarter = last, half = last, three_quarters = last;
  bool have_quarter = false, have_half = false;
  float cumulative = 0.0f;
  for (std::size_t k = 0; k < kept; ++k) {
    cumulative += candidates_[k].weight;
    if (!have_quarter && cumulative >= at_quarter) {
      quarter = candidates_[k].value;
      have_quarter = true;
    }
    if (!have_half && cumulative >= at_half) {
      half = candidates_[k].value;
      have_half = true;
    }
    if (cumulative >= at_three_quarters) {
      three_quarters = candidates_[k].value;
      break;
    }
  }
  const bool test_spread = options_.max_quartile_spread_m > 0.0;
  return test_spread && three_quarters - quarter > static_cast<float>(options_.max_quartile_spread_m) ? kNaN : half;
}

void WeightedMedianFill::fill_exact_windows() {
  // Per padded cell, which of the 2w + 1 cells of its row centred on it
  // are known, and which of those hold a zero or NaN (the sorted walk's):
  // a window's tests are a few loads and bit operations. Rolled along
  // each row; the margin keeps every window inside.
  const int w = options_.window_radius_cells;
  const std::size_t p = pitch_, padded_cells = p * p;
  const std::size_t un = cells_per_side_;
  cell_bits_.resize(padded_cells);
  row_bits_.resize(padded_cells);  // row_bits_of writes all but the ends, never read
  cell_bits_of(known_.data(), value_.data(), padded_cells, cell_bits_.data());
  if (w == 1) {
    row_bits_of<1>(cell_bits_.data(), padded_cells, row_bits_.data());
  } else {
    row_bits_of<2>(cell_bits_.data(), padded_cells, row_bits_.data());
  }
  walk_cells_.resize(un * un);
  walk_totals_.resize(un * un);
  columns_.resize(un + 8);
  fill_detail::WindowInput in{};
  in.value = value_.data();
  in.weight = weight_.data();
  in.row_bits = row_bits_.data();
  in.known = known_.data();
  in.pitch = p;
  in.margin = margin_;
  in.n = un;
  in.near_factor = static_cast<float>(options_.near_weight);
  in.min_known = options_.min_known_neighbours;
  in.min_quadrants = options_.min_quadrants;
  in.spread = static_cast<float>(options_.max_quartile_spread_m);
  in.test_spread = options_.max_quartile_spread_m > 0.0;
  in.slot = slot_.data();
  in.result = result_.data();
  in.columns = columns_.data();
  in.walk_cells = walk_cells_.data();
  in.walk_totals = walk_totals_.data();
  const std::size_t walks =
      w == 1 ? fill_detail::fill_exact_windows_radius1(in) : fill_detail::fill_exact_windows_radius2(in);
  for (std::size_t k = 0; k < walks; ++k) {
    const std::size_t local = walk_cells_[k];
    const std::size_t centre = (local / un + margin_) * p + local % un + margin_;
    result_[slot_[local]] = sorted_walk(centre, walk_totals_[k]);
  }
}

void WeightedMedianFill::fill_row_by_row() {
  // Per row, the admission tests of every cell at once: for each neighbour
  // in turn, one pass along the row's contiguous arrays, so that each
  // cell's total weight adds its known neighbours in the same order as
  // ever while the compiler works on many cells side by side. Only cells
  // that pass are gathered and sorted.
  constexpr unsigned kQuadrantsIn[16] = {0, 1, 1, 2, 1, 2, 2, 3, 1, 2, 2, 3, 2, 3, 3, 4};
  const std::size_t p = pitch_;
  const std::size_t un = cells_per_side_;
  const std::size_t groups = (un + 3) / 4 * 4;
  count_.resize(groups);
  quadrants_.resize(groups);
  total_.resize(groups);
  unknown_columns_.resize(un);
  for (std::size_t i = 0; i < un; ++i) {
    const std::size_t row_start = (i + margin_) * p + margin_;
    // Four cells at a time, their sums kept in registers over all the
    // neighbours; the arrays have room for the last group of four.
    for (std::size_t j = 0; j < un; j += 4) {
      Masks count = {0, 0, 0, 0}, quadrants = {0, 0, 0, 0};
      Floats total = {0.0f, 0.0f, 0.0f, 0.0f};
      for (std::size_t k = 0; k < neighbour_count_; ++k) {
        const Neighbour& nb = neighbours_[k];
        const std::size_t t = row_start + j + static_cast<std::size_t>(nb.offset);
        Masks known;
        Floats weight;
        std::memcpy(&known, known_mask_.data() + t, sizeof known);
        std::memcpy(&weight, weight_.data() + t, sizeof weight);
        const Floats add = weight * nb.factor;
        // A select by bits: the sum is formed for every cell (a conditional
        // float add is a branch to the compiler) and kept only where known.
        const Floats sum = total + add;
        total = reinterpret_cast<Floats>((reinterpret_cast<Masks>(sum) & known) |
                                         (reinterpret_cast<Masks>(total) & ~known));
        count -= known;  // all ones is -1
        quadrants |= known & nb.quadrant_bit;
      }
      std::memcpy(count_.data() + j, &count, sizeof count);
      std::memcpy(quadrants_.data() + j, &quadrants, sizeof quadrants);
      std::memcpy(total_.data() + j, &total, sizeof total);
    }
    // The row's unknown cells listed first, without a branch: measured or
    // not is as random as the map, a loop over the list is not.
    std::size_t unknown_count = 0;
    for (std::size_t j = 0; j < un; ++j) {
      unknown_columns_[unknown_count] = j;
      unknown_count += known_[row_start + j] == 0 ? 1 : 0;
    }
    for (std::size_t u = 0; u < unknown_count; ++u) {
      const std::size_t j = unknown_columns_[u];
      const auto count = static_cast<std::int32_t>(count_[j]);
      const auto quadrants = static_cast<int>(kQuadrantsIn[quadrants_[j]]);
      const float total_weight = total_[j];
      if (count < options_.min_known_neighbours || quadrants < options_.min_quadrants || total_weight <= 0.0f) {
        continue;
      }
      result_[slot_[i * un + j]] = sorted_walk(row_start + j, total_weight);
    }
  }
}

std::size_t WeightedMedianFill::write_results_to(ElevationMap& map) {
  // A pass on vectors for the cells that keep or take a value, then every
  // layer reset (reset_slot) for the cells left without one, found eight
  // flags at a time (few in a map with small holes).
  const std::size_t cells = result_.size();
  reset_.resize((cells + 7) / 8 * 8);
  std::fill(reset_.begin() + static_cast<std::ptrdiff_t>(cells), reset_.end(), std::uint8_t{0});  // write_results writes the rest
  const std::size_t filled = write_results(result_.data(), cells, map.elevation_data(), map.state_data(), reset_.data());
  for (std::size_t s = 0; s < cells; s += 8) {
    std::uint64_t flags;
    std::memcpy(&flags, reset_.data() + s, sizeof flags);
    while (flags != 0) {
      const auto byte = static_cast<std::size_t>(std::countr_zero(flags)) / 8;
      map.reset_slot(s + byte);
      flags &= ~(std::uint64_t{0xff} << (8 * byte));
    }
  }
  return filled;
}

std::size_t WeightedMedianFill::fill_prepared(ElevationMap& map) {
  const int n = map.cells_per_side();
  result_.assign(static_cast<std::size_t>(n) * static_cast<std::size_t>(n), kNaN);
  list_neighbours();
  if (options_.window_radius_cells <= 2 && window_sums_exact()) {
    fill_exact_windows();
  } else {
    fill_row_by_row();
  }
  return write_results_to(map);
}

}  // namespace stridemap
