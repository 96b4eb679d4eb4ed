// The fast fill-in and CAS filter give bit for bit the maps of the kept
// reference (fill_reference.hpp, the straightforward code) over
// random maps: several seeds and sizes, windows moved so that the circular
// buffer wraps, holes, spikes, steps, filled cells from an earlier pass,
// elevations on a coarse grid so that equal values (the tie-breaking path)
// are common, certainties that keep every sum exact (the sort-free path) or
// not, zeros of either sign and NaN heights, and non-default options.
#include <gtest/gtest.h>

#include <cstring>
#include <limits>
#include <random>

#include "core/fill_reference.hpp"
#include "stridemap/core/cas_filter.hpp"
#include "stridemap/core/weighted_median_fill.hpp"

namespace stridemap {
namespace {

// How the certainties and elevations of a random map are drawn: the fast
// fill takes a sort-free path when every sum of weights is exact (whole
// sixteenths) and no value is a zero or NaN, the sorted walk otherwise.
enum class Draw {
  whole,        // certainties 1..12: exact sums
  sixteenths,   // certainties k / 16: exact sums with fractions
  arbitrary,    // any float certainty: sums rounded, the sorted walk
  huge,         // certainties near 2^20: whole, but a window's sum is not exact
  special,      // whole certainties with zeros (+0 and -0) and NaN elevations,
                // zero and infinite certainties among them
  infinite,     // whole certainties (zeros among them: exact sums) with
                // +inf and -inf elevations, rows all unknown or all measured
};

ElevationMap random_map(int n, std::uint64_t seed, bool coarse_values, Draw draw = Draw::whole) {
  ElevationMap map({n, 0.01});
  std::mt19937_64 rng(seed);
  std::uniform_real_distribution<double> u(0.0, 1.0);
  map.move_corner_to({static_cast<std::int64_t>(u(rng) * 1000) - 500, static_cast<std::int64_t>(u(rng) * 1000) - 500});
  const double unknown = 0.1 + 0.5 * u(rng);
  for (int i = 0; i < n; ++i) {
    // Whole rows unknown or measured: rows with no window to fill, or all.
    const int row_kind = draw == Draw::infinite ? static_cast<int>(u(rng) * 6) : 2;
    for (int j = 0; j < n; ++j) {
      const std::size_t s = map.slot(map.cell_at_local(i, j));
      const double r = u(rng);
      if (row_kind == 0 || (row_kind != 1 && r < unknown)) continue;
      double h = 0.002 * i - 0.001 * j + 0.01 * u(rng) + (j > n / 2 ? 0.05 : 0.0);  // a step across the map
      if (u(rng) < 0.03) h += 0.1;                                               // a spike
      if (coarse_values) h = std::round(h * 200.0) / 200.0;                     // 5 mm steps: many ties
      const bool filled = u(rng) < 0.05;
      float certainty = static_cast<float>(1 + static_cast<int>(u(rng) * 12));
      auto height = static_cast<float>(h);
      switch (draw) {
        case Draw::whole: break;
        case Draw::sixteenths: certainty = static_cast<float>(1 + static_cast<int>(u(rng) * 200)) / 16.0f; break;
        case Draw::arbitrary: certainty = static_cast<float>(0.01 + 12.0 * u(rng)); break;
        case Draw::huge: certainty = static_cast<float>(1 << 20) + static_cast<float>(static_cast<int>(u(rng) * 8)); break;
        case Draw::special: {
          const double x = u(rng);
          if (x < 0.04) height = 0.0f;
          else if (x < 0.08) height = -0.0f;
          else if (x < 0.09) height = std::numeric_limits<float>::quiet_NaN();
          else if (x < 0.11) certainty = 0.0f;
          else if (x < 0.115) certainty = std::numeric_limits<float>::infinity();
          break;
        }
        case Draw::infinite: {
          const double x = u(rng);
          if (x < 0.03) height = std::numeric_limits<float>::infinity();
          else if (x < 0.06) height = -std::numeric_limits<float>::infinity();
          else if (x < 0.1) certainty = 0.0f;
          break;
        }
      }
      map.elevation_data()[s] = height;
      map.certainty_data()[s] = filled ? 0.0f : certainty;
      map.state_data()[s] = static_cast<std::uint8_t>(filled ? CellState::filled : CellState::measured);
    }
  }
  return map;
}

void expect_identical(const ElevationMap& a, const ElevationMap& b, const std::string& what) {
  ASSERT_EQ(a.layer_count(), b.layer_count());
  const auto cells = static_cast<std::size_t>(a.cells_per_side()) * static_cast<std::size_t>(a.cells_per_side());
  for (std::size_t l = 0; l < a.layer_count(); ++l) {
    const std::size_t bytes = cells * layer_type_bytes(a.layer_spec(l).type);
    EXPECT_EQ(0, std::memcmp(a.layer_bytes(l), b.layer_bytes(l), bytes)) << what << ", layer " << a.layer_spec(l).name;
  }
}

// Fills a copy of `original` with the library and another with the
// reference; checks the counts and every layer's bytes agree. Returns the
// cells filled.
std::size_t fill_matches_reference(const ElevationMap& original, const FillOptions& options, const std::string& what) {
  ElevationMap fast = original, reference = original;
  WeightedMedianFill fill(options);
  const std::size_t filled = fill.apply(fast);
  EXPECT_EQ(filled, reference::reference_fill(reference, options)) << what;
  expect_identical(fast, reference, what);
  return filled;
}

std::vector<FillOptions> fill_options() {
  std::vector<FillOptions> all(4);
  all[1].window_radius_cells = 1;
  all[1].min_known_neighbours = 3;
  all[1].min_quadrants = 2;
  all[2].window_radius_cells = 3;
  all[2].near_weight = 3.5;
  all[2].max_quartile_spread_m = 0.0;  // no spread test
  all[3].window_radius_cells = 7;
  all[3].min_known_neighbours = 1;
  all[3].min_quadrants = 1;
  all[3].max_quartile_spread_m = 0.2;
  return all;
}

TEST(FillReference, FastFillMatchesTheReferenceBitForBit) {
  std::size_t filled = 0;
  for (std::uint64_t seed = 1; seed <= 12; ++seed) {
    for (const bool coarse : {false, true}) {
      const int n = seed % 3 == 0 ? 37 : 100;
      const ElevationMap original = random_map(n, seed, coarse, seed <= 6 ? Draw::whole : Draw::sixteenths);
      for (const FillOptions& options : fill_options()) {
        ElevationMap fast = original, reference = original;
        WeightedMedianFill fill(options);
        const std::size_t a = fill.apply(fast);
        const std::size_t b = reference::reference_fill(reference, options);
        EXPECT_EQ(a, b);
        filled += a;
        expect_identical(fast, reference, "seed " + std::to_string(seed) + (coarse ? " coarse" : ""));
        // A second pass re-estimates the filled cells: still the same.
        EXPECT_EQ(fill.apply(fast), reference::reference_fill(reference, options));
        expect_identical(fast, reference, "second pass, seed " + std::to_string(seed));
      }
    }
  }
  EXPECT_GT(filled, 1000u);  // the maps do exercise the fill
}

// The sorted walk (rounded sums, huge sums) and the values that decide the
// path per window (zeros of either sign, NaN) against the reference.
TEST(FillReference, FastFillMatchesTheReferenceOnEveryPath) {
  std::size_t filled = 0;
  for (const Draw draw : {Draw::arbitrary, Draw::huge, Draw::special}) {
    for (std::uint64_t seed = 41; seed <= 46; ++seed) {
      const bool coarse = seed % 2 == 0;
      const ElevationMap original = random_map(seed % 3 == 0 ? 23 : 60, seed, coarse, draw);
      for (const FillOptions& options : fill_options()) {
        filled += fill_matches_reference(
            original, options, "draw " + std::to_string(static_cast<int>(draw)) + ", seed " + std::to_string(seed));
      }
    }
  }
  EXPECT_GT(filled, 1000u);
}

// The edges of the eight-lane path: maps smaller than a window (every
// window reaches past the map), infinite heights with exact sums, rows with
// every cell unknown or every cell measured, and every radius.
TEST(FillReference, FastFillMatchesTheReferenceAtTheEdges) {
  std::size_t filled = 0;
  for (std::uint64_t seed = 61; seed <= 72; ++seed) {
    const int sizes[] = {1, 2, 3, 4, 5, 7, 9, 16, 31};
    const int n = sizes[seed % 9];
    for (const Draw draw : {Draw::whole, Draw::infinite}) {
      const ElevationMap original = random_map(n, seed, seed % 2 == 0, draw);
      std::vector<FillOptions> all = fill_options();
      all.push_back({});
      all.back().min_known_neighbours = 1;
      all.back().min_quadrants = 1;  // windows with a single known cell
      all.push_back(all.back());
      all.back().window_radius_cells = 1;
      for (const FillOptions& options : all) {
        filled += fill_matches_reference(original, options, "n " + std::to_string(n) + ", seed " + std::to_string(seed));
      }
    }
  }
  for (std::uint64_t seed = 81; seed <= 84; ++seed) {
    const ElevationMap original = random_map(100, seed, seed % 2 == 0, Draw::infinite);
    for (const FillOptions& options : fill_options()) {
      filled += fill_matches_reference(original, options, "infinite heights, seed " + std::to_string(seed));
    }
  }
  EXPECT_GT(filled, 1000u);
}

TEST(FillReference, FastCasMatchesTheReferenceBitForBit) {
  std::size_t removed = 0;
  for (std::uint64_t seed = 21; seed <= 32; ++seed) {
    for (const bool coarse : {false, true}) {
      // Every third seed with zeros, NaN heights and infinite certainties:
      // the median by nth_element, not by a count.
      const ElevationMap original =
          random_map(seed % 3 == 0 ? 41 : 100, seed, coarse, seed % 3 == 1 ? Draw::special : Draw::whole);
      std::vector<CasOptions> all(3);
      all[0].max_removable_certainty = 6.0;  // more candidates than the default
      all[1].window_radius_cells = 1;
      all[1].min_agreeing_neighbours = 0;
      all[2].window_radius_cells = 4;
      all[2].min_agreeing_neighbours = 5;
      all[2].max_removable_certainty = 12.0;
      all[2].fill.window_radius_cells = 3;
      // Limits that no float equals, just below and above a certainty of 3
      // (the fast test compares in float), and the fill's radius 1.
      all.push_back({});
      all.back().max_removable_certainty = 3.0 - 1e-12;
      all.back().fill.window_radius_cells = 1;
      all.push_back({});
      all.back().max_removable_certainty = 3.0 + 1e-12;
      all.back().min_agreeing_neighbours = 4;
      for (const CasOptions& options : all) {
        ElevationMap fast = original, reference = original;
        CasFilter cas(options);
        const CasResult a = cas.apply(fast);
        const CasResult b = reference::reference_cas(reference, options);
        EXPECT_EQ(a.removed, b.removed);
        EXPECT_EQ(a.filled, b.filled);
        removed += a.removed;
        expect_identical(fast, reference, "CAS, seed " + std::to_string(seed));
      }
    }
  }
  EXPECT_GT(removed, 100u);  // the maps do exercise the removal
}

// CAS on maps of 1 to 20 cells a side with the narrowest margin (radius 1
// for CAS and its fill): the removable cells of a row are listed 8 at a
// time, and the flags read past the row's end (the next row's cells when
// the margin is narrow) must not be listed.
TEST(FillReference, FastCasMatchesTheReferenceOnSmallMaps) {
  std::size_t removed = 0;
  for (int n = 1; n <= 20; ++n) {
    for (std::uint64_t seed = 91; seed <= 93; ++seed) {
      const ElevationMap original = random_map(n, seed + 10 * static_cast<std::uint64_t>(n), seed % 2 == 0);
      CasOptions options;
      options.window_radius_cells = 1;
      options.fill.window_radius_cells = 1;
      options.min_agreeing_neighbours = 3;
      options.max_removable_certainty = 12.0;  // every measured cell a candidate
      options.certainty_ratio = 2.0;
      ElevationMap fast = original, reference = original;
      CasFilter cas(options);
      const CasResult a = cas.apply(fast);
      const CasResult b = reference::reference_cas(reference, options);
      EXPECT_EQ(a.removed, b.removed) << "n " << n << ", seed " << seed;
      EXPECT_EQ(a.filled, b.filled) << "n " << n << ", seed " << seed;
      removed += a.removed;
      expect_identical(fast, reference, "CAS, n " + std::to_string(n) + ", seed " + std::to_string(seed));
    }
  }
  EXPECT_GT(removed, 20u);  // the small maps do exercise the removal
}

}  // namespace
}  // namespace stridemap
