#include "stridemap/preprocess/scan_sequence.hpp"

#include <gtest/gtest.h>

#include <cmath>

#include "test_scans.hpp"

namespace stridemap {
namespace {

using test::nan;

constexpr std::size_t beams = 201;
constexpr double ground_x = 0.60;
constexpr double face_x = 0.45;  // scan k-1: the box's front face
constexpr double top_x = 0.42;   // scan k+1: the box's top, seen past the edge
constexpr double half_width = 0.10;

PlanarScan box_scan(double box_x, std::uint64_t noise_seed, double time_s) {
  PlanarScan scan = test::centred_scan(beams);
  test::put_box_scene(scan, ground_x, box_x, half_width);
  test::add_noise(scan, 0.002, noise_seed);
  scan.time_s = time_s;
  return scan;
}

/// Scan k: where k-1 saw the face, the beams cross the top edge and return a
/// trailing group of mixed ranges between the edge and the ground behind it.
PlanarScan veiled_scan(std::uint64_t seed, double time_s) {
  PlanarScan scan = box_scan(face_x, seed, time_s);
  std::size_t first = 0;
  std::size_t last = 0;
  test::box_beams(scan, face_x, half_width, first, last);
  test::put_wavy_veil(scan, first, last, 0.43, 0.55, static_cast<double>(seed));
  return scan;
}

void face_beams(std::size_t& first, std::size_t& last) {
  test::box_beams(test::centred_scan(beams), face_x, half_width, first, last);
}

TEST(ScanSequence, DropsTheVeilOfScanKWhenScanKPlusOneIsClean) {
  ScanSequenceFilter filter;
  PlanarScan out;
  std::vector<std::uint8_t> removed;
  EXPECT_FALSE(filter.push(box_scan(face_x, 1, 0.0), out, removed));
  ASSERT_TRUE(filter.push(veiled_scan(2, 0.1), out, removed));
  EXPECT_DOUBLE_EQ(out.time_s, 0.0);
  EXPECT_EQ(test::count_marked(removed), 0u);  // the first scan has no k-1
  ASSERT_TRUE(filter.push(box_scan(top_x, 3, 0.2), out, removed));
  EXPECT_DOUBLE_EQ(out.time_s, 0.1);

  std::size_t first = 0;
  std::size_t last = 0;
  face_beams(first, last);
  const std::size_t margin = filter.options().sector_margin_beams;
  for (std::size_t i = 0; i < beams; ++i) {
    const bool in_sector = i + margin >= first && i <= last + margin;
    EXPECT_EQ(removed[i], in_sector ? 1 : 0) << "beam " << i;
    EXPECT_EQ(std::isnan(out.range_m[i]), in_sector) << "beam " << i;
  }
  EXPECT_EQ(filter.last_stats().removed, last - first + 1 + 2 * margin);
  ASSERT_EQ(filter.last_sectors().size(), 1u);
  const ScanSequenceSector& sector = filter.last_sectors()[0];
  EXPECT_TRUE(sector.removed);
  EXPECT_EQ(sector.spread_first_beam, first);
  EXPECT_EQ(sector.spread_last_beam, last);
  EXPECT_GT(sector.spread_k_m, 0.03);
  EXPECT_LT(sector.spread_next_m, 0.004);
}

TEST(ScanSequence, KeepsScanKWhenScanKPlusOneIsAsScattered) {
  ScanSequenceFilter filter;
  PlanarScan out;
  std::vector<std::uint8_t> removed;
  filter.push(box_scan(face_x, 1, 0.0), out, removed);
  filter.push(veiled_scan(2, 0.1), out, removed);
  ASSERT_TRUE(filter.push(veiled_scan(3, 0.2), out, removed));
  EXPECT_EQ(test::count_marked(removed), 0u);
  ASSERT_EQ(filter.last_sectors().size(), 1u);
  EXPECT_FALSE(filter.last_sectors()[0].removed);
}

TEST(ScanSequence, KeepsACleanSequenceUntouched) {
  ScanSequenceFilter filter;
  PlanarScan out;
  std::vector<std::uint8_t> removed;
  filter.push(box_scan(0.46, 1, 0.0), out, removed);
  filter.push(box_scan(0.45, 2, 0.1), out, removed);
  ASSERT_TRUE(filter.push(box_scan(0.44, 3, 0.2), out, removed));
  EXPECT_EQ(test::count_marked(removed), 0u);
  EXPECT_EQ(test::count_valid(out), beams);
}

TEST(ScanSequence, AFloorWithoutOccludingEndIsNoEdge) {
  // Scan k scattered over the middle of a plain floor: no edge in k-1, so no
  // sector and nothing removed (that is range clustering's job).
  PlanarScan floor = test::centred_scan(beams);
  test::put_on_line_x(floor, 0, beams - 1, ground_x);
  PlanarScan scattered = floor;
  for (std::size_t i = 90; i <= 110; ++i) scattered.range_m[i] += (i % 2 == 0 ? 0.05 : -0.05);
  ScanSequenceFilter filter;
  PlanarScan out;
  std::vector<std::uint8_t> removed;
  filter.push(floor, out, removed);
  filter.push(scattered, out, removed);
  ASSERT_TRUE(filter.push(floor, out, removed));
  EXPECT_TRUE(filter.last_sectors().empty());
  EXPECT_EQ(test::count_marked(removed), 0u);
}

TEST(ScanSequence, EdgeTiltIsJudgedAtBothEndsOfTheSegment) {
  // Without the occlusion requirement, a floor line is an edge candidate only
  // while the beams at both of its ends meet it within 90 +- 60 deg.
  ScanSequenceOptions options;
  options.require_occluding_end = false;
  const auto run = [&](std::size_t floor_beams) {
    PlanarScan floor = test::centred_scan(floor_beams);
    test::put_on_line_x(floor, 0, floor_beams - 1, ground_x);
    PlanarScan scattered = floor;
    const std::size_t middle = floor_beams / 2;
    test::put_wavy_veil(scattered, middle - 10, middle + 10, ground_x, ground_x + 0.1, 0.0);
    ScanSequenceFilter filter(options);
    PlanarScan out;
    filter.push(floor, out);
    filter.push(scattered, out);
    filter.push(floor, out);
    return filter.last_stats().removed;
  };
  EXPECT_EQ(run(401), 0u);  // +-70 deg: ends seen at 70 deg from perpendicular
  EXPECT_EQ(run(331), 331u);  // +-58 deg: the whole floor is the sector, removed
}

TEST(ScanSequence, OneScanOfDelayAndFlushReturnsTheLastScan) {
  ScanSequenceFilter filter;
  PlanarScan out;
  EXPECT_FALSE(filter.flush(out));
  EXPECT_FALSE(filter.push(box_scan(face_x, 1, 1.0), out));
  EXPECT_TRUE(filter.push(box_scan(face_x, 2, 2.0), out));
  EXPECT_DOUBLE_EQ(out.time_s, 1.0);
  EXPECT_TRUE(filter.push(box_scan(face_x, 3, 3.0), out));
  EXPECT_DOUBLE_EQ(out.time_s, 2.0);
  ASSERT_TRUE(filter.flush(out));
  EXPECT_DOUBLE_EQ(out.time_s, 3.0);
  EXPECT_EQ(filter.last_stats().removed, 0u);
  EXPECT_FALSE(filter.flush(out));
  // After a flush the next push starts a new stream.
  EXPECT_FALSE(filter.push(box_scan(face_x, 4, 4.0), out));
}

TEST(ScanSequence, FlushReturnsTheLastScanUnfiltered) {
  ScanSequenceFilter filter;
  PlanarScan out;
  std::vector<std::uint8_t> removed;
  filter.push(box_scan(face_x, 1, 0.0), out, removed);
  const PlanarScan veiled = veiled_scan(2, 0.1);
  filter.push(veiled, out, removed);
  ASSERT_TRUE(filter.flush(out, removed));
  EXPECT_EQ(test::count_marked(removed), 0u);
  for (std::size_t i = 0; i < beams; ++i) EXPECT_DOUBLE_EQ(out.range_m[i], veiled.range_m[i]);
}

TEST(ScanSequence, OutputMayBeTheInputObject) {
  ScanSequenceFilter filter;
  PlanarScan scan = box_scan(face_x, 1, 0.0);
  EXPECT_FALSE(filter.push(scan, scan));
  scan = veiled_scan(2, 0.1);
  ASSERT_TRUE(filter.push(scan, scan));
  EXPECT_DOUBLE_EQ(scan.time_s, 0.0);
  scan = box_scan(top_x, 3, 0.2);
  ASSERT_TRUE(filter.push(scan, scan));
  EXPECT_DOUBLE_EQ(scan.time_s, 0.1);
  EXPECT_GT(filter.last_stats().removed, 0u);
}

TEST(ScanSequence, LengthChangeWithinAStreamNamesBothLengthsAndTheScan) {
  ScanSequenceFilter filter;
  PlanarScan out;
  filter.push(box_scan(face_x, 1, 0.0), out);
  const std::string message =
      test::input_error_message([&] { filter.push(test::centred_scan(200), out); });
  EXPECT_NE(message.find("scan-sequence"), std::string::npos) << message;
  EXPECT_NE(message.find("scan 1 of the stream"), std::string::npos) << message;
  EXPECT_NE(message.find("200 beams"), std::string::npos) << message;
  EXPECT_NE(message.find("have 201"), std::string::npos) << message;
  // The stream is as it was: the held scan is still there.
  ASSERT_TRUE(filter.flush(out));
  EXPECT_EQ(out.size(), beams);
  filter.reset();
  EXPECT_FALSE(filter.push(test::centred_scan(200), out));
}

TEST(ScanSequence, MalformedScanIsAnInputError) {
  ScanSequenceFilter filter;
  PlanarScan out;
  PlanarScan bad = test::centred_scan(10);
  bad.range_error_m.resize(3);
  const std::string message = test::input_error_message([&] { filter.push(bad, out); });
  EXPECT_NE(message.find("10 angles, 10 ranges and 3 range errors"), std::string::npos) << message;
}

TEST(ScanSequence, EmptyAndAllInvalidScansPassThrough) {
  ScanSequenceFilter filter;
  PlanarScan out;
  std::vector<std::uint8_t> removed;
  EXPECT_FALSE(filter.push(PlanarScan{}, out, removed));
  ASSERT_TRUE(filter.push(PlanarScan{}, out, removed));
  EXPECT_EQ(out.size(), 0u);
  EXPECT_TRUE(removed.empty());
  filter.reset();

  filter.push(box_scan(face_x, 1, 0.0), out, removed);
  PlanarScan invalid = test::centred_scan(beams);
  invalid.range_m[5] = std::numeric_limits<double>::infinity();
  filter.push(invalid, out, removed);
  ASSERT_TRUE(filter.push(box_scan(top_x, 2, 0.2), out, removed));
  EXPECT_EQ(test::count_valid(out), 0u);
  EXPECT_EQ(filter.last_stats().invalid_input, beams);
  EXPECT_EQ(filter.last_stats().removed, 0u);
}

TEST(ScanSequence, RejectsNegativeSpreadRatio) {
  ScanSequenceOptions options;
  options.spread_ratio = -1.0;
  const std::string message = test::input_error_message([&] { ScanSequenceFilter filter(options); });
  EXPECT_NE(message.find("ScanSequenceOptions: spread_ratio"), std::string::npos) << message;
}

}  // namespace
}  // namespace stridemap

namespace stridemap {
namespace {

// A box off to the left: beams whose hit on the line x = x_m lies within
// y in [0.15, 0.35] m get range_at(i, beam's y on that line), the others see
// the ground line.
template <typename RangeAt>
PlanarScan side_box_scan(std::size_t n, double x_m, RangeAt range_at) {
  PlanarScan scan = test::centred_scan(n);
  test::put_on_line_x(scan, 0, n - 1, ground_x);
  for (std::size_t i = 0; i < n; ++i) {
    const double t = scan.angle_rad[i];
    if (std::cos(t) <= 0.0) continue;
    const double y = x_m * std::tan(t);
    if (y >= 0.15 && y <= 0.35) scan.range_m[i] = range_at(i, t);
  }
  return scan;
}

TEST(ScanSequence, TheSpreadAlongTheEdgeNormalSeesMixedPointsOffTheBoresight) {
  // Scan k-1 sees the box's face at 25-38 deg to the left; scan k a scattered
  // row of mixed points behind the edge (+-20 mm along x); scan k+1 the clean
  // top. Along the line of sight both rows spread by about 30 mm (their
  // length times the sine of the bearing), so that axis cannot tell them
  // apart; along the edge's normal the clean row has no spread.
  const std::size_t n = 401;
  const PlanarScan before =
      side_box_scan(n, face_x, [](std::size_t, double t) { return face_x / std::cos(t); });
  const PlanarScan mixed = side_box_scan(n, face_x, [](std::size_t i, double t) {
    return (0.50 + 0.02 * std::sin(1.7 * static_cast<double>(i))) / std::cos(t);
  });
  const PlanarScan after = side_box_scan(n, face_x, [](std::size_t, double t) { return top_x / std::cos(t); });
  const auto removed_with = [&](SpreadAxis axis) {
    ScanSequenceOptions options;
    options.spread_axis = axis;
    ScanSequenceFilter filter(options);
    PlanarScan out;
    filter.push(before, out);
    filter.push(mixed, out);
    EXPECT_TRUE(filter.push(after, out));
    return filter.last_stats().removed;
  };
  EXPECT_GT(removed_with(SpreadAxis::edge_normal), 30u);
  EXPECT_EQ(removed_with(SpreadAxis::line_of_sight), 0u);
}

TEST(ScanSequence, RejectsAnUnknownSpreadAxis) {
  ScanSequenceOptions options;
  options.spread_axis = static_cast<SpreadAxis>(7);
  const std::string message = test::input_error_message([&] { ScanSequenceFilter{options}; });
  EXPECT_NE(message.find("spread_axis"), std::string::npos) << message;
}

}  // namespace
}  // namespace stridemap
