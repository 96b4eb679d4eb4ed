#include "stridemap/preprocess/speckle_filter.hpp"

#include <gtest/gtest.h>

#include <cmath>

#include "test_scans.hpp"

namespace stridemap {
namespace {

SpeckleFilterOptions with_mode(SpeckleMode mode) {
  SpeckleFilterOptions options;
  options.mode = mode;
  return options;
}

class SpeckleModes : public ::testing::TestWithParam<SpeckleMode> {};

TEST_P(SpeckleModes, RemovesIsolatedPointsAndPairsKeepsTheWall) {
  PlanarScan scan = test::centred_scan(121);
  test::put_on_line_x(scan, 0, 120, 0.5);
  scan.range_m[20] += 0.15;                           // single point behind
  scan.range_m[60] -= 0.12;                           // single point in front
  scan.range_m[90] += 0.2;                            // a pair
  scan.range_m[91] = scan.range_m[90];
  std::vector<std::uint8_t> removed;
  const ScanFilterStats stats = SpeckleFilter(with_mode(GetParam())).apply(scan, removed);
  EXPECT_EQ(stats.removed, 4u);
  EXPECT_EQ(removed[20], 1);
  EXPECT_EQ(removed[60], 1);
  EXPECT_EQ(removed[90], 1);
  EXPECT_EQ(removed[91], 1);
}

TEST_P(SpeckleModes, KeepsAGroupOfFourPoints) {
  // Distance mode keeps runs of `window` (3) points; radius mode needs
  // `window` neighbours for each point, so a group of window + 1.
  PlanarScan scan = test::centred_scan(121);
  test::put_on_line_x(scan, 0, 120, 0.5);
  for (std::size_t i = 50; i <= 53; ++i) scan.range_m[i] += 0.2;
  std::vector<std::uint8_t> removed;
  EXPECT_EQ(SpeckleFilter(with_mode(GetParam())).apply(scan, removed).removed, 0u);
}

TEST_P(SpeckleModes, PointsBeyondMaxRangeAreNotTested) {
  PlanarScan scan = test::centred_scan(41);
  test::put_on_line_x(scan, 0, 40, 0.5);
  scan.range_m[20] = 3.0;
  SpeckleFilterOptions options = with_mode(GetParam());
  options.max_range_m = 2.0;
  std::vector<std::uint8_t> removed;
  EXPECT_EQ(SpeckleFilter(options).apply(scan, removed).removed, 0u);
}

TEST_P(SpeckleModes, EmptyAndAllInvalidScansPassThrough) {
  SpeckleFilter filter(with_mode(GetParam()));
  std::vector<std::uint8_t> removed;
  PlanarScan empty;
  EXPECT_EQ(filter.apply(empty, removed).removed, 0u);
  PlanarScan invalid = test::centred_scan(17);
  const ScanFilterStats stats = filter.apply(invalid, removed);
  EXPECT_EQ(stats.invalid_input, 17u);
  EXPECT_EQ(stats.removed, 0u);
}

INSTANTIATE_TEST_SUITE_P(BothModes, SpeckleModes,
                         ::testing::Values(SpeckleMode::distance, SpeckleMode::radius_outlier));

TEST(SpeckleFilter, DistanceRunsAreMeasuredFromTheRunsFirstRange) {
  // Ranges climbing 3 cm per beam: each step is within 5 cm, but over a run of
  // three the third is 6 cm from the first, so no run exists.
  PlanarScan scan = test::centred_scan(10);
  for (std::size_t i = 0; i < 10; ++i) scan.range_m[i] = 0.5 + 0.03 * static_cast<double>(i);
  std::vector<std::uint8_t> removed;
  EXPECT_EQ(SpeckleFilter().apply(scan, removed).removed, 10u);
}

TEST(SpeckleFilter, ScanShorterThanTheWindowHasNoRun) {
  PlanarScan scan = test::centred_scan(2);
  scan.range_m = {0.5, 0.5};
  std::vector<std::uint8_t> removed;
  EXPECT_EQ(SpeckleFilter().apply(scan, removed).removed, 2u);
  SpeckleFilterOptions one;
  one.window = 1;
  scan.range_m = {0.5, 0.9};
  EXPECT_EQ(SpeckleFilter(one).apply(scan, removed).removed, 0u);
}

TEST(SpeckleFilter, InvalidBeamsBreakRuns) {
  PlanarScan scan = test::centred_scan(7);
  scan.range_m = {0.5, 0.5, test::nan, 0.5, 0.5, 0.5, 0.5};
  std::vector<std::uint8_t> removed;
  const ScanFilterStats stats = SpeckleFilter().apply(scan, removed);
  EXPECT_EQ(stats.removed, 2u);
  EXPECT_EQ(removed[0], 1);
  EXPECT_EQ(removed[1], 1);
}

TEST(SpeckleFilter, RejectsBadOptions) {
  SpeckleFilterOptions options;
  options.window = 0;
  std::string message = test::input_error_message([&] { SpeckleFilter filter(options); });
  EXPECT_NE(message.find("SpeckleFilterOptions: window"), std::string::npos) << message;
  options = {};
  options.max_range_difference_m = -0.1;
  message = test::input_error_message([&] { SpeckleFilter filter(options); });
  EXPECT_NE(message.find("max_range_difference_m"), std::string::npos) << message;
}

}  // namespace
}  // namespace stridemap
