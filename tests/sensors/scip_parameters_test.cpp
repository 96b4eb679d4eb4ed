// PP/VV parsing, conversion to the sensor model, the reply encoder, the
// timestamp unwrapper and the raw-scan conversion.
#include "stridemap/sensors/scip_parameters.hpp"

#include <gtest/gtest.h>

#include <string>
#include <vector>

#include "stridemap/core/error.hpp"
#include "stridemap/sensors/scip_decoder.hpp"
#include "stridemap/sensors/scip_encoding.hpp"
#include "stridemap/sensors/scip_reply_encoder.hpp"
#include "stridemap/sensors/scip_scan.hpp"

namespace stridemap::scip {
namespace scip_parameters_test {
namespace {

std::string message_of(auto&& call) {
  try {
    call();
  } catch (const InputError& error) {
    return error.what();
  }
  return "no exception";
}

std::vector<InfoField> without(std::vector<InfoField> fields, std::string_view key) {
  std::erase_if(fields, [&](const InfoField& field) { return field.key == key; });
  return fields;
}

std::vector<InfoField> with_value(std::vector<InfoField> fields, std::string_view key, std::string value) {
  for (auto& field : fields) {
    if (field.key == key) field.value = std::move(value);
  }
  return fields;
}

TEST(ScipParameters, MissingOrInvalidFieldsAreNamed) {
  const auto fields = to_info_fields(ScipParameters{});
  for (const auto* key : {"MODL", "DMIN", "DMAX", "ARES", "AMIN", "AMAX", "AFRT", "SCAN"}) {
    EXPECT_EQ(message_of([&] { parse_parameters(without(fields, key)); }),
              "SCIP PP reply: field " + std::string(key) + " is missing");
  }
  EXPECT_EQ(message_of([&] { parse_parameters(with_value(fields, "AMIN", "4x")); }),
            "SCIP PP reply: field AMIN value '4x' is not a non-negative decimal integer");
  EXPECT_NE(message_of([&] { parse_parameters(with_value(fields, "DMAX", "")); }).find("field DMAX"), std::string::npos);
  EXPECT_NE(message_of([&] { parse_parameters(with_value(fields, "SCAN", "-600")); }).find("field SCAN"),
            std::string::npos);
  EXPECT_NE(message_of([&] { parse_parameters(with_value(fields, "ARES", "99999999999")); }).find("field ARES"),
            std::string::npos);
  EXPECT_EQ(message_of([&] { parse_version(without(to_info_fields(VersionInfo{"a", "b", "c", "d", "e"}), "SERI")); }),
            "SCIP VV reply: field SERI is missing");
}

TEST(ScipParameters, InconsistentValuesAreNamedOnConversion) {
  auto bad = [](auto change) {
    ScipParameters parameters;
    change(parameters);
    return message_of([&] { to_urg_parameters(parameters); });
  };
  EXPECT_EQ(bad([](ScipParameters& p) { p.motor_speed_rpm = 0; }), "SCIP PP reply: field SCAN = 0 must be positive");
  EXPECT_EQ(bad([](ScipParameters& p) { p.steps_per_turn = 0; }), "SCIP PP reply: field ARES = 0 must be positive");
  EXPECT_EQ(bad([](ScipParameters& p) { p.last_step = 40; }), "SCIP PP reply: field AMAX = 40 is below AMIN = 44");
  EXPECT_EQ(bad([](ScipParameters& p) { p.last_step = 1024; }),
            "SCIP PP reply: field AMAX = 1024 is not below ARES = 1024");
  EXPECT_EQ(bad([](ScipParameters& p) {
              p.steps_per_turn = 1'024'077'777;
              p.last_step = 777'777'800;
            }),
            "SCIP PP reply: field AMAX = 777777800 is above 9999, the largest step a scan command can name");
  EXPECT_EQ(bad([](ScipParameters& p) { p.front_step = 2000; }),
            "SCIP PP reply: field AFRT = 2000 is outside 0..ARES-1 = 1023");
  EXPECT_EQ(bad([](ScipParameters& p) { p.max_distance_mm = 20; }),
            "SCIP PP reply: field DMAX = 20 is not above DMIN = 20");
  ScipParameters fast;
  fast.motor_speed_rpm = 2400;
  EXPECT_DOUBLE_EQ(to_urg_parameters(fast).scan_period_s, 0.025);
}

TEST(ScipReplyEncoder, ProducesTheSensorsBytes) {
  std::string out;
  append_status_reply("BM", "02", out);
  EXPECT_EQ(out, "BM\n02R\n\n");
  out.clear();
  append_status_reply("SCIP2.0", "0", out);
  EXPECT_EQ(out, "SCIP2.0\n0\n\n");
  out.clear();
  append_status_reply("SCIP2.0", "0E", out);
  EXPECT_EQ(out, "SCIP2.0\n0Ee\n\n");
  out.clear();
  append_info_reply("VV", to_info_fields(VersionInfo{"Hokuyo Automatic Co.,Ltd.", "x", "3.4.03(17/Dec./2012)",
                                                     "SCIP 2.0", "H1510998"}),
                    out);
  EXPECT_NE(out.find("VV\n00P\nVEND:Hokuyo Automatic Co.,Ltd.;[\n"), std::string::npos);
  EXPECT_NE(out.find("\nFIRM:3.4.03(17/Dec./2012);T\nPROT:SCIP 2.0;N\nSERI:H1510998;V\n\n"), std::string::npos);

  // Data lines hold 64 characters plus checksum; values straddle line ends.
  out.clear();
  std::vector<std::uint32_t> values(682, 3505);  // "0fa"
  append_distance_reply(parse_command("GD0044072501"), 11149560, values, out);
  EXPECT_EQ(out.substr(0, 23), "GD0044072501\n00P\nZR3h7\n");
  const std::size_t first_line_end = out.find('\n', 23);
  EXPECT_EQ(first_line_end - 23, 65u);
  EXPECT_EQ(out.substr(first_line_end - 2, 3), "0" + std::string(1, checksum(out.substr(23, 64))) + "\n");
  EXPECT_EQ(out.substr(first_line_end + 1, 2), "fa");
  EXPECT_EQ(out.substr(out.size() - 2), "\n\n");
}

TEST(ScipReplyEncoder, RejectsWhatASensorCouldNotSend) {
  std::string out;
  const Command gd = parse_command("GD0044072501");
  EXPECT_EQ(message_of([&] { append_distance_reply(gd, 0, std::vector<std::uint32_t>(681, 5), out); }),
            "SCIP reply encoder: 'GD0044072501' needs 682 values, 681 given");
  std::vector<std::uint32_t> values(682, 5);
  values[17] = 262144;
  EXPECT_EQ(message_of([&] { append_distance_reply(gd, 0, values, out); }),
            "SCIP reply encoder: value 262144 mm at index 17 does not fit 3 characters (max 262143)");
  values[17] = 4096;
  EXPECT_NE(message_of([&] { append_distance_frame("GS0044072501", "00", 0, values, 2, out); }).find("index 17"),
            std::string::npos);
  values[17] = 5;
  EXPECT_NE(message_of([&] { append_distance_reply(gd, 1u << 24, values, out); }).find("does not fit 24 bits"),
            std::string::npos);
  EXPECT_NE(message_of([&] { append_distance_reply(parse_command("BM"), 0, values, out); }).find("not a well-formed"),
            std::string::npos);
  EXPECT_NE(message_of([&] { append_status_reply("BM", "0e", out); }).find("status '0e'"), std::string::npos);
  EXPECT_NE(message_of([&] { append_status_reply("B\nM", "00", out); }).find("echo character 1 is 0x0a"),
            std::string::npos);
  EXPECT_NE(message_of([&] { append_info_reply("PP", {{"DM:IN", "20"}}, out); }).find("'DM:IN'"), std::string::npos);
  // Found by the scip_parameters fuzzer: a line the decoder would drop.
  EXPECT_EQ(message_of([&] { append_info_reply("PP", {{"MODL", std::string(250, 'x')}}, out); }),
            "SCIP reply encoder: info line of MODL would be 257 bytes, more than the 256 a decoder accepts");
  EXPECT_EQ(message_of([&] { append_info_reply("PP", {{"MODL", std::string(249, 'x')}}, out); }), "no exception");
  const std::vector<Event> longest = decode_all(out);
  ASSERT_EQ(longest.size(), 1u);
  EXPECT_EQ(longest[0].kind, EventKind::info);
  out.clear();
  EXPECT_TRUE(out.empty());
}

TEST(ScipTimestamp, UnwrapsThe24BitCounter) {
  TimestampUnwrapper unwrapper;
  constexpr std::uint64_t kPeriod = TimestampUnwrapper::kPeriodMs;
  EXPECT_EQ(unwrapper.unwrap(16777000), 16777000u);
  EXPECT_EQ(unwrapper.unwrap(16777100), 16777100u);
  EXPECT_EQ(unwrapper.unwrap(20), kPeriod + 20);  // wrapped
  EXPECT_EQ(unwrapper.unwrap(120), kPeriod + 120);
  EXPECT_EQ(unwrapper.unwrap(120), kPeriod + 120);  // same scan time twice: no step
  std::uint64_t previous = unwrapper.last_ms();
  for (std::uint64_t t = kPeriod + 220; t < 5 * kPeriod; t += 3'000'000) {  // several wraps
    const std::uint64_t now = unwrapper.unwrap(static_cast<std::uint32_t>(t % kPeriod));
    EXPECT_EQ(now, t);
    EXPECT_GT(now, previous);
    previous = now;
  }
  unwrapper.reset();  // after RS the sensor's timer restarts
  EXPECT_EQ(unwrapper.unwrap(5), 5u);
  EXPECT_EQ(message_of([&] { unwrapper.unwrap(1u << 24); }), "SCIP timestamp 16777216 ms does not fit 24 bits");
}

TEST(ScipScan, ClusteredReplyToRawScan) {
  std::string bytes;
  std::vector<std::uint32_t> values(228, 1000);  // ceil(682 / 3)
  values[0] = 6;                                   // an error code, kept
  append_distance_reply(parse_command("MD0044072503000"), 42, values, bytes);
  const auto events = decode_all(bytes);
  ASSERT_EQ(events.size(), 1u);
  UrgRawScan raw;
  raw.values_mm.reserve(1000);
  const auto* storage = raw.values_mm.data();
  to_urg_raw_scan(events[0], 0.042, raw);
  EXPECT_EQ(raw.first_step, 44);
  EXPECT_EQ(raw.cluster, 3);
  EXPECT_EQ(raw.values_mm, values);
  EXPECT_EQ(raw.values_mm.data(), storage);
  const auto status = decode_all("BM\n00P\n\n");
  EXPECT_NE(message_of([&] { to_urg_raw_scan(status[0], 0.0, raw); }).find("not a distance reply (echo 'BM')"),
            std::string::npos);
}

TEST(ScipStatusInfo, SpecExampleLinesDecodeAndParse) {
  // LASR, MESM, TIME and STAT are the spec's II example lines with their
  // printed checksums (7, :, f, 8); the other lines fill the reply out.
  const std::string reply =
      "II\n00P\nMODL:URG-04LX(Hokuyo Automatic Co.,Ltd.);N\nLASR:OFF;7\nSCSP:Initial(600[rpm]);[\n"
      "MESM:IDLE;:\nSBPS:USB;L\nTIME:002AA9;f\nSTAT:Sensor works well.;8\n\n";
  const auto events = decode_all(reply);
  ASSERT_EQ(events.size(), 1u);
  ASSERT_EQ(events[0].kind, EventKind::info) << events[0].error.message;
  const StatusInfo info = parse_status_info(events[0].info);
  EXPECT_FALSE(info.laser_on);
  EXPECT_EQ(info.time_ms, 0x2AA9u);
  EXPECT_EQ(info.measurement_mode, "IDLE");
  EXPECT_EQ(info.state, "Sensor works well.");
  EXPECT_EQ(parse_status_info(to_info_fields(info)), info);
}

TEST(ScipStatusInfo, BadFieldsAreNamed) {
  std::vector<InfoField> fields = to_info_fields(StatusInfo{});
  fields[1].value = "MAYBE";
  EXPECT_NE(message_of([&] { parse_status_info(fields); }).find("LASR value 'MAYBE'"), std::string::npos);
  fields = to_info_fields(StatusInfo{});
  fields[5].value = "12G";
  EXPECT_NE(message_of([&] { parse_status_info(fields); }).find("TIME value '12G'"), std::string::npos);
  fields = to_info_fields(StatusInfo{});
  fields.pop_back();
  EXPECT_NE(message_of([&] { parse_status_info(fields); }).find("field STAT is missing"), std::string::npos);
}

}  // namespace
}  // namespace scip_parameters_test
}  // namespace stridemap::scip
