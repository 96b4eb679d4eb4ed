// The codec against bytes and scans from real URG-04LX units (../shared/data;
// skipped when the folder is absent).
#include <gtest/gtest.h>

#include <cstdint>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <sstream>
#include <string>
#include <vector>

#include "stridemap/sensors/scip_decoder.hpp"
#include "stridemap/sensors/scip_reply_encoder.hpp"
#include "stridemap/sensors/scip_scan.hpp"
#include "test_paths.hpp"

namespace stridemap::scip {
namespace {

const std::filesystem::path kDataDir = STRIDEMAP_SHARED_DATA_DIR;
const std::filesystem::path kCapture =
    kDataDir / "urg04lx_scip_capture" / "rtf_urg_GD0044072501_URG-04LX-UG01.scip";
const std::filesystem::path kCaptureExpected = kDataDir / "urg04lx_scip_capture" / "rtf_urg_GD0044072501.expected_mm.txt";

std::string read_bytes(const std::filesystem::path& path) {
  std::ifstream file(path, std::ios::binary);
  return {std::istreambuf_iterator<char>(file), std::istreambuf_iterator<char>()};
}

struct RecordedScan {
  std::uint64_t time_us = 0;
  std::vector<std::uint32_t> values_mm;
};

// BreezySLAM log: token 0 = time [us], tokens 24..706 = 683 raw values.
std::vector<RecordedScan> read_breezyslam(const std::filesystem::path& path) {
  constexpr std::size_t kFirstValueToken = 24;
  constexpr std::size_t kValues = 683;
  std::ifstream file(path);
  std::vector<RecordedScan> scans;
  std::string line;
  while (std::getline(file, line)) {
    std::istringstream tokens(line);
    std::vector<std::string> fields{std::istream_iterator<std::string>(tokens), std::istream_iterator<std::string>()};
    if (fields.empty()) continue;
    EXPECT_EQ(fields.size(), kFirstValueToken + kValues) << path << " line " << scans.size() + 1;
    if (fields.size() != kFirstValueToken + kValues) continue;
    RecordedScan scan;
    scan.time_us = std::stoull(fields[0]);
    for (std::size_t i = kFirstValueToken; i < fields.size(); ++i) {
      scan.values_mm.push_back(static_cast<std::uint32_t>(std::stoul(fields[i])));
    }
    scans.push_back(std::move(scan));
  }
  return scans;
}

TEST(ScipRealData, RealUg01CaptureDecodesBitExactly) {
  if (!std::filesystem::exists(kCapture)) GTEST_SKIP() << "real capture not found at " << kCapture;
  const std::string bytes = read_bytes(kCapture);
  ASSERT_EQ(bytes.size(), 2134u);
  std::vector<std::uint32_t> expected;
  std::ifstream expected_file(kCaptureExpected);
  for (std::uint32_t value = 0; expected_file >> value;) expected.push_back(value);
  ASSERT_EQ(expected.size(), 682u);

  // Whole, and one byte at a time, give the same single event.
  for (const bool bytewise : {false, true}) {
    Decoder decoder;
    Event event;
    std::vector<Event> events;
    if (bytewise) {
      for (const char c : bytes) {
        decoder.feed(std::string_view(&c, 1));
        while (decoder.next(event)) events.push_back(event);
      }
    } else {
      decoder.feed(bytes);
      while (decoder.next(event)) events.push_back(event);
    }
    ASSERT_EQ(events.size(), 1u);
    const Event& reply = events[0];
    ASSERT_EQ(reply.kind, EventKind::distance) << reply.error.message;
    EXPECT_EQ(reply.reply.echo.text, "GD0044072501");
    EXPECT_EQ(reply.reply.status, "00");
    EXPECT_EQ(reply.distance.timestamp_ms, 11149560u);  // "ZR3h", sum '7'
    EXPECT_EQ(reply.distance.values, expected);
    EXPECT_EQ(reply.byte_count, bytes.size());

    UrgRawScan raw;
    to_urg_raw_scan(reply, 11149.560, raw);
    EXPECT_EQ(raw.first_step, 44);
    EXPECT_EQ(raw.cluster, 1);
    EXPECT_EQ(raw.values_mm, expected);
    EXPECT_DOUBLE_EQ(raw.time_s, 11149.560);
  }

  // Re-encoding the decoded values gives the device's bytes back.
  std::string reencoded;
  append_distance_reply(parse_command("GD0044072501"), 11149560, expected, reencoded);
  EXPECT_EQ(reencoded, bytes);
}

void round_trip_recording(const std::filesystem::path& path, std::size_t expected_scans) {
  if (!std::filesystem::exists(path)) GTEST_SKIP() << "BreezySLAM recording not found at " << path;
  const auto scans = read_breezyslam(path);
  ASSERT_EQ(scans.size(), expected_scans);

  // One continuous MD stream: 683 values = steps 44..726, scans remaining counting down.
  std::string stream;
  append_status_reply("MD0044072601000", "00", stream);
  for (std::size_t i = 0; i < scans.size(); ++i) {
    const auto timestamp = static_cast<std::uint32_t>((scans[i].time_us / 1000) % TimestampUnwrapper::kPeriodMs);
    append_distance_reply(parse_command("MD0044072601000"), timestamp, scans[i].values_mm, stream);
  }

  Decoder decoder;
  Event event;
  TimestampUnwrapper unwrapper;
  UrgRawScan raw;
  std::size_t next_scan = 0;
  std::size_t error_codes = 0;
  decoder.feed(stream);
  ASSERT_TRUE(decoder.next(event));
  EXPECT_EQ(event.kind, EventKind::status_reply);
  std::uint64_t previous_ms = 0;
  while (decoder.next(event)) {
    ASSERT_EQ(event.kind, EventKind::distance) << event.error.message;
    ASSERT_LT(next_scan, scans.size());
    const RecordedScan& scan = scans[next_scan];
    ASSERT_EQ(event.distance.values, scan.values_mm) << "scan " << next_scan;
    const std::uint64_t unwrapped_ms = unwrapper.unwrap(event.distance.timestamp_ms);
    EXPECT_GE(unwrapped_ms, previous_ms);
    EXPECT_EQ(unwrapped_ms - (next_scan == 0 ? 0 : previous_ms),
              next_scan == 0 ? unwrapped_ms : scan.time_us / 1000 - scans[next_scan - 1].time_us / 1000);
    previous_ms = unwrapped_ms;
    to_urg_raw_scan(event, static_cast<double>(unwrapped_ms) * 1e-3, raw);
    EXPECT_EQ(raw.values_mm.size(), 683u);
    for (const auto value : raw.values_mm) error_codes += value < 20 ? 1 : 0;
    ++next_scan;
  }
  EXPECT_EQ(next_scan, scans.size());
  EXPECT_GT(error_codes, 0u);  // the codes (0, 1, 2, 6, 7, ...) went through unchanged
}

TEST(ScipRealData, BreezySlamExp1ScansRoundTripAsMdFrames) {
  round_trip_recording(kDataDir / "urg04lx_breezyslam" / "exp1.dat", 756);
}

TEST(ScipRealData, BreezySlamExp2ScansRoundTripAsMdFrames) {
  round_trip_recording(kDataDir / "urg04lx_breezyslam" / "exp2.dat", 641);
}

}  // namespace
}  // namespace stridemap::scip
