#include "stridemap/sensors/scip_command.hpp"

#include <gtest/gtest.h>

#include <string>

#include "stridemap/core/error.hpp"
#include "stridemap/sensors/scip_status.hpp"

namespace stridemap::scip {
namespace {

std::string message_of(auto&& call) {
  try {
    call();
  } catch (const InputError& error) {
    return error.what();
  }
  return "no exception";
}

TEST(ScipCommand, SimpleCommandsAreExactBytes) {
  EXPECT_EQ(version_command(), "VV\n");
  EXPECT_EQ(parameters_command(), "PP\n");
  EXPECT_EQ(status_info_command(), "II\n");
  EXPECT_EQ(laser_on_command(), "BM\n");
  EXPECT_EQ(laser_off_command(), "QT\n");
  EXPECT_EQ(reset_command(), "RS\n");
  EXPECT_EQ(switch_to_scip2_command(), "SCIP2.0\n");
  EXPECT_EQ(time_command(TimeMode::adjust_on), "TM0\n");
  EXPECT_EQ(time_command(TimeMode::read), "TM1\n");
  EXPECT_EQ(time_command(TimeMode::adjust_off), "TM2\n");
  EXPECT_EQ(version_command("Hokuyo"), "VV;Hokuyo\n");
  EXPECT_EQ(laser_on_command("a.b_c+d@e 1"), "BM;a.b_c+d@e 1\n");
}

TEST(ScipCommand, ScanCommandsAreZeroPadded) {
  EXPECT_EQ(single_scan_command({}), "GD0044072501\n");
  EXPECT_EQ(single_scan_command({0, 768, 0, true}, "x"), "GS0000076800;x\n");
  EXPECT_EQ(stream_command({44, 725, 1, false}, 0, 0), "MD0044072501000\n");
  EXPECT_EQ(stream_command({44, 725, 3, true}, 9, 2), "MS0044072503902\n");
}

TEST(ScipCommand, OutOfRangeParametersNameTheField) {
  EXPECT_NE(message_of([] { single_scan_command({800, 700, 1, false}); }).find("end step 700 is outside 800..9999"),
            std::string::npos);
  EXPECT_NE(message_of([] { single_scan_command({-1, 700, 1, false}); }).find("start step -1"), std::string::npos);
  EXPECT_NE(message_of([] { single_scan_command({0, 700, 100, false}); }).find("cluster count 100"),
            std::string::npos);
  EXPECT_NE(message_of([] { stream_command({}, 10, 0); }).find("scan interval 10 is outside 0..9"), std::string::npos);
  EXPECT_NE(message_of([] { stream_command({}, 0, 100); }).find("number of scans 100"), std::string::npos);
  EXPECT_NE(message_of([] { version_command("12345678901234567"); }).find("17 characters, at most 16"),
            std::string::npos);
  EXPECT_NE(message_of([] { version_command("a$b"); }).find("tag character 1 '$'"), std::string::npos);
  EXPECT_NO_THROW(version_command("1234567890123456"));
}

TEST(ScipCommand, ParsesEveryEncodedCommandBack) {
  const Command md = parse_command("MD0044072501002;tag1");
  EXPECT_EQ(md.type, CommandType::stream_3char);
  EXPECT_TRUE(md.well_formed) << md.problem;
  EXPECT_EQ(md.start_step, 44);
  EXPECT_EQ(md.end_step, 725);
  EXPECT_EQ(md.cluster, 1);
  EXPECT_EQ(md.scan_interval, 0);
  EXPECT_EQ(md.scan_count, 2);
  EXPECT_TRUE(md.has_tag);
  EXPECT_EQ(md.tag, "tag1");
  EXPECT_EQ(expected_value_count(md), 682);

  const Command gs = parse_command("GS0000076803");
  EXPECT_EQ(gs.type, CommandType::scan_2char);
  EXPECT_EQ(chars_per_value(gs.type), 2);
  EXPECT_EQ(expected_value_count(gs), 257);  // ceil(769 / 3)
  EXPECT_EQ(expected_value_count(parse_command("GD0044072500")), 682);  // cluster 00 acts as 01

  EXPECT_EQ(parse_command("TM1").code, 1);
  EXPECT_EQ(parse_command("SS115200").bit_rate, 115200);
  EXPECT_EQ(parse_command("SCIP2.0").type, CommandType::switch_to_scip2);
  EXPECT_TRUE(parse_command("SCIP2.0").well_formed);
  for (const auto* text : {"VV", "PP", "II", "BM", "QT", "RS", "CR05", "HS1", "DB02"}) {
    const Command command = parse_command(text);
    EXPECT_NE(command.type, CommandType::unknown) << text;
    EXPECT_TRUE(command.well_formed) << text << ": " << command.problem;
    EXPECT_EQ(command.text, text);
  }
}

TEST(ScipCommand, MalformedParametersKeepTheTypeAndSayWhy) {
  const Command bad = parse_command("GD00x4072501");
  EXPECT_EQ(bad.type, CommandType::scan_3char);
  EXPECT_FALSE(bad.well_formed);
  EXPECT_NE(bad.problem.find("start step '00x4' is not 4 decimal digits"), std::string::npos) << bad.problem;
  EXPECT_NE(parse_command("MD004407250100").problem.find("number of scans is missing"), std::string::npos);
  EXPECT_NE(parse_command("BM1").problem.find("unexpected parameter characters '1'"), std::string::npos);
  EXPECT_FALSE(parse_command("TM3").well_formed);
  EXPECT_FALSE(parse_command("VV;way too long a tag here").well_formed);
  EXPECT_EQ(parse_command("XY").type, CommandType::unknown);
  EXPECT_EQ(parse_command("V").type, CommandType::unknown);
  EXPECT_EQ(parse_command("VV\r").type, CommandType::unknown);
  EXPECT_EQ(parse_command("").type, CommandType::unknown);
}

TEST(ScipCommand, EchoOfAStreamCarriesScansRemaining) {
  const Command sent = parse_command("MD0044072501002");
  EXPECT_TRUE(echo_matches(sent, parse_command("MD0044072501002")));  // the acknowledgement
  EXPECT_TRUE(echo_matches(sent, parse_command("MD0044072501001")));
  EXPECT_TRUE(echo_matches(sent, parse_command("MD0044072501000")));
  EXPECT_FALSE(echo_matches(sent, parse_command("MD0044072501003")));
  EXPECT_FALSE(echo_matches(sent, parse_command("MD0044072502001")));
  EXPECT_FALSE(echo_matches(sent, parse_command("MS0044072501001")));
  EXPECT_TRUE(echo_matches(parse_command("GD0044072501;a"), parse_command("GD0044072501;a")));
  EXPECT_FALSE(echo_matches(parse_command("GD0044072501;a"), parse_command("GD0044072501;b")));
}

TEST(ScipStatus, TablesFollowTheSpec) {
  EXPECT_TRUE(is_known_status(CommandType::scan_3char, "10"));
  EXPECT_EQ(status_meaning(CommandType::scan_3char, "10"), "laser is off");
  EXPECT_FALSE(is_known_status(CommandType::scan_3char, "99"));
  EXPECT_TRUE(is_known_status(CommandType::stream_3char, "99"));
  EXPECT_TRUE(is_known_status(CommandType::stream_3char, "35"));
  EXPECT_FALSE(is_known_status(CommandType::scan_3char, "35"));
  EXPECT_TRUE(is_known_status(CommandType::version, "0E"));
  EXPECT_EQ(status_meaning(CommandType::version, "0E"), "undefined command (2)");
  EXPECT_FALSE(is_known_status(CommandType::version, "01"));
  EXPECT_FALSE(is_known_status(CommandType::version, "0L"));
  EXPECT_TRUE(is_known_status(CommandType::laser_on, "02"));
  EXPECT_TRUE(is_known_status(CommandType::laser_off, "0"));  // SCIP 1.1 one-character status

  EXPECT_TRUE(status_means_success(CommandType::laser_on, "02"));  // laser already on
  EXPECT_FALSE(status_means_success(CommandType::laser_on, "01"));
  EXPECT_FALSE(status_means_success(CommandType::scan_3char, "0E"));  // not "0" as strtol would read it
  EXPECT_TRUE(status_means_success(CommandType::switch_to_scip2, "0"));
  EXPECT_TRUE(status_means_success(CommandType::switch_to_scip2, "0E"));
  EXPECT_FALSE(status_means_success(CommandType::switch_to_scip2, "0I"));
  EXPECT_TRUE(status_means_success(CommandType::stream_3char, "99"));
  EXPECT_FALSE(status_means_success(CommandType::scan_3char, "99"));
}

}  // namespace
}  // namespace stridemap::scip
