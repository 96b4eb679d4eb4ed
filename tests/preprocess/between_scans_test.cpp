// The between-scans test of the scan-sequence filter (BetweenScansOptions)
// and the chain's "between-scans" stage.
#include <gtest/gtest.h>

#include <cmath>

#include "stridemap/preprocess/scan_filter_chain.hpp"
#include "stridemap/preprocess/scan_sequence.hpp"
#include "test_scans.hpp"

namespace stridemap {
namespace between_scans_test {

constexpr std::size_t beams = 201;
constexpr double ground_x = 0.60;  // floor line of the tilted scan plane
constexpr double top_x = 0.42;     // the box top in scan k-1
constexpr double half_width = 0.10;

ScanSequenceOptions with_between_scans(bool spread_test) {
  ScanSequenceOptions options;
  options.spread_test = spread_test;
  options.between_scans.enabled = true;
  return options;
}

// k-1: the box top; k: its beams read a co-linear row at row_x (the edge
// square to the scan line); k+1: the floor behind.
struct EdgeSequence {
  PlanarScan before, now, after;
  std::size_t first = 0, last = 0;
};

EdgeSequence edge_sequence(double row_x, double noise_m = 0.002) {
  EdgeSequence s;
  s.before = test::centred_scan(beams);
  test::put_box_scene(s.before, ground_x, top_x, half_width);
  test::box_beams(s.before, top_x, half_width, s.first, s.last);
  s.now = s.before;
  test::put_on_line_x(s.now, s.first, s.last, row_x);
  s.after = test::centred_scan(beams);
  test::put_on_line_x(s.after, 0, beams - 1, ground_x);
  test::add_noise(s.before, noise_m, 1);
  test::add_noise(s.now, noise_m, 2);
  test::add_noise(s.after, noise_m, 3);
  return s;
}

std::vector<std::uint8_t> judge(ScanSequenceFilter& filter, const EdgeSequence& s, PlanarScan& out) {
  std::vector<std::uint8_t> removed;
  EXPECT_FALSE(filter.push(s.before, out, removed));
  EXPECT_TRUE(filter.push(s.now, out, removed));  // returns k-1, unjudged
  EXPECT_TRUE(filter.push(s.after, out, removed));  // returns k
  return removed;
}

TEST(BetweenScans, RemovesACoLinearRowBetweenTheTopAndTheFloorBehindThatEq12Keeps) {
  const EdgeSequence s = edge_sequence(0.51);
  PlanarScan out;
  ScanSequenceFilter paper;  // eq. 12 alone: a co-linear row does not scatter
  EXPECT_EQ(test::count_marked(judge(paper, s, out)), 0u);

  ScanSequenceFilter filter(with_between_scans(true));
  const std::vector<std::uint8_t> removed = judge(filter, s, out);
  for (std::size_t i = 0; i < beams; ++i) {
    const bool on_row = i >= s.first && i <= s.last;
    EXPECT_EQ(removed[i], on_row ? 1 : 0) << "beam " << i;
    EXPECT_EQ(std::isnan(out.range_m[i]), on_row) << "beam " << i;
    EXPECT_EQ(filter.last_removed_between_scans()[i], removed[i]) << "beam " << i;
  }
  EXPECT_EQ(filter.last_stats().removed, s.last - s.first + 1);
}

TEST(BetweenScans, KeepsReadingsOnEitherSurfaceOfTheEdge) {
  for (const double x : {top_x, ground_x}) {
    const EdgeSequence s = edge_sequence(x);
    ScanSequenceFilter filter(with_between_scans(false));
    PlanarScan out;
    EXPECT_EQ(test::count_marked(judge(filter, s, out)), 0u) << "row at x = " << x;
  }
}

TEST(BetweenScans, KeepsReadingsWithinTheMarginOfASurface) {
  // 3 sigma_r = 10 mm along the beam (no noise here): a row 8 mm (in x,
  // at most 8.6 mm along the beams) behind the top stays, 12 mm goes.
  ScanSequenceFilter filter(with_between_scans(false));
  PlanarScan out;
  EXPECT_EQ(test::count_marked(judge(filter, edge_sequence(top_x + 0.008, 0.0), out)), 0u);
  const EdgeSequence s = edge_sequence(top_x + 0.012, 0.0);
  ScanSequenceFilter fresh(with_between_scans(false));
  EXPECT_EQ(test::count_marked(judge(fresh, s, out)), s.last - s.first + 1);
}

TEST(BetweenScans, KeepsAFaceThatComesCloserScanByScan) {
  // A vertical face ahead: the range shrinks 15 mm per scan, the middle
  // reading lies between the others but the two differ by less than min_jump_m.
  PlanarScan scans[3];
  for (int k = 0; k < 3; ++k) {
    scans[k] = test::centred_scan(beams);
    test::put_on_line_x(scans[k], 0, beams - 1, 0.50 - 0.015 * k);
  }
  ScanSequenceFilter filter(with_between_scans(false));
  PlanarScan out;
  std::vector<std::uint8_t> removed;
  filter.push(scans[0], out, removed);
  filter.push(scans[1], out, removed);
  ASSERT_TRUE(filter.push(scans[2], out, removed));
  EXPECT_EQ(test::count_marked(removed), 0u);
  // With a smaller jump threshold the same face would go: the threshold is what keeps it.
  ScanSequenceOptions loose = with_between_scans(false);
  loose.between_scans.min_jump_m = 0.02;
  ScanSequenceFilter loose_filter(loose);
  loose_filter.push(scans[0], out, removed);
  loose_filter.push(scans[1], out, removed);
  ASSERT_TRUE(loose_filter.push(scans[2], out, removed));
  EXPECT_EQ(test::count_marked(removed), beams);
}

TEST(BetweenScans, BadOptionsNameTheStructAndTheField) {
  ScanSequenceOptions options = with_between_scans(true);
  options.between_scans.min_jump_m = 0.0;
  std::string message = test::input_error_message([&] { ScanSequenceFilter filter(options); });
  EXPECT_NE(message.find("ScanSequenceOptions.between_scans: min_jump_m is 0 m"), std::string::npos) << message;
  options.between_scans.min_jump_m = std::nan("");
  message = test::input_error_message([&] { ScanSequenceFilter filter(options); });
  EXPECT_NE(message.find("min_jump_m"), std::string::npos) << message;
  options = with_between_scans(true);
  options.between_scans.margin_sigmas = -1.0;
  message = test::input_error_message([&] { ScanSequenceFilter filter(options); });
  EXPECT_NE(message.find("ScanSequenceOptions.between_scans: margin_sigmas is -1"), std::string::npos) << message;
}

TEST(BetweenScansChain, NamesAndAdjacency) {
  using Kinds = std::vector<ScanFilterKind>;
  EXPECT_EQ(parse_scan_filter_list("urg"), (Kinds{ScanFilterKind::range_clustering, ScanFilterKind::scan_sequence,
                                                   ScanFilterKind::between_scans}));
  EXPECT_EQ(scan_filter_list_name(parse_scan_filter_list("paper,between-scans")),
            "range-clustering,scan-sequence,between-scans");
  EXPECT_NE(test::input_error_message([] { parse_scan_filter_list("urg,between-scans"); }).find("appears twice"),
            std::string::npos);
  const std::string message = test::input_error_message(
      [] { ScanFilterChain chain({ScanFilterKind::scan_sequence, ScanFilterKind::speckle, ScanFilterKind::between_scans}); });
  EXPECT_NE(message.find("must be next to each other"), std::string::npos) << message;
  EXPECT_EQ(ScanFilterChain({ScanFilterKind::between_scans}).delay_scans(), 1u);
}

TEST(BetweenScansChain, EachStageMarksItsOwnRemovals) {
  const EdgeSequence s = edge_sequence(0.51);
  ScanFilterChain chain({ScanFilterKind::scan_sequence, ScanFilterKind::between_scans});
  PlanarScan out;
  EXPECT_FALSE(chain.push(s.before, out));
  EXPECT_TRUE(chain.push(s.now, out));
  ASSERT_TRUE(chain.push(s.after, out));
  const std::size_t row = s.last - s.first + 1;
  EXPECT_EQ(test::count_marked(chain.removed_by_stage(0)), 0u);  // eq. 12 keeps the co-linear row
  EXPECT_EQ(test::count_marked(chain.removed_by_stage(1)), row);
  EXPECT_EQ(chain.stats_of_stage(1).removed, row);
  EXPECT_EQ(test::count_marked(chain.removed_by_any()), row);
  // Between-scans alone: the spread test is off, the row goes all the same.
  ScanFilterChain alone({ScanFilterKind::between_scans});
  alone.push(s.before, out);
  alone.push(s.now, out);
  ASSERT_TRUE(alone.push(s.after, out));
  EXPECT_EQ(test::count_marked(alone.removed_by_stage(0)), row);
}

}  // namespace between_scans_test
}  // namespace stridemap
