#include "stridemap/preprocess/line_extraction.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <cstring>
#include <limits>
#include <random>

#include "test_scans.hpp"

namespace stridemap {
namespace {

using test::deg;

TEST(LineExtraction, StraightLineIsOneSegmentWithItsParameters) {
  PlanarScan scan = test::centred_scan(101);
  test::put_on_line_x(scan, 0, 100, 0.45);
  LineExtractor extractor;
  std::vector<LineSegment> segments;
  extractor.extract(scan, segments);
  ASSERT_EQ(segments.size(), 1u);
  const LineSegment& line = segments[0];
  EXPECT_EQ(line.first_beam, 0u);
  EXPECT_EQ(line.last_beam, 100u);
  EXPECT_EQ(line.point_count, 101u);
  EXPECT_NEAR(line.distance_m, 0.45, 1e-9);
  EXPECT_NEAR(std::remainder(line.normal_angle_rad, 2.0 * test::pi), 0.0, 1e-9);
  EXPECT_NEAR(line.length_m, 2.0 * 0.45 * std::tan(scan.angle_rad[100]), 1e-9);
  EXPECT_LT(line.max_residual_m, 1e-9);
  EXPECT_FALSE(line.occludes_before);
  EXPECT_FALSE(line.occludes_after);
}

TEST(LineExtraction, CornerSplitsIntoTwoSegments) {
  // Beams 0..50 on the line x = 0.5, beams 50..100 on a line through the same
  // corner point turned by 60 deg: one cluster, two lines.
  PlanarScan scan = test::centred_scan(101);
  test::put_on_line_x(scan, 0, 50, 0.5);
  const double corner_x = 0.5;
  const double corner_y = 0.5 * std::tan(scan.angle_rad[50]);
  const double normal = deg(60.0);
  const double distance = corner_x * std::cos(normal) + corner_y * std::sin(normal);
  for (std::size_t i = 51; i <= 100; ++i) scan.range_m[i] = distance / std::cos(scan.angle_rad[i] - normal);
  LineExtractor extractor;
  std::vector<LineSegment> segments;
  extractor.extract(scan, segments);
  ASSERT_EQ(segments.size(), 2u);
  EXPECT_EQ(segments[0].first_beam, 0u);
  EXPECT_NEAR(static_cast<double>(segments[0].last_beam), 50.0, 1.0);
  EXPECT_NEAR(static_cast<double>(segments[1].first_beam), 50.0, 1.0);
  EXPECT_EQ(segments[1].last_beam, 100u);
  EXPECT_NEAR(segments[1].normal_angle_rad, normal, 1e-6);
}

TEST(LineExtraction, BoxFaceOccludesTheGroundOnBothSidesButNotViceVersa) {
  PlanarScan scan = test::centred_scan(201);
  test::put_box_scene(scan, 0.60, 0.45, 0.10);
  std::size_t first = 0;
  std::size_t last = 0;
  test::box_beams(scan, 0.45, 0.10, first, last);
  LineExtractor extractor;
  std::vector<LineSegment> segments;
  extractor.extract(scan, segments);
  ASSERT_EQ(segments.size(), 3u);
  EXPECT_EQ(segments[1].first_beam, first);
  EXPECT_EQ(segments[1].last_beam, last);
  EXPECT_TRUE(segments[1].occludes_before);
  EXPECT_TRUE(segments[1].occludes_after);
  EXPECT_FALSE(segments[0].occludes_after);  // ground next to the face is behind it
  EXPECT_FALSE(segments[2].occludes_before);
}

TEST(LineExtraction, OcclusionIsSeenAcrossAFewRemovedBeams) {
  PlanarScan scan = test::centred_scan(201);
  test::put_box_scene(scan, 0.60, 0.45, 0.10);
  std::size_t first = 0;
  std::size_t last = 0;
  test::box_beams(scan, 0.45, 0.10, first, last);
  scan.range_m[last + 1] = test::nan;
  scan.range_m[last + 2] = test::nan;
  for (std::size_t i = first - 4; i < first; ++i) scan.range_m[i] = test::nan;  // more than 3
  LineExtractor extractor;
  std::vector<LineSegment> segments;
  extractor.extract(scan, segments);
  ASSERT_EQ(segments.size(), 3u);
  EXPECT_FALSE(segments[1].occludes_before);
  EXPECT_TRUE(segments[1].occludes_after);
}

TEST(LineExtraction, GrazingContinuationIsNoOcclusion) {
  // A floor line seen out to 85 deg incidence: the break test ends the
  // cluster near beta_max = 75 deg, but the beams beyond continue the same
  // line, so the segment does not occlude anything there.
  PlanarScan scan = test::centred_scan(483);  // about +-85 deg
  test::put_on_line_x(scan, 0, 482, 0.45);
  LineExtractor extractor;
  std::vector<LineSegment> segments;
  extractor.extract(scan, segments);
  ASSERT_FALSE(segments.empty());
  const LineSegment* middle = nullptr;
  for (const LineSegment& segment : segments) {
    if (segment.first_beam < 241 && segment.last_beam > 241) middle = &segment;
  }
  ASSERT_NE(middle, nullptr);
  EXPECT_GT(middle->first_beam, 10u);  // the cluster did end before the scan's ends
  EXPECT_FALSE(middle->occludes_before);
  EXPECT_FALSE(middle->occludes_after);
}

TEST(LineExtraction, ShortGroupsAreNoSegments) {
  PlanarScan scan = test::centred_scan(40);
  test::put_on_line_x(scan, 10, 16, 0.5);  // 7 points, fewer than min_points
  LineExtractor extractor;
  std::vector<LineSegment> segments;
  extractor.extract(scan, segments);
  EXPECT_TRUE(segments.empty());
  test::put_on_line_x(scan, 10, 25, 0.2);  // 16 points but only about 19 mm long
  extractor.extract(scan, segments);
  EXPECT_TRUE(segments.empty());
}

TEST(LineExtraction, NoisyLineStaysOneSegment) {
  PlanarScan scan = test::centred_scan(151);
  test::put_on_line_x(scan, 0, 150, 0.45);
  test::add_noise(scan, 0.002, 7);
  LineExtractor extractor;
  std::vector<LineSegment> segments;
  extractor.extract(scan, segments);
  ASSERT_EQ(segments.size(), 1u);
  EXPECT_NEAR(segments[0].distance_m, 0.45, 0.002);
}

bool same_bits(double a, double b) { return std::memcmp(&a, &b, sizeof(double)) == 0; }

// Keep::occluding hands back exactly the occluding segments of Keep::all,
// bit for bit, on rough scenes with boxes, dropouts and noise.
TEST(LineExtraction, OccludingSegmentsAreThoseOfAllSegments) {
  std::mt19937_64 rng(3);
  std::uniform_real_distribution<double> box_x(0.25, 0.55), half_width(0.02, 0.15), dropout(0.0, 1.0);
  std::size_t occluding_seen = 0;
  for (int trial = 0; trial < 200; ++trial) {
    PlanarScan scan = test::centred_scan(301);
    test::put_box_scene(scan, 0.60, box_x(rng), half_width(rng));
    test::add_noise(scan, 0.001 + 0.004 * dropout(rng), static_cast<unsigned>(trial));
    for (double& r : scan.range_m) {
      if (dropout(rng) < 0.03) r = std::numeric_limits<double>::quiet_NaN();
    }
    LineExtractor extractor;
    std::vector<LineSegment> all, occluding;
    extractor.extract(scan, all);
    extractor.extract(scan, occluding, LineExtractor::Keep::occluding);
    std::vector<LineSegment> expected;
    for (const LineSegment& s : all) {
      if (s.occludes_before || s.occludes_after) expected.push_back(s);
    }
    ASSERT_EQ(occluding.size(), expected.size()) << "trial " << trial;
    for (std::size_t k = 0; k < expected.size(); ++k) {
      const LineSegment &a = occluding[k], &b = expected[k];
      EXPECT_TRUE(a.first_beam == b.first_beam && a.last_beam == b.last_beam && a.point_count == b.point_count &&
                  same_bits(a.normal_angle_rad, b.normal_angle_rad) && same_bits(a.distance_m, b.distance_m) &&
                  same_bits(a.length_m, b.length_m) && same_bits(a.max_residual_m, b.max_residual_m) &&
                  same_bits(a.mid_x_m, b.mid_x_m) && same_bits(a.mid_y_m, b.mid_y_m) &&
                  a.occludes_before == b.occludes_before && a.occludes_after == b.occludes_after)
          << "trial " << trial << " segment " << k;
    }
    occluding_seen += expected.size();
  }
  EXPECT_GT(occluding_seen, 100u);
}

TEST(LineExtraction, RejectsTooFewMinPoints) {
  LineExtractionOptions options;
  options.min_points = 1;
  const std::string message = test::input_error_message([&] { LineExtractor extractor(options); });
  EXPECT_NE(message.find("min_points"), std::string::npos) << message;
}

}  // namespace
}  // namespace stridemap
