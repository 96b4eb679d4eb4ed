#include "stridemap/sensors/scip_decoder.hpp"

#include <gtest/gtest.h>

#include <cstdint>
#include <random>
#include <string>
#include <vector>

#include "stridemap/sensors/scip_encoding.hpp"
#include "stridemap/sensors/scip_parameters.hpp"
#include "stridemap/sensors/scip_reply_encoder.hpp"

namespace stridemap::scip {
namespace {

// Real UG01 VV reply with its checksums (scip.md A.6, from a published lab report).
constexpr std::string_view kRealVersionReply =
    "VV\n00P\n"
    "VEND:Hokuyo Automatic Co.,Ltd.;[\n"
    "PROD:SOKUIKI Sensor URG-04LX-UG01(Simple-URG);[\n"
    "FIRM:3.4.03(17/Dec./2012);T\n"
    "PROT:SCIP 2.0;N\n"
    "SERI:H1510998;V\n"
    "\n";

std::vector<std::uint32_t> ramp_values(std::size_t count, std::uint32_t seed, std::uint32_t limit = 5600) {
  std::vector<std::uint32_t> values(count);
  for (std::size_t i = 0; i < count; ++i) values[i] = (seed * 7919u + static_cast<std::uint32_t>(i) * 37u) % limit;
  return values;
}

// One line per event with everything a consumer can see, to compare runs.
std::string describe(const Event& event) {
  std::string text = std::to_string(static_cast<int>(event.kind)) + " @" + std::to_string(event.stream_offset) + "+" +
                     std::to_string(event.byte_count);
  if (event.kind == EventKind::error) {
    return text + " " + std::string(error_kind_name(event.error.kind)) + ": " + event.error.message;
  }
  text += " " + event.reply.echo.text + " [" + event.reply.status + "]";
  if (event.kind == EventKind::distance) {
    text += " ts=" + std::to_string(event.distance.timestamp_ms);
    for (const auto value : event.distance.values) text += " " + std::to_string(value);
  }
  if (event.kind == EventKind::info) {
    for (const auto& field : event.info) text += " " + field.key + "=" + field.value;
  }
  if (event.kind == EventKind::time) text += " t=" + std::to_string(event.time_ms);
  return text;
}

std::vector<std::string> decode_in_chunks(std::string_view bytes, const std::vector<std::size_t>& chunks) {
  Decoder decoder;
  Event event;
  std::vector<std::string> out;
  std::size_t pos = 0;
  for (std::size_t i = 0; pos < bytes.size(); ++i) {
    const std::size_t size = std::min(chunks[i % chunks.size()], bytes.size() - pos);
    decoder.feed(bytes.substr(pos, size));
    pos += size;
    while (decoder.next(event)) out.push_back(describe(event));
  }
  while (decoder.next(event)) out.push_back(describe(event));
  return out;
}

TEST(ScipDecoder, RealVersionReplyWithDeviceChecksums) {
  const auto events = decode_all(kRealVersionReply);
  ASSERT_EQ(events.size(), 1u);
  const Event& event = events[0];
  ASSERT_EQ(event.kind, EventKind::info) << describe(event);
  EXPECT_EQ(event.reply.echo.type, CommandType::version);
  EXPECT_EQ(event.reply.status, "00");
  EXPECT_TRUE(event.reply.status_checksummed);
  EXPECT_EQ(event.stream_offset, 0u);
  EXPECT_EQ(event.byte_count, kRealVersionReply.size());
  const VersionInfo version = parse_version(event.info);
  EXPECT_EQ(version.vendor, "Hokuyo Automatic Co.,Ltd.");
  EXPECT_EQ(version.product, "SOKUIKI Sensor URG-04LX-UG01(Simple-URG)");
  EXPECT_EQ(version.firmware, "3.4.03(17/Dec./2012)");
  EXPECT_EQ(version.protocol, "SCIP 2.0");
  EXPECT_EQ(version.serial, "H1510998");
}

TEST(ScipDecoder, InfoChecksumOverTheSemicolonIsAcceptedToo) {
  // Both sums seen in the wild: over "KEY:value" ('7') and over "KEY:value;" ('2').
  const auto events = decode_all("II\n00P\nLASR:OFF;7\nLASR:OFF;2\nMESM:IDLE;:\nTIME:002AA9;f\n\n");
  ASSERT_EQ(events.size(), 1u);
  ASSERT_EQ(events[0].kind, EventKind::info) << describe(events[0]);
  ASSERT_EQ(events[0].info.size(), 4u);
  EXPECT_EQ(*find_field(events[0].info, "TIME"), "002AA9");
  EXPECT_EQ(find_field(events[0].info, "STAT"), nullptr);
}

TEST(ScipDecoder, ParameterReplyDrivesTheSensorModel) {
  ScipParameters real;  // the real UG01's PP values (scip.md A.6)
  real.model = "URG-04LX-UG01(Simple-URG)(Hokuyo Automatic Co.,Ltd.)";
  std::string bytes;
  append_info_reply("PP", to_info_fields(real), bytes);
  EXPECT_NE(bytes.find("\nDMIN:20;4\n"), std::string::npos);  // spec example line, without the typeset spaces
  const auto events = decode_all(bytes);
  ASSERT_EQ(events.size(), 1u);
  ASSERT_EQ(events[0].kind, EventKind::info) << describe(events[0]);
  const ScipParameters parsed = parse_parameters(events[0].info);
  EXPECT_EQ(parsed, real);
  const UrgParameters urg = to_urg_parameters(parsed);
  EXPECT_EQ(urg.first_step, 44);
  EXPECT_EQ(urg.last_step, 725);
  EXPECT_EQ(urg.front_step, 384);
  EXPECT_EQ(urg.steps_per_turn, 1024);
  EXPECT_DOUBLE_EQ(urg.min_range_m, 0.020);
  EXPECT_DOUBLE_EQ(urg.max_range_m, 5.600);
  EXPECT_DOUBLE_EQ(urg.scan_period_s, 0.1);
}

TEST(ScipDecoder, StatusRepliesAndTheirMeaning) {
  const auto events = decode_all(
      "BM\n00P\n\nBM\n02R\n\nBM\n01Q\n\nQT\n00P\n\nRS;x\n00P\n\nGD0044072501\n10Q\n\nMD0044072501002\n00P\n\n");
  ASSERT_EQ(events.size(), 7u);
  for (const auto& event : events) ASSERT_EQ(event.kind, EventKind::status_reply) << describe(event);
  EXPECT_TRUE(succeeded(events[0].reply));
  EXPECT_TRUE(succeeded(events[1].reply));  // BM 02R: laser already on
  EXPECT_EQ(events[1].reply.status, "02");
  EXPECT_FALSE(succeeded(events[2].reply));  // laser malfunction
  EXPECT_EQ(events[3].reply.echo.type, CommandType::laser_off);
  EXPECT_EQ(events[4].reply.echo.tag, "x");
  EXPECT_FALSE(succeeded(events[5].reply));  // GD while the laser is off
  EXPECT_EQ(events[5].reply.status, "10");
  EXPECT_TRUE(succeeded(events[6].reply));  // MD acknowledgement, data frames follow
}

TEST(ScipDecoder, Scip11SwitchReplies) {
  // A URG-04LX in SCIP 1.1: one-character status, no checksum.
  auto events = decode_all("SCIP2.0\n0\n\n");
  ASSERT_EQ(events.size(), 1u);
  ASSERT_EQ(events[0].kind, EventKind::status_reply) << describe(events[0]);
  EXPECT_EQ(events[0].reply.status, "0");
  EXPECT_FALSE(events[0].reply.status_checksummed);
  EXPECT_TRUE(switched_to_scip2(events[0].reply));
  // A UG01 (native SCIP 2.0) calls SCIP2.0 an undefined command: still fine.
  events = decode_all("SCIP2.0\n0Ee\n\n");
  ASSERT_EQ(events.size(), 1u);
  ASSERT_EQ(events[0].kind, EventKind::status_reply) << describe(events[0]);
  EXPECT_EQ(events[0].reply.status, "0E");
  EXPECT_TRUE(events[0].reply.status_checksummed);
  EXPECT_TRUE(switched_to_scip2(events[0].reply));
  EXPECT_FALSE(switched_to_scip2(decode_all("SCIP2.0\n0Ii\n\n")[0].reply));
  // The official probe's QT answered in SCIP 1.1: 'E'.
  events = decode_all("QT\nE\n\n");
  ASSERT_EQ(events.size(), 1u);
  EXPECT_EQ(events[0].reply.status, "E");
  EXPECT_FALSE(succeeded(events[0].reply));
  // An unknown command answered 0Ee by a UG01 in SCIP 2.0 is not success.
  EXPECT_FALSE(succeeded(decode_all("VV\n0Ee\n\n")[0].reply));
}

TEST(ScipDecoder, StreamAcknowledgementThenDataFrames) {
  const auto first = ramp_values(682, 1);
  const auto second = ramp_values(682, 2);
  std::string bytes;
  append_status_reply("MD0044072501002", "00", bytes);
  append_distance_reply(parse_command("MD0044072501001"), 11149560, first, bytes);
  append_distance_reply(parse_command("MD0044072501000"), 11149660, second, bytes);
  const auto events = decode_all(bytes);
  ASSERT_EQ(events.size(), 3u);
  EXPECT_EQ(events[0].kind, EventKind::status_reply);
  ASSERT_EQ(events[1].kind, EventKind::distance) << describe(events[1]);
  ASSERT_EQ(events[2].kind, EventKind::distance) << describe(events[2]);
  EXPECT_EQ(events[1].reply.status, "99");
  EXPECT_EQ(events[1].reply.echo.scan_count, 1);
  EXPECT_EQ(events[1].distance.timestamp_ms, 11149560u);
  EXPECT_EQ(events[1].distance.chars_per_value, 3);
  EXPECT_EQ(events[1].distance.values, first);
  EXPECT_EQ(events[2].distance.values, second);
  EXPECT_EQ(events[2].stream_offset, events[1].stream_offset + events[1].byte_count);
  EXPECT_EQ(events[2].stream_offset + events[2].byte_count, bytes.size());
}

TEST(ScipDecoder, TwoCharacterAndClusteredScans) {
  const auto values = ramp_values(257, 3, 4096);  // ceil(769 / 3)
  std::string bytes;
  append_distance_reply(parse_command("GS0000076803"), 5, values, bytes);
  const auto events = decode_all(bytes);
  ASSERT_EQ(events.size(), 1u);
  ASSERT_EQ(events[0].kind, EventKind::distance) << describe(events[0]);
  EXPECT_EQ(events[0].distance.chars_per_value, 2);
  EXPECT_EQ(events[0].distance.values, values);
}

TEST(ScipDecoder, TimeReply) {
  std::string bytes;
  append_time_reply("TM1", 16000000, bytes);
  EXPECT_EQ(bytes, "TM1\n00P\nm2@0" + std::string(1, checksum("m2@0")) + "\n\n");
  const auto events = decode_all("TM0\n00P\n\n" + bytes + "TM2\n00P\n\n");
  ASSERT_EQ(events.size(), 3u);
  ASSERT_EQ(events[1].kind, EventKind::time) << describe(events[1]);
  EXPECT_EQ(events[1].time_ms, 16000000u);
  EXPECT_EQ(events[2].kind, EventKind::status_reply);
}

TEST(ScipDecoder, BlankLinesBetweenFramesAreIgnored) {
  const auto events = decode_all("\n\n\nBM\n00P\n\n\n\nQT\n00P\n\n\n");
  ASSERT_EQ(events.size(), 2u);
  EXPECT_EQ(events[0].stream_offset, 3u);
  EXPECT_EQ(events[1].stream_offset, 13u);
}

// A stream mixing every kind of reply with malformed frames in between.
std::string mixed_stream() {
  std::string bytes = "junk before\n\n";
  bytes += std::string(kRealVersionReply);
  append_status_reply("MD0044072501000", "00", bytes);
  for (std::uint32_t scan = 0; scan < 5; ++scan) {
    append_distance_reply(parse_command("MD0044072501000"), 1000 + 100 * scan, ramp_values(682, scan), bytes);
  }
  bytes += "GD0044072501\n00P\nZR3h7\n0060061\n\n";  // far too short
  append_info_reply("PP", to_info_fields(ScipParameters{}), bytes);
  bytes += "BM\n00Q\n\n";  // bad status checksum
  bytes += "SCIP2.0\n0\n\n";
  append_distance_reply(parse_command("GS0044072502"), 77, ramp_values(341, 9, 4096), bytes);
  bytes += "\x01\x02" "BM\n02R\n\n";
  append_time_reply("TM1", 123456, bytes);
  bytes += std::string(3000, 'x') + "\n\n";
  append_status_reply("QT", "00", bytes);
  return bytes;
}

TEST(ScipDecoder, ChunkingDoesNotChangeTheEvents) {
  const std::string bytes = mixed_stream();
  const auto whole = decode_in_chunks(bytes, {bytes.size()});
  ASSERT_GE(whole.size(), 15u);
  EXPECT_EQ(decode_in_chunks(bytes, {1}), whole);
  EXPECT_EQ(decode_in_chunks(bytes, {2, 3, 5, 7, 64, 65, 66, 1000}), whole);
  std::mt19937_64 rng(20240611);
  std::uniform_int_distribution<std::size_t> size(1, 300);
  for (int trial = 0; trial < 5; ++trial) {
    std::vector<std::size_t> chunks(97);
    for (auto& chunk : chunks) chunk = size(rng);
    EXPECT_EQ(decode_in_chunks(bytes, chunks), whole) << "trial " << trial;
  }
  // Every byte is accounted for once: events tile the stream except for
  // blank lines between frames.
  const auto events = decode_all(bytes);
  std::size_t covered = 0;
  std::size_t previous_end = 0;
  for (const auto& event : events) {
    EXPECT_GE(event.stream_offset, previous_end) << describe(event);
    for (std::size_t i = previous_end; i < event.stream_offset; ++i) EXPECT_EQ(bytes[i], '\n') << i;
    previous_end = event.stream_offset + event.byte_count;
    covered += event.byte_count;
  }
  EXPECT_LE(covered, bytes.size());
  EXPECT_EQ(previous_end, bytes.size());
}

TEST(ScipDecoder, EventStorageIsReused) {
  std::string bytes;
  for (std::uint32_t scan = 0; scan < 3; ++scan) {
    append_distance_reply(parse_command("MD0044072501000"), scan, ramp_values(682, scan), bytes);
  }
  Decoder decoder;
  decoder.feed(bytes);
  Event event;
  ASSERT_TRUE(decoder.next(event));
  const std::uint32_t* storage = event.distance.values.data();
  ASSERT_TRUE(decoder.next(event));
  ASSERT_TRUE(decoder.next(event));
  EXPECT_EQ(event.distance.values.data(), storage);
  EXPECT_EQ(event.distance.timestamp_ms, 2u);
  EXPECT_FALSE(decoder.next(event));
  EXPECT_EQ(decoder.stream_offset(), bytes.size());
  EXPECT_EQ(decoder.pending_bytes(), 0u);
}

TEST(ScipDecoder, ResetForgetsAPartialFrame) {
  std::string frame;
  append_distance_reply(parse_command("GD0044072501"), 9, ramp_values(682, 4), frame);
  Decoder decoder;
  Event event;
  decoder.feed(std::string_view(frame).substr(0, 1000));
  EXPECT_FALSE(decoder.next(event));
  decoder.reset();  // e.g. the device was unplugged mid-frame
  decoder.feed(frame);
  ASSERT_TRUE(decoder.next(event));
  ASSERT_EQ(event.kind, EventKind::distance) << event.error.message;
  EXPECT_EQ(event.stream_offset, 1000u);
  EXPECT_EQ(event.distance.values, ramp_values(682, 4));
  EXPECT_FALSE(decoder.next(event));
}

}  // namespace
}  // namespace stridemap::scip
