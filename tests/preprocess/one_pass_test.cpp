// The one-pass clustering test (evenly spaced beams) and the chain's
// checked-scan entries against the way they replaced, bit for bit: range
// clustering as a pair-by-pair loop over a RangeRatioBandCache, and the
// chain's stages run one by one through their public entries.
#include <gtest/gtest.h>

#include <cstring>
#include <limits>
#include <random>
#include <string_view>
#include <vector>

#include "stridemap/preprocess/line_extraction.hpp"
#include "stridemap/preprocess/range_clustering.hpp"
#include "stridemap/preprocess/scan_sequence.hpp"
#include "stridemap/preprocess/scan_filter_chain.hpp"
#include "test_scans.hpp"

namespace stridemap {
namespace {

// A noisy floor with boxes, in-between readings at their edges, dropouts,
// a few unusable ranges and beams without a Delta r of their own.
PlanarScan cluttered_scan(std::uint64_t seed) {
  std::mt19937_64 engine(seed);
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  std::normal_distribution<double> noise(0.0, 0.004);
  PlanarScan scan = test::centred_scan(683);
  double x = 0.5;
  for (std::size_t i = 0; i < scan.size(); ++i) {
    if (unit(engine) < 0.02) x = 0.25 + 0.5 * unit(engine);  // an edge
    scan.range_m[i] = x / std::cos(scan.angle_rad[i]) + noise(engine);
    const double u = unit(engine);
    if (u < 0.05) scan.range_m[i] = test::nan;
    else if (u < 0.06) scan.range_m[i] = u < 0.055 ? -1.0 : std::numeric_limits<double>::infinity();
    else if (u < 0.10) scan.range_m[i] *= 0.8 + 0.4 * unit(engine);  // mixed
    if (unit(engine) < 0.03) scan.range_error_m[i] = unit(engine) < 0.5 ? test::nan : 0.0;
  }
  return scan;
}

bool same_bits(const std::vector<double>& a, const std::vector<double>& b) {
  return a.size() == b.size() && std::memcmp(a.data(), b.data(), a.size() * sizeof(double)) == 0;
}

// RangeClusteringFilter's loop before the one-pass test (no bridging).
void cluster_pair_by_pair(const RangeClusteringOptions& o, PlanarScan& scan, std::vector<std::uint8_t>& removed,
                          std::vector<int>& labels) {
  prepare_scan_for_filter(scan, removed, "reference");
  const std::size_t n = scan.size();
  labels.assign(n, -1);
  RangeRatioBandCache bands(o.max_incidence_angle_rad, o.messorsim_swapped_bounds);
  std::size_t first = n, points = 0;
  int label = -1;
  const auto close = [&](std::size_t last) {
    if (points < o.min_cluster_points) {
      for (std::size_t i = first; i <= last; ++i) removed[i] = 1;
    }
    first = n;
  };
  for (std::size_t i = 0; i < n; ++i) {
    if (std::isnan(scan.range_m[i])) {
      if (first != n) close(i - 1);
      continue;
    }
    if (first != n) {
      const double tolerance = o.noise_sigmas * o.sigma.sigma_m(scan.range_m[i - 1], scan.range_error_m[i - 1]);
      if (!ranges_on_one_surface(scan.range_m[i - 1], scan.range_m[i], tolerance,
                                 bands.band(scan.angle_rad[i] - scan.angle_rad[i - 1]))) {
        close(i - 1);
      }
    }
    if (first == n) {
      first = i;
      points = 0;
      ++label;
    }
    labels[i] = label;
    ++points;
  }
  if (first != n) close(n - 1);
  apply_removal_mask(scan, removed);
}

TEST(OnePassClustering, MatchesThePairByPairLoopBitForBit) {
  for (int variant = 0; variant < 3; ++variant) {
    RangeClusteringOptions options;
    options.messorsim_swapped_bounds = variant == 1;
    options.sigma.always_use_urg_spec = variant == 2;
    RangeClusteringFilter filter(options);
    for (std::uint64_t seed = 1; seed <= 20; ++seed) {
      PlanarScan scan = cluttered_scan(seed), expected = scan;
      std::vector<std::uint8_t> removed, expected_removed;
      std::vector<int> expected_labels;
      filter.apply(scan, removed);
      cluster_pair_by_pair(options, expected, expected_removed, expected_labels);
      ASSERT_TRUE(same_bits(scan.range_m, expected.range_m)) << variant << " " << seed;
      ASSERT_EQ(removed, expected_removed) << variant << " " << seed;
      ASSERT_EQ(filter.cluster_labels(), expected_labels) << variant << " " << seed;
    }
  }
}

// The test that the clustering hands on: that of the scan it returns, its
// removed beams' pairs broken too (a wrong mask would join across them).
TEST(OnePassClustering, ItsBreaksAreTheTestOfTheScanItReturns) {
  std::size_t removed_beams = 0;
  for (int variant = 0; variant < 3; ++variant) {
    RangeClusteringOptions options;
    options.messorsim_swapped_bounds = variant == 1;
    options.min_cluster_points = variant == 2 ? 8 : 3;
    RangeClusteringFilter filter(options);
    for (std::uint64_t seed = 1; seed <= 20; ++seed) {
      PlanarScan scan = cluttered_scan(seed);
      std::vector<std::uint8_t> removed;
      filter.apply(scan, removed);
      removed_beams += test::count_marked(removed);
      const RangeBreaks& breaks = filter.last_breaks();
      ASSERT_TRUE(breaks.valid);
      ASSERT_EQ(breaks.breaks.size(), scan.size());
      ASSERT_EQ(breaks.breaks[0], 1);
      for (std::size_t i = 1; i < scan.size(); ++i) {
        const double previous = scan.range_m[i - 1], next = scan.range_m[i];
        const bool joined =
            is_usable_range(previous) && is_usable_range(next) &&
            ranges_on_one_surface(previous, next,
                                  options.noise_sigmas * options.sigma.sigma_m(previous, scan.range_error_m[i - 1]),
                                  breaks.band);
        ASSERT_EQ(breaks.breaks[i], joined ? 0 : 1) << variant << " " << seed << " " << i;
      }
    }
  }
  EXPECT_GT(removed_beams, 100u);
}

// Segments from the clustering's mask and from the extractor's own test;
// an extractor whose test differs (a tighter tolerance) must use its own.
TEST(OnePassClustering, TheLineExtractorTakesItsBreaksForTheSameSegments) {
  for (const double break_noise_sigmas : {3.0, 0.5}) {
    RangeClusteringOptions options;
    options.min_cluster_points = 8;
    RangeClusteringFilter filter(options);
    LineExtractionOptions line_options;
    line_options.break_noise_sigmas = break_noise_sigmas;
    LineExtractor with_breaks(line_options), without(line_options);
    std::size_t segments = 0;
    for (std::uint64_t seed = 1; seed <= 20; ++seed) {
      PlanarScan scan = cluttered_scan(seed);
      std::vector<std::uint8_t> removed;
      filter.apply(scan, removed);
      std::vector<LineSegment> expected, taken;
      without.extract(scan, expected);
      with_breaks.extract(scan, taken, LineExtractor::Keep::all, &filter.last_breaks());
      ASSERT_EQ(taken.size(), expected.size()) << seed;
      for (std::size_t k = 0; k < taken.size(); ++k) {
        ASSERT_EQ(taken[k].first_beam, expected[k].first_beam) << seed;
        ASSERT_EQ(taken[k].last_beam, expected[k].last_beam) << seed;
        ASSERT_EQ(std::memcmp(&taken[k].normal_angle_rad, &expected[k].normal_angle_rad, sizeof(double)), 0) << seed;
      }
      segments += taken.size();
    }
    EXPECT_GT(segments, 20u);
  }
}

// A scan-sequence filter given the clustering's masks (the chain's way)
// against one that tests every pair itself, on streams where a judged scan
// that lost beams is the k-1 that the next judgement extracts lines from:
// a box whose edge leaves a veil in every third scan (eq. 12 removes it),
// and a box face with notches, still joined to it, whose readings lie
// between those of the scans around (the between-scans test removes them:
// the face splits there).
TEST(OnePassClustering, TheScanSequenceCarriesTheMasksThroughItsRemovals) {
  constexpr double ground_x = 0.60, face_x = 0.45, top_x = 0.42, half_width = 0.10;
  for (const bool notches : {false, true}) {
    ScanSequenceOptions options;
    options.between_scans.enabled = notches;
    RangeClusteringFilter clustering;
    ScanSequenceFilter with_breaks(options), without(options);
    PlanarScan out, expected, work;
    std::vector<std::uint8_t> removed, expected_removed, clustering_removed;
    std::size_t sectors = 0, removed_beams = 0, compared = 0;
    for (std::uint64_t seed = 1; seed <= 30; ++seed) {
      const std::uint64_t phase = seed % 3;
      PlanarScan scan = test::centred_scan(201);
      test::put_box_scene(scan, ground_x, phase == 2 && !notches ? top_x : face_x, half_width);
      std::size_t first = 0, last = 0;
      test::box_beams(scan, face_x, half_width, first, last);
      if (phase == 1 && !notches) test::put_wavy_veil(scan, first, last, 0.43, 0.55, static_cast<double>(seed));
      if (phase != 0 && notches) {
        for (const std::size_t notch : {first + 20, last - 20}) {
          test::put_on_line_x(scan, notch - 1, notch + 1, phase == 1 ? 0.465 : ground_x);
        }
      }
      test::add_noise(scan, 0.002, seed);
      for (const std::size_t i : {10, 30, 50, 150, 170, 190}) scan.range_m[i] *= 1.3;  // lone beams, off the box
      work = scan;
      const std::size_t invalid = prepare_scan_for_filter(work, clustering_removed, "test").invalid_input;
      clustering.apply_prepared(work, clustering_removed, invalid);
      const bool ready = with_breaks.push_prepared(work, invalid, out, removed, &clustering.last_breaks());
      clustering.apply(scan, clustering_removed);
      ASSERT_EQ(without.push(scan, expected, expected_removed), ready);
      if (!ready) continue;
      ASSERT_TRUE(same_bits(out.range_m, expected.range_m)) << notches << " " << seed;
      ASSERT_EQ(removed, expected_removed) << notches << " " << seed;
      const auto& got = with_breaks.last_sectors();
      const auto& want = without.last_sectors();
      ASSERT_EQ(got.size(), want.size()) << notches << " " << seed;
      for (std::size_t k = 0; k < got.size(); ++k) {
        ASSERT_EQ(got[k].first_beam, want[k].first_beam) << notches << " " << seed;
        ASSERT_EQ(got[k].last_beam, want[k].last_beam) << notches << " " << seed;
        ASSERT_EQ(std::memcmp(&got[k].spread_k_m, &want[k].spread_k_m, sizeof(double)), 0) << notches << " " << seed;
        ASSERT_EQ(got[k].removed, want[k].removed) << notches << " " << seed;
      }
      sectors += got.size();
      removed_beams += test::count_marked(removed);
      ++compared;
    }
    EXPECT_EQ(compared, 29u);
    EXPECT_GT(sectors, 5u) << notches;
    EXPECT_GT(removed_beams, 0u) << notches;
  }
}

// Each stage's count is its mask's: the sequence stages' split of the
// filter's removals, for either of them alone and both.
TEST(OnePassClustering, TheChainMatchesItsStagesRunOneByOne) {
  for (const char* stages : {"paper", "urg", "range-clustering,between-scans"}) {
    const bool between = std::string_view(stages) != "paper";
    ScanFilterChainOptions options;
    ScanFilterChain chain(parse_scan_filter_list(stages), options);
    RangeClusteringFilter clustering(options.range_clustering);
    ScanSequenceOptions sequence_options = options.scan_sequence;
    sequence_options.between_scans.enabled = between;
    sequence_options.spread_test = std::string_view(stages) != "range-clustering,between-scans";
    ScanSequenceFilter sequence(sequence_options);
    PlanarScan out, expected;
    std::vector<std::uint8_t> removed, sequence_removed;
    std::size_t compared = 0, removed_beams = 0;
    for (std::uint64_t seed = 1; seed <= 30; ++seed) {
      PlanarScan scan = cluttered_scan(seed / 3);  // neighbours alike, as a sensor's scans
      // A face that steps back 5 cm a scan, every third scan from the start:
      // the middle scan's readings lie between the others'.
      test::put_on_line_x(scan, 300, 380, 0.5 + 0.05 * static_cast<double>(seed % 3));
      test::add_noise(scan, 0.002, seed);
      const bool ready = chain.push(scan, out);
      clustering.apply(scan, removed);
      ASSERT_EQ(sequence.push(scan, expected, sequence_removed), ready);
      if (!ready) continue;
      ASSERT_TRUE(same_bits(out.range_m, expected.range_m)) << seed;
      ASSERT_EQ(sequence.last_stats().invalid_input, chain.stats_of_stage(1).invalid_input) << seed;
      std::size_t stage_removals = 0;
      for (std::size_t stage = 0; stage < chain.stage_count(); ++stage) {
        ASSERT_EQ(chain.stats_of_stage(stage).removed, test::count_marked(chain.removed_by_stage(stage)))
            << stages << " " << seed << " " << stage;
        if (stage > 0) stage_removals += chain.stats_of_stage(stage).removed;
      }
      ASSERT_EQ(sequence.last_stats().removed, stage_removals) << stages << " " << seed;
      ++compared;
      removed_beams += sequence.last_stats().removed;
    }
    EXPECT_EQ(compared, 29u);
    if (between) EXPECT_GT(removed_beams, 0u);  // the scan-sequence stages had something to judge
  }
}

}  // namespace
}  // namespace stridemap
