#include "stridemap/preprocess/scan_checks.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <limits>

#include "stridemap/core/error.hpp"
#include "stridemap/preprocess/range_sigma.hpp"
#include "test_scans.hpp"

namespace stridemap {
namespace {

using test::nan;

TEST(ScanChecks, MismatchedLengthsNameAllThreeLengthsAndTheFilter) {
  PlanarScan scan = test::centred_scan(10);
  scan.range_m.resize(8);
  const std::string message = test::input_error_message([&] { check_scan_shape(scan, "my filter"); });
  EXPECT_NE(message.find("my filter"), std::string::npos) << message;
  EXPECT_NE(message.find("10 angles, 8 ranges and 10 range errors"), std::string::npos) << message;
}

TEST(ScanChecks, StreamIndexIsNamedWhenGiven) {
  PlanarScan scan = test::centred_scan(4);
  scan.range_error_m.clear();
  const std::string message = test::input_error_message([&] { check_scan_shape(scan, "f", 7); });
  EXPECT_NE(message.find("scan 7 of the stream"), std::string::npos) << message;
}

TEST(ScanChecks, NonFiniteAngleNamesTheBeam) {
  PlanarScan scan = test::centred_scan(6);
  scan.angle_rad[3] = std::numeric_limits<double>::infinity();
  const std::string message = test::input_error_message([&] { check_scan_shape(scan, "f"); });
  EXPECT_NE(message.find("beam 3"), std::string::npos) << message;
}

TEST(ScanChecks, UnusableRangesBecomeNaNAndAreCountedAsInvalidInput) {
  PlanarScan scan = test::centred_scan(6);
  scan.range_m = {0.5, nan, std::numeric_limits<double>::infinity(), -0.3, 0.0,
                  -std::numeric_limits<double>::infinity()};
  std::vector<std::uint8_t> removed(2, 1);
  const ScanFilterStats stats = prepare_scan_for_filter(scan, removed, "f");
  EXPECT_EQ(stats.beams, 6u);
  EXPECT_EQ(stats.invalid_input, 5u);
  EXPECT_EQ(stats.removed, 0u);
  EXPECT_DOUBLE_EQ(scan.range_m[0], 0.5);
  for (std::size_t i = 1; i < 6; ++i) EXPECT_TRUE(std::isnan(scan.range_m[i])) << i;
  ASSERT_EQ(removed.size(), 6u);
  EXPECT_EQ(test::count_marked(removed), 0u);
}

TEST(ScanChecks, RemovalMaskCountsOnlyBeamsThatWereValid) {
  PlanarScan scan = test::centred_scan(4);
  scan.range_m = {0.5, nan, 0.7, 0.8};
  const std::vector<std::uint8_t> removed{1, 1, 0, 1};
  EXPECT_EQ(apply_removal_mask(scan, removed), 2u);
  EXPECT_TRUE(std::isnan(scan.range_m[0]));
  EXPECT_DOUBLE_EQ(scan.range_m[2], 0.7);
  EXPECT_TRUE(std::isnan(scan.range_m[3]));
}

TEST(RangeSigma, ReadsDeltaRAsThreeSigmaByDefault) {
  const RangeSigmaModel model;
  EXPECT_NEAR(model.sigma_m(0.5, 0.012), 0.004, 1e-12);
}

TEST(RangeSigma, FallsBackToTheUrgSpecWhenDeltaRIsMissing) {
  const RangeSigmaModel model;
  EXPECT_NEAR(model.sigma_m(0.5, nan), 0.010 / 3.0, 1e-12);
  EXPECT_NEAR(model.sigma_m(2.0, -1.0), 0.020 / 3.0, 1e-12);
  RangeSigmaModel spec;
  spec.always_use_urg_spec = true;
  spec.sigma_per_range_error = 1.0;
  EXPECT_NEAR(spec.sigma_m(0.5, 0.1), 0.010, 1e-12);
}

TEST(RangeSigma, RejectsNonPositiveFactor) {
  RangeSigmaModel model;
  model.sigma_per_range_error = 0.0;
  const std::string message = test::input_error_message([&] { model.validate("Owner"); });
  EXPECT_NE(message.find("Owner"), std::string::npos) << message;
  EXPECT_NE(message.find("sigma_per_range_error"), std::string::npos) << message;
}

}  // namespace
}  // namespace stridemap
