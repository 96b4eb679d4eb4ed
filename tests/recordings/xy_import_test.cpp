// Point-pair logs (io::import_xy): the beam angles come back from the
// points alone, ranges to the millimetre, and every fault is named.
#include <cmath>
#include <cstdint>
#include <cstring>
#include <numbers>
#include <random>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "stridemap/core/error.hpp"
#include "stridemap/recordings/log_import.hpp"

namespace stridemap {
namespace {

constexpr double kStepRad = 2.0 * std::numbers::pi / 1024.0;  // the URG-04LX's
constexpr int kBeams = 682;
constexpr double kFirstRad = (44 - 384) * kStepRad;

// One scan of a URG-04LX seen as millimetre pairs: every 37th beam no return.
std::vector<std::int32_t> urg_pairs(std::uint32_t seed, std::vector<std::uint32_t>* ranges_mm = nullptr) {
  std::mt19937 random(seed);
  std::uniform_real_distribution<double> range_m(0.3, 3.0);
  std::vector<std::int32_t> xy;
  for (int k = 0; k < kBeams; ++k) {
    const double angle = kFirstRad + k * kStepRad, r = range_m(random);
    const bool none = k % 37 == 0;
    xy.push_back(none ? 0 : static_cast<std::int32_t>(std::lround(r * 1000.0 * std::cos(angle))));
    xy.push_back(none ? 0 : static_cast<std::int32_t>(std::lround(r * 1000.0 * std::sin(angle))));
    if (ranges_mm) ranges_mm->push_back(none ? 0u : static_cast<std::uint32_t>(std::lround(std::hypot(xy[xy.size() - 2], xy.back()))));
  }
  return xy;
}

void append_int32(std::string& bytes, std::int32_t v) {
  char b[4];
  std::memcpy(b, &v, 4);  // the test machines are little-endian, as the format
  bytes.append(b, 4);
}

TEST(XyImport, BinaryPairsGiveTheUrgsBeamsBackAndEveryRangeToTheMillimetre) {
  std::string bytes = "LOGHEADER-16byte";
  std::vector<std::vector<std::uint32_t>> expected(5);
  for (int s = 0; s < 5; ++s) {
    for (std::int32_t v : urg_pairs(static_cast<std::uint32_t>(s), &expected[static_cast<std::size_t>(s)])) {
      append_int32(bytes, v);
    }
    append_int32(bytes, -1);
    append_int32(bytes, -1);
  }
  io::XyImportOptions o;
  o.header_bytes = 16;
  o.separator = -1.0;
  o.scan_rate_hz = 10.0;
  const io::ImportedData data = io::import_xy(bytes, "run.bin", o);
  ASSERT_EQ(data.scans.size(), 5u);
  EXPECT_EQ(data.report.skipped, 0u);
  EXPECT_EQ(data.sensor.steps_per_turn, 1024);
  EXPECT_EQ(data.sensor.front_step - data.sensor.first_step, 384 - 44);
  EXPECT_EQ(data.sensor.last_step - data.sensor.first_step, kBeams - 1);
  for (std::size_t s = 0; s < 5; ++s) {
    EXPECT_NEAR(data.scans[s].raw.time_s, 0.1 * static_cast<double>(s), 1e-12);
    ASSERT_EQ(data.scans[s].raw.values_mm.size(), static_cast<std::size_t>(kBeams));
    for (int k = 0; k < kBeams; ++k) {
      const std::uint32_t got = data.scans[s].raw.values_mm[static_cast<std::size_t>(k)];
      const std::uint32_t want = expected[s][static_cast<std::size_t>(k)];
      ASSERT_LE(got > want ? got - want : want - got, 1u) << "scan " << s << " beam " << k;
    }
  }
  EXPECT_TRUE(data.poses.empty());
}

TEST(XyImport, FloatPairsInFixedSizeScansWithAStaticPoseAndAShortLastScan) {
  std::string bytes;
  for (int s = 0; s < 3; ++s) {
    for (std::int32_t v : urg_pairs(9u + static_cast<std::uint32_t>(s))) {
      const float metres = static_cast<float>(v) / 1000.0f;
      char b[4];
      std::memcpy(b, &metres, 4);
      bytes.append(b, 4);
    }
  }
  bytes.append(std::string(8 * 10 + 3, '\0'));  // 10 pairs of a cut-off fourth scan and 3 stray bytes
  io::XyImportOptions o;
  o.encoding = io::XyEncoding::float32;
  o.pairs_per_scan = kBeams;
  o.unit_m = 1.0;
  o.scan_rate_hz = 40.0;
  TrunkPose pose;
  pose.x_m = 1.5;
  pose.yaw_rad = 0.25;
  o.static_pose = pose;
  const io::ImportedData data = io::import_xy(bytes, "f.bin", o);
  ASSERT_EQ(data.scans.size(), 3u);
  ASSERT_EQ(data.poses.size(), 3u);
  EXPECT_EQ(data.poses[2].time_s, data.scans[2].raw.time_s);
  EXPECT_EQ(data.poses[2].pose.x_m, 1.5);
  EXPECT_EQ(data.report.skipped, 2u);
  ASSERT_EQ(data.report.problems.size(), 2u);
  EXPECT_NE(data.report.problems[0].find("3 bytes at the end are not a whole pair"), std::string::npos);
  EXPECT_NE(data.report.problems[1].find("10 of 682 pairs (cut short)"), std::string::npos);
  EXPECT_EQ(data.sensor.steps_per_turn, 1024);
}

TEST(XyImport, TextWithTimesSkipsAndNamesBadLines) {
  io::XyImportOptions o;
  o.encoding = io::XyEncoding::text;
  o.time_first = true;
  o.unit_m = 1.0;
  std::string text;
  const double step = 2.0 * std::numbers::pi / 128.0;
  const auto even = [&](double t, double scale) {
    std::string l = std::to_string(t);
    for (int k = 0; k < 4; ++k) {
      const double angle = -step + step * k;
      l += " " + std::to_string(scale * std::cos(angle)) + " " + std::to_string(scale * std::sin(angle));
    }
    return l + "\n";
  };
  text = "t,x0,y0,x1,y1\n" + even(1.0, 1.0) + even(1.1, 1.2) + "1.2 0.5 0.1 0.5 0.2\n" + even(1.05, 1.0) + even(1.3, 0.9) + "1.4 0.5 x\n";
  const io::ImportedData data = io::import_xy(text, "t.txt", o);
  ASSERT_EQ(data.scans.size(), 3u);
  EXPECT_EQ(data.sensor.steps_per_turn, 128);
  EXPECT_EQ(data.report.out_of_order, 1u);
  std::string problems;
  for (const std::string& p : data.report.problems) problems += p + "\n";
  EXPECT_NE(problems.find("t.txt:4: 2 pairs, the first scan had 4"), std::string::npos) << problems;
  EXPECT_NE(problems.find("t.txt:5: time 1.05"), std::string::npos) << problems;
  EXPECT_NE(problems.find("t.txt:7: value 3 ('x') is not a number"), std::string::npos) << problems;
  EXPECT_NEAR(data.scans[1].raw.values_mm[0], 1200.0, 1.0);
}

TEST(XyImport, WhatIsMissingIsAskedForByItsOption) {
  const auto message = [](const std::string& bytes, const io::XyImportOptions& o) {
    try {
      io::import_xy(bytes, "in.bin", o);
    } catch (const InputError& e) {
      return std::string(e.what());
    }
    return std::string("no error");
  };
  io::XyImportOptions o;
  o.separator = -1.0;
  EXPECT_NE(message("", o).find("--scan-rate-hz"), std::string::npos) << message("", o);
  o.separator.reset();
  o.scan_rate_hz = 10.0;
  EXPECT_NE(message("", o).find("--separator"), std::string::npos) << message("", o);
  o.pairs_per_scan = 4;
  o.header_bytes = 100;
  EXPECT_NE(message("abc", o).find("header of 100 bytes is longer than the file"), std::string::npos);
  // Points in no beam order: the fit refuses and asks for the angles.
  o.header_bytes = 0;
  std::string scrambled;
  std::mt19937 random(3);
  std::uniform_int_distribution<std::int32_t> coordinate(-3000, 3000);
  for (int k = 0; k < 4 * 50; ++k) {
    append_int32(scrambled, coordinate(random));
    append_int32(scrambled, coordinate(random));
  }
  const std::string fit = message(scrambled, o);
  EXPECT_NE(fit.find("--angle-min-deg and --angle-step-deg"), std::string::npos) << fit;
}

}  // namespace
}  // namespace stridemap
