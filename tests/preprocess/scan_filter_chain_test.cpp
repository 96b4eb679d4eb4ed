#include "stridemap/preprocess/scan_filter_chain.hpp"

#include <gtest/gtest.h>

#include <cmath>

#include "test_scans.hpp"

namespace stridemap {
namespace {

using Kinds = std::vector<ScanFilterKind>;

TEST(ScanFilterNames, ParseSingleNamesAndLists) {
  EXPECT_EQ(parse_scan_filter_kind("shadow"), ScanFilterKind::shadow);
  EXPECT_EQ(parse_scan_filter_kind(" speckle "), ScanFilterKind::speckle);
  EXPECT_EQ(parse_scan_filter_list("paper"),
            (Kinds{ScanFilterKind::range_clustering, ScanFilterKind::scan_sequence}));
  EXPECT_EQ(parse_scan_filter_list("speckle, scan-sequence,shadow"),
            (Kinds{ScanFilterKind::speckle, ScanFilterKind::scan_sequence, ScanFilterKind::shadow}));
  EXPECT_TRUE(parse_scan_filter_list("none").empty());
  EXPECT_EQ(parse_scan_filter_list(std::vector<std::string>{"paper", "shadow"}),
            (Kinds{ScanFilterKind::range_clustering, ScanFilterKind::scan_sequence, ScanFilterKind::shadow}));
  for (const ScanFilterKind kind : {ScanFilterKind::range_clustering, ScanFilterKind::scan_sequence,
                                    ScanFilterKind::shadow, ScanFilterKind::speckle}) {
    EXPECT_EQ(parse_scan_filter_kind(scan_filter_name(kind)), kind);
  }
  EXPECT_EQ(scan_filter_list_name(parse_scan_filter_list("paper")), "range-clustering,scan-sequence");
  EXPECT_EQ(scan_filter_list_name({}), "none");
}

TEST(ScanFilterNames, BadNamesAreInputErrorsListingTheValidNames) {
  std::string message = test::input_error_message([] { parse_scan_filter_list("range-clustering,veil"); });
  EXPECT_NE(message.find("\"veil\""), std::string::npos) << message;
  EXPECT_NE(message.find("range-clustering, scan-sequence, shadow, speckle, between-scans"), std::string::npos)
      << message;
  EXPECT_NE(message.find("paper = range-clustering,scan-sequence"), std::string::npos) << message;
  message = test::input_error_message([] { parse_scan_filter_list("paper,range-clustering"); });
  EXPECT_NE(message.find("appears twice"), std::string::npos) << message;
  message = test::input_error_message([] { parse_scan_filter_list(""); });
  EXPECT_NE(message.find("empty name"), std::string::npos) << message;
  message = test::input_error_message([] { parse_scan_filter_list("shadow,,speckle"); });
  EXPECT_NE(message.find("empty name"), std::string::npos) << message;
  message = test::input_error_message([] { parse_scan_filter_list("none,shadow"); });
  EXPECT_NE(message.find("\"none\" cannot be combined"), std::string::npos) << message;
  message = test::input_error_message([] {
    ScanFilterChain chain({ScanFilterKind::shadow, ScanFilterKind::shadow});
  });
  EXPECT_NE(message.find("given twice"), std::string::npos) << message;
}

/// Wall with an isolated point in front (beam 30) and a 2-beam speck (80, 81).
PlanarScan wall_with_specks(double time_s) {
  PlanarScan scan = test::centred_scan(121);
  test::put_on_line_x(scan, 0, 120, 0.5);
  scan.range_m[30] -= 0.1;
  scan.range_m[80] += 0.1;
  scan.range_m[81] += 0.1;
  scan.time_s = time_s;
  return scan;
}

TEST(ScanFilterChain, WithoutScanSequenceReturnsEachScanAtOnce) {
  ScanFilterChain chain(parse_scan_filter_list("range-clustering,speckle"));
  EXPECT_EQ(chain.delay_scans(), 0u);
  PlanarScan out;
  ASSERT_TRUE(chain.push(wall_with_specks(1.0), out));
  EXPECT_DOUBLE_EQ(out.time_s, 1.0);
  // Range clustering takes all three; speckle finds nothing left.
  EXPECT_EQ(test::count_marked(chain.removed_by_stage(0)), 3u);
  EXPECT_EQ(test::count_marked(chain.removed_by_stage(1)), 0u);
  EXPECT_EQ(chain.stats_of_stage(1).invalid_input, 3u);
  EXPECT_EQ(test::count_marked(chain.removed_by_any()), 3u);
  EXPECT_EQ(test::count_valid(out), 118u);
  EXPECT_FALSE(chain.flush(out));
}

TEST(ScanFilterChain, EmptyChainPassesScansThroughWithInvalidRangesAsNaN) {
  ScanFilterChain chain({});
  PlanarScan scan = wall_with_specks(0.0);
  scan.range_m[3] = -2.0;
  PlanarScan out;
  ASSERT_TRUE(chain.push(scan, out));
  EXPECT_TRUE(std::isnan(out.range_m[3]));
  EXPECT_EQ(test::count_valid(out), 120u);
  EXPECT_EQ(test::count_marked(chain.removed_by_any()), 0u);
}

TEST(ScanFilterChain, PaperChainDelaysByOneScanAndKeepsEachStagesMask) {
  ScanFilterChain chain(parse_scan_filter_list("paper"));
  EXPECT_EQ(chain.delay_scans(), 1u);
  PlanarScan out;
  EXPECT_FALSE(chain.push(wall_with_specks(1.0), out));
  PlanarScan second = wall_with_specks(2.0);
  second.range_m[100] += 0.2;  // one more speck, only in the second scan
  ASSERT_TRUE(chain.push(second, out));
  EXPECT_DOUBLE_EQ(out.time_s, 1.0);
  // The masks belong to the first scan, although the second was clustered since.
  EXPECT_EQ(chain.removed_by_stage(0)[100], 0);
  EXPECT_EQ(test::count_marked(chain.removed_by_stage(0)), 3u);
  EXPECT_EQ(test::count_marked(chain.removed_by_stage(1)), 0u);
  ASSERT_TRUE(chain.flush(out));
  EXPECT_DOUBLE_EQ(out.time_s, 2.0);
  EXPECT_EQ(chain.removed_by_stage(0)[100], 1);
  EXPECT_EQ(test::count_marked(chain.removed_by_stage(0)), 4u);
  EXPECT_TRUE(std::isnan(out.range_m[100]));
  EXPECT_FALSE(chain.flush(out));
}

TEST(ScanFilterChain, StagesAfterScanSequenceRunOnTheDelayedScan) {
  ScanFilterChain chain(parse_scan_filter_list("scan-sequence,speckle"));
  PlanarScan out;
  EXPECT_FALSE(chain.push(wall_with_specks(1.0), out));
  ASSERT_TRUE(chain.push(wall_with_specks(2.0), out));
  EXPECT_EQ(test::count_marked(chain.removed_by_stage(1)), 3u);
  EXPECT_EQ(chain.removed_by_stage(1)[30], 1);
  ASSERT_TRUE(chain.flush(out));
  EXPECT_EQ(test::count_marked(chain.removed_by_stage(1)), 3u);
}

TEST(ScanFilterChain, ScanSequenceStageRemovesAVeil) {
  // The box sequence of the scan-sequence tests, through the paper's chain.
  const auto box = [](double box_x) {
    PlanarScan scan = test::centred_scan(201);
    test::put_box_scene(scan, 0.60, box_x, 0.10);
    return scan;
  };
  PlanarScan veiled = box(0.45);
  std::size_t first = 0;
  std::size_t last = 0;
  test::box_beams(veiled, 0.45, 0.10, first, last);
  test::put_wavy_veil(veiled, first, last, 0.43, 0.55, 0.0);

  ScanFilterChain chain(parse_scan_filter_list("paper"));
  PlanarScan out;
  chain.push(box(0.45), out);
  chain.push(veiled, out);
  ASSERT_TRUE(chain.push(box(0.42), out));
  const std::size_t by_clustering = test::count_marked(chain.removed_by_stage(0));
  const std::size_t by_sequence = test::count_marked(chain.removed_by_stage(1));
  // Range clustering cuts the trail where it jumps from the ground; the rest
  // is one large group that only scan-sequence removes.
  EXPECT_GT(by_sequence, (last - first + 1) / 2);
  EXPECT_EQ(by_clustering + by_sequence, test::count_marked(chain.removed_by_any()));
  for (std::size_t i = first; i <= last; ++i) EXPECT_EQ(chain.removed_by_any()[i], 1) << i;
  for (std::size_t i = 0; i < out.size(); ++i) {
    EXPECT_FALSE(chain.removed_by_stage(0)[i] == 1 && chain.removed_by_stage(1)[i] == 1) << i;
  }
}

TEST(ScanFilterChain, LengthChangeWithScanSequenceIsAnInputError) {
  ScanFilterChain chain(parse_scan_filter_list("paper"));
  PlanarScan out;
  chain.push(wall_with_specks(0.0), out);
  const std::string message = test::input_error_message([&] { chain.push(test::centred_scan(100), out); });
  EXPECT_NE(message.find("100 beams"), std::string::npos) << message;
  EXPECT_NE(message.find("121"), std::string::npos) << message;
  chain.reset();
  EXPECT_FALSE(chain.push(test::centred_scan(100), out));
}

TEST(ScanFilterChain, MalformedScanIsAnInputErrorInEveryChain) {
  PlanarScan bad = test::centred_scan(10);
  bad.angle_rad.resize(4);
  PlanarScan out;
  for (const char* names : {"none", "shadow", "scan-sequence", "paper"}) {
    ScanFilterChain chain(parse_scan_filter_list(names));
    const std::string message = test::input_error_message([&] { chain.push(bad, out); });
    EXPECT_NE(message.find("4 angles, 10 ranges"), std::string::npos) << names << ": " << message;
  }
}

TEST(ScanFilterChain, StageIndexOutOfRangeThrows) {
  ScanFilterChain chain(parse_scan_filter_list("shadow"));
  EXPECT_THROW(chain.removed_by_stage(1), std::out_of_range);
}

}  // namespace
}  // namespace stridemap
