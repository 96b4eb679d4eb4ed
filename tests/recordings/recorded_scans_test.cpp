// Recordings for the emulator to replay: BreezySLAM text logs and scan logs,
// and what is refused in them (with the file and line).
#include "stridemap/recordings/recorded_scans.hpp"

#include <gtest/gtest.h>

#include <string>

#include "stridemap/core/error.hpp"

namespace stridemap::io {
namespace recorded_scans_test {
namespace {

std::string breezyslam_line(std::size_t values, const std::string& last = "1000") {
  std::string line = "123456";
  for (int i = 0; i < 23; ++i) line += " 0";
  for (std::size_t i = 0; i + 1 < values; ++i) line += " 1500";
  return line + " " + last + "\n";
}

std::string error_of(const std::string& text) {
  try {
    parse_recorded_scans(text, "run.log");
  } catch (const InputError& e) {
    return e.what();
  }
  return "no error";
}

TEST(RecordedScans, BreezySlamLinesBecomeScans) {
  const RecordedScans r = parse_recorded_scans(breezyslam_line(683) + "\n" + breezyslam_line(683, "19"), "run.log");
  EXPECT_EQ(r.format, "breezyslam");
  ASSERT_EQ(r.scans.size(), 2u);
  EXPECT_EQ(r.scans[1].size(), 683u);
  EXPECT_EQ(r.scans[1].back(), 19u);
}

TEST(RecordedScans, BadBreezySlamLinesAreNamed) {
  EXPECT_EQ(error_of(breezyslam_line(683) + breezyslam_line(682)),
            "run.log:2: 706 tokens; a BreezySLAM scan line has 707 (24 fields, then 683 values)");
  EXPECT_EQ(error_of(breezyslam_line(684)),
            "run.log:1: more than 707 tokens; a BreezySLAM scan line has 707 (24 fields, then 683 values)");
  EXPECT_NE(error_of(breezyslam_line(683, "-5")).find("run.log:1: token 707 '-5' is not a raw URG value"),
            std::string::npos);
  // The emulator sends 3-character SCIP values: 18 bits at most.
  EXPECT_NE(error_of(breezyslam_line(683, "262144")).find("run.log:1: token 707 '262144'"), std::string::npos);
  EXPECT_EQ(error_of("\n\n"), "run.log: no scans in the recording");
}

}  // namespace
}  // namespace recorded_scans_test
}  // namespace stridemap::io
