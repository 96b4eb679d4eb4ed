#include "stridemap/preprocess/shadow_filter.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <random>

#include "test_scans.hpp"

namespace stridemap {
namespace {

using test::deg;

/// Face x = 0.40 on beams 30..70, a veil trailing behind its right edge on
/// beams 71..73, ground x = 0.65 elsewhere.
PlanarScan veiled_edge() {
  PlanarScan scan = test::centred_scan(121);
  test::put_on_line_x(scan, 0, 120, 0.65);
  test::put_on_line_x(scan, 30, 70, 0.40);
  test::put_on_line_x(scan, 71, 71, 0.45);
  test::put_on_line_x(scan, 72, 72, 0.52);
  test::put_on_line_x(scan, 73, 73, 0.58);
  return scan;
}

TEST(ShadowFilter, RemovesTheVeilAndKeepsTheNearSurface) {
  PlanarScan scan = veiled_edge();
  std::vector<std::uint8_t> removed;
  const ScanFilterStats stats = ShadowFilter().apply(scan, removed);
  for (std::size_t i = 71; i <= 73; ++i) EXPECT_EQ(removed[i], 1) << i;
  for (std::size_t i = 30; i <= 70; ++i) EXPECT_EQ(removed[i], 0) << i;
  // The known cost of the baseline: farther ground within `neighbors` beams of
  // a jump goes too (the jump at 29/30 has no veil but looks like one from
  // beam 29); ground farther from any jump stays.
  EXPECT_GT(stats.removed, 3u);
  EXPECT_EQ(removed[9], 1);
  for (std::size_t i = 0; i < 9; ++i) EXPECT_EQ(removed[i], 0) << i;
  for (std::size_t i = 95; i <= 120; ++i) EXPECT_EQ(removed[i], 0) << i;
  EXPECT_EQ(test::count_valid(scan), 121u - stats.removed);
}

TEST(ShadowFilter, MixedPointInFrontSurvivesAndTakesTheWallBehindIt) {
  PlanarScan scan = test::centred_scan(121);
  test::put_on_line_x(scan, 0, 120, 0.5);
  scan.range_m[60] = 0.3;
  std::vector<std::uint8_t> removed;
  ShadowFilter().apply(scan, removed);
  // Veils start at 60 (wall behind it) and at 59 and 61 (the point in front
  // of them); each takes the farther beams within 20 of it.
  EXPECT_EQ(removed[60], 0);
  for (std::size_t i = 39; i <= 81; ++i) EXPECT_EQ(removed[i], i == 60 ? 0 : 1) << i;
  EXPECT_EQ(test::count_marked(removed), 42u);
}

TEST(ShadowFilter, HeadOnWallIsUntouchedAndStartPointOptionWorks) {
  PlanarScan scan = test::centred_scan(121);
  test::put_on_line_x(scan, 0, 120, 0.5);
  std::vector<std::uint8_t> removed;
  EXPECT_EQ(ShadowFilter().apply(scan, removed).removed, 0u);

  ShadowFilterOptions options;
  options.remove_shadow_start_point = true;
  scan.range_m[60] = 0.3;
  ShadowFilter(options).apply(scan, removed);
  EXPECT_EQ(removed[60], 1);
}

TEST(ShadowFilter, AngleTestAgreesWithAtan2) {
  // Two beams: a veil at beam a (angle at P_a outside [10, 170] deg) removes
  // beam b when b is farther. Checked against the plain atan2 definition.
  std::mt19937_64 engine(11);
  std::uniform_real_distribution<double> range(0.05, 2.0);
  std::uniform_real_distribution<double> step(1e-4, 0.3);
  ShadowFilter filter;
  std::vector<std::uint8_t> removed;
  const auto veil_at = [](double r_a, double r_b, double delta) {
    const double angle = std::atan2(r_b * std::abs(std::sin(delta)), r_a - r_b * std::cos(delta));
    return angle < deg(10.0) || angle > deg(170.0);
  };
  for (int trial = 0; trial < 2000; ++trial) {
    PlanarScan scan = test::centred_scan(2);
    scan.angle_rad = {0.0, step(engine)};
    scan.range_m = {range(engine), range(engine)};
    const double r0 = scan.range_m[0];
    const double r1 = scan.range_m[1];
    const double delta = scan.angle_rad[1];
    filter.apply(scan, removed);
    EXPECT_EQ(removed[1] == 1, veil_at(r0, r1, delta) && r1 > r0) << r0 << " " << r1 << " " << delta;
    EXPECT_EQ(removed[0] == 1, veil_at(r1, r0, -delta) && r0 > r1) << r0 << " " << r1 << " " << delta;
  }
}

TEST(ShadowFilter, EmptyAllInvalidAndBadScans) {
  ShadowFilter filter;
  std::vector<std::uint8_t> removed;
  PlanarScan empty;
  EXPECT_EQ(filter.apply(empty, removed).beams, 0u);
  PlanarScan invalid = test::centred_scan(30);
  EXPECT_EQ(filter.apply(invalid, removed).invalid_input, 30u);
  EXPECT_EQ(test::count_marked(removed), 0u);
  invalid.range_m.resize(5);
  const std::string message = test::input_error_message([&] { filter.apply(invalid, removed); });
  EXPECT_NE(message.find("shadow filter"), std::string::npos) << message;
}

TEST(ShadowFilter, RejectsAnglesOnTheWrongSideOfNinetyDegrees) {
  ShadowFilterOptions options;
  options.min_angle_rad = deg(95.0);
  std::string message = test::input_error_message([&] { ShadowFilter filter(options); });
  EXPECT_NE(message.find("min_angle_rad"), std::string::npos) << message;
  options = {};
  options.max_angle_rad = deg(80.0);
  message = test::input_error_message([&] { ShadowFilter filter(options); });
  EXPECT_NE(message.find("max_angle_rad"), std::string::npos) << message;
  options = {};
  options.window = 0;
  message = test::input_error_message([&] { ShadowFilter filter(options); });
  EXPECT_NE(message.find("window"), std::string::npos) << message;
}

}  // namespace
}  // namespace stridemap
