#include "stridemap/preprocess/range_clustering.hpp"

#include <gtest/gtest.h>

#include <cmath>

#include "test_scans.hpp"

namespace stridemap {
namespace {

using test::deg;
using test::nan;

TEST(RangeRatioBand, IntendedBoundsWidenTheBandAroundOne) {
  const RangeRatioBand band = range_ratio_band(deg(0.36), deg(75.0));
  const double slope = deg(0.36) * std::tan(deg(75.0));  // small-step approximation
  EXPECT_NEAR(band.lower_factor, 1.0 - slope, 1e-3);
  EXPECT_NEAR(band.upper_factor, 1.0 + slope, 1e-3);
  EXPECT_LT(band.lower_factor, 1.0);
  EXPECT_GT(band.upper_factor, 1.0);
}

TEST(RangeRatioBand, MessorSimBoundsAreSwapped) {
  const RangeRatioBand band = range_ratio_band(deg(0.36), deg(75.0), true);
  EXPECT_NEAR(band.lower_factor, 1.0235, 5e-4);
  EXPECT_NEAR(band.upper_factor, 0.9764, 5e-4);
}

TEST(RangeRatioBand, NoUpperLimitWhenTheNextBeamCanRunAlongTheSurface) {
  const RangeRatioBand band = range_ratio_band(deg(20.0), deg(75.0));
  EXPECT_TRUE(std::isinf(band.upper_factor));
}

TEST(RangeRatioBand, AcceptedStepAtHalfAMetreMatchesAlgorithmsNotes) {
  // sigma = 10 mm as in MessorSim: intended band +-42 mm, swapped +-18 mm.
  const double tolerance = 3.0 * 0.010;
  const RangeRatioBand intended = range_ratio_band(deg(0.36), deg(75.0));
  const RangeRatioBand swapped = range_ratio_band(deg(0.36), deg(75.0), true);
  EXPECT_TRUE(ranges_on_one_surface(0.5, 0.540, tolerance, intended));
  EXPECT_TRUE(ranges_on_one_surface(0.5, 0.460, tolerance, intended));
  EXPECT_FALSE(ranges_on_one_surface(0.5, 0.545, tolerance, intended));
  EXPECT_FALSE(ranges_on_one_surface(0.5, 0.540, tolerance, swapped));
  EXPECT_TRUE(ranges_on_one_surface(0.5, 0.515, tolerance, swapped));
  EXPECT_FALSE(ranges_on_one_surface(0.5, 0.520, tolerance, swapped));
}

class RangeClusteringWall : public ::testing::Test {
 protected:
  void SetUp() override {
    scan = test::centred_scan(121);
    test::put_on_line_x(scan, 0, 120, 0.5);
  }
  PlanarScan scan;
  std::vector<std::uint8_t> removed;
  RangeClusteringFilter filter;
  RangeClusteringFilter bridging{[] {
    RangeClusteringOptions o;
    o.max_bridged_invalid_beams = 2;
    return o;
  }()};
};

TEST_F(RangeClusteringWall, KeepsAPlainWall) {
  const ScanFilterStats stats = filter.apply(scan, removed);
  EXPECT_EQ(stats.removed, 0u);
  EXPECT_EQ(test::count_valid(scan), 121u);
  for (const int label : filter.cluster_labels()) EXPECT_EQ(label, 0);
}

TEST_F(RangeClusteringWall, RemovesAnIsolatedPointInFront) {
  scan.range_m[60] -= 0.10;
  const ScanFilterStats stats = filter.apply(scan, removed);
  EXPECT_EQ(stats.removed, 1u);
  EXPECT_EQ(removed[60], 1);
  EXPECT_TRUE(std::isnan(scan.range_m[60]));
  EXPECT_EQ(test::count_valid(scan), 120u);
  EXPECT_EQ(filter.cluster_labels()[59], 0);
  EXPECT_EQ(filter.cluster_labels()[60], 1);
  EXPECT_EQ(filter.cluster_labels()[61], 2);
}

TEST_F(RangeClusteringWall, RemovesASmallGroupBehind) {
  for (std::size_t i = 30; i <= 31; ++i) scan.range_m[i] += 0.08;
  const ScanFilterStats stats = filter.apply(scan, removed);
  EXPECT_EQ(stats.removed, 2u);
  for (std::size_t i = 30; i <= 31; ++i) EXPECT_EQ(removed[i], 1) << i;
  EXPECT_EQ(test::count_marked(removed), 2u);
}

TEST_F(RangeClusteringWall, KeepsAGroupOfMinClusterPoints) {
  for (std::size_t i = 80; i <= 82; ++i) scan.range_m[i] += 0.08;
  EXPECT_EQ(filter.apply(scan, removed).removed, 0u);
}

TEST_F(RangeClusteringWall, TheAuthorsSizeRemovesGroupsOfFour) {
  // MessorSim deletes clusters of up to 4 points (min_cluster_points = 5).
  RangeClusteringOptions options;
  options.min_cluster_points = 5;
  RangeClusteringFilter authors(options);
  for (std::size_t i = 30; i <= 33; ++i) scan.range_m[i] += 0.08;
  for (std::size_t i = 80; i <= 84; ++i) scan.range_m[i] += 0.08;
  const ScanFilterStats stats = authors.apply(scan, removed);
  EXPECT_EQ(stats.removed, 4u);
  for (std::size_t i = 30; i <= 33; ++i) EXPECT_EQ(removed[i], 1) << i;
  EXPECT_EQ(test::count_marked(removed), 4u);
}

TEST_F(RangeClusteringWall, ThePublishedRuleEndsClustersAtInvalidBeams) {
  RangeClusteringFilter& unbridged = filter;  // the default
  scan.range_m[10] = nan;
  scan.range_m[13] = -1.0;  // negative: treated as no return
  const ScanFilterStats stats = unbridged.apply(scan, removed);
  EXPECT_EQ(stats.invalid_input, 2u);
  EXPECT_EQ(stats.removed, 2u);
  for (std::size_t i = 11; i <= 12; ++i) EXPECT_EQ(removed[i], 1) << i;
  EXPECT_EQ(unbridged.cluster_labels()[10], -1);
  EXPECT_TRUE(std::isnan(scan.range_m[13]));
}

TEST_F(RangeClusteringWall, ShortDropoutsOnOneSurfaceAreBridged) {
  // A dark floor: two valid beams between dropouts of one and two beams.
  scan.range_m[10] = nan;
  scan.range_m[13] = -1.0;
  scan.range_m[14] = nan;
  const ScanFilterStats stats = bridging.apply(scan, removed);
  EXPECT_EQ(stats.invalid_input, 3u);
  EXPECT_EQ(stats.removed, 0u);
  EXPECT_EQ(test::count_marked(removed), 0u);
  EXPECT_EQ(test::count_valid(scan), 118u);
  EXPECT_EQ(bridging.cluster_labels()[9], bridging.cluster_labels()[15]);
  EXPECT_EQ(bridging.cluster_labels()[10], -1);
}

TEST_F(RangeClusteringWall, ALongerDropoutEndsTheCluster) {
  for (std::size_t i = 10; i <= 12; ++i) scan.range_m[i] = nan;
  for (std::size_t i = 15; i <= 17; ++i) scan.range_m[i] = nan;
  const ScanFilterStats stats = bridging.apply(scan, removed);
  EXPECT_EQ(stats.removed, 2u);
  for (std::size_t i = 13; i <= 14; ++i) EXPECT_EQ(removed[i], 1) << i;
  EXPECT_EQ(test::count_marked(removed), 2u);
  EXPECT_NE(bridging.cluster_labels()[9], bridging.cluster_labels()[13]);
}

TEST_F(RangeClusteringWall, BridgingDoesNotCrossAJumpInRange) {
  // Mixed pixels next to a dropout: a two-beam group 80 mm behind the wall
  // is still its own cluster, and the invalid beams are not marked removed.
  scan.range_m[30] = nan;
  for (std::size_t i = 31; i <= 32; ++i) scan.range_m[i] += 0.08;
  scan.range_m[33] = nan;
  const ScanFilterStats stats = bridging.apply(scan, removed);
  EXPECT_EQ(stats.removed, 2u);
  for (std::size_t i = 31; i <= 32; ++i) EXPECT_EQ(removed[i], 1) << i;
  EXPECT_EQ(removed[30], 0);
  EXPECT_EQ(removed[33], 0);
  // The segmentation is sequential: the wall after the group starts anew.
  const auto& labels = bridging.cluster_labels();
  EXPECT_EQ(labels[31], labels[32]);
  EXPECT_NE(labels[29], labels[31]);
  EXPECT_NE(labels[34], labels[31]);
}

TEST_F(RangeClusteringWall, BridgedClustersAreSizedByTheirValidBeams) {
  // Two valid beams around a one-beam dropout, walled off by longer gaps:
  // four beams wide but only two points, so still too small.
  for (std::size_t i = 40; i <= 42; ++i) scan.range_m[i] = nan;
  scan.range_m[44] = nan;
  for (std::size_t i = 46; i <= 48; ++i) scan.range_m[i] = nan;
  const ScanFilterStats stats = bridging.apply(scan, removed);
  EXPECT_EQ(stats.removed, 2u);
  EXPECT_EQ(removed[43], 1);
  EXPECT_EQ(removed[45], 1);
  EXPECT_EQ(removed[44], 0);
}

TEST_F(RangeClusteringWall, NoisyWallStaysOneSurface) {
  test::add_noise(scan, 0.003, 42);
  EXPECT_EQ(filter.apply(scan, removed).removed, 0u);
}

TEST(RangeClustering, MinExtentRemovesShortClusters) {
  PlanarScan scan = test::centred_scan(20);
  test::put_on_line_x(scan, 6, 13, 0.5);  // 8 points spanning about 21 mm
  std::vector<std::uint8_t> removed;
  RangeClusteringOptions options;
  options.min_cluster_extent_m = 0.03;
  EXPECT_EQ(RangeClusteringFilter(options).apply(scan, removed).removed, 8u);
  test::put_on_line_x(scan, 6, 13, 0.5);
  options.min_cluster_extent_m = 0.01;
  EXPECT_EQ(RangeClusteringFilter(options).apply(scan, removed).removed, 0u);
}

TEST(RangeClustering, ObliqueSurfaceKeptByIntendedBandSplitByMessorSimBand) {
  // A plane seen at 65-75 deg incidence about 0.8 m away.
  PlanarScan scan = test::centred_scan(29);
  const double normal = deg(70.0);
  const double distance = 0.8 * std::cos(normal);
  for (std::size_t i = 0; i < scan.size(); ++i) scan.range_m[i] = distance / std::cos(scan.angle_rad[i] - normal);
  PlanarScan copy = scan;
  std::vector<std::uint8_t> removed;
  EXPECT_EQ(RangeClusteringFilter().apply(scan, removed).removed, 0u);
  RangeClusteringOptions compat;
  compat.messorsim_swapped_bounds = true;
  EXPECT_EQ(RangeClusteringFilter(compat).apply(copy, removed).removed, 29u);
}

TEST(RangeClustering, EmptyAndAllInvalidScansPassThrough) {
  RangeClusteringFilter filter;
  std::vector<std::uint8_t> removed(3, 1);
  PlanarScan empty;
  const ScanFilterStats empty_stats = filter.apply(empty, removed);
  EXPECT_EQ(empty_stats.beams, 0u);
  EXPECT_TRUE(removed.empty());
  PlanarScan invalid = test::centred_scan(50);
  const ScanFilterStats stats = filter.apply(invalid, removed);
  EXPECT_EQ(stats.invalid_input, 50u);
  EXPECT_EQ(stats.removed, 0u);
  EXPECT_EQ(removed.size(), 50u);
}

TEST(RangeClustering, MismatchedScanIsAnInputError) {
  PlanarScan scan = test::centred_scan(10);
  scan.angle_rad.pop_back();
  std::vector<std::uint8_t> removed;
  RangeClusteringFilter filter;
  const std::string message = test::input_error_message([&] { filter.apply(scan, removed); });
  EXPECT_NE(message.find("range clustering"), std::string::npos) << message;
  EXPECT_NE(message.find("9 angles, 10 ranges"), std::string::npos) << message;
}

TEST(RangeClustering, RejectsIncidenceAngleOfNinetyDegrees) {
  RangeClusteringOptions options;
  options.max_incidence_angle_rad = deg(90.0);
  const std::string message = test::input_error_message([&] { RangeClusteringFilter filter(options); });
  EXPECT_NE(message.find("max_incidence_angle_rad"), std::string::npos) << message;
  EXPECT_NE(message.find("90 deg"), std::string::npos) << message;
}

}  // namespace
}  // namespace stridemap
