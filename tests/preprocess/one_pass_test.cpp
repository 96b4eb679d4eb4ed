// The one-pass clustering test (evenly spaced beams) and the chain's
// checked-scan entries against the way they replaced, bit for bit: range
// clustering as a pair-by-pair loop over a RangeRatioBandCache, and the
// chain's stages run one by one through their public entries.
#include <gtest/gtest.h>

#include <cstring>
#include <limits>
#include <random>
#include <vector>

#include "stridemap/preprocess/range_clustering.hpp"
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

TEST(OnePassClustering, TheChainMatchesItsStagesRunOneByOne) {
  ScanFilterChainOptions options;
  ScanFilterChain chain(parse_scan_filter_list("urg"), options);
  RangeClusteringFilter clustering(options.range_clustering);
  ScanSequenceOptions sequence_options = options.scan_sequence;
  sequence_options.between_scans.enabled = true;
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
    ASSERT_EQ(sequence.last_stats().removed, chain.stats_of_stage(1).removed + chain.stats_of_stage(2).removed) << seed;
    ++compared;
    removed_beams += sequence.last_stats().removed;
  }
  EXPECT_EQ(compared, 29u);
  EXPECT_GT(removed_beams, 0u);  // the scan-sequence stages had something to judge
}

}  // namespace
}  // namespace stridemap
