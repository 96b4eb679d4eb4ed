// A `map` run that mapped nothing fails (exit 1) and says why and what to
// change: every scan rejected as stale (a log no newer than the map it
// resumes), no cell known at the end (the default mount placed the points
// elsewhere, a --window away from them). The scans rejected in the mapper
// are counted on the terminal and in summary.json, also when the run
// succeeds.
#include <gtest/gtest.h>

#include <filesystem>
#include <string>

#include <nlohmann/json.hpp>

#include "cli/background_process.hpp"
#include "cli/cli_runner.hpp"
#include "cli/straight_run_log.hpp"
#include "live/test_folder.hpp"
#include "test_paths.hpp"

namespace stridemap {
namespace empty_run_cli_test {
namespace {

using test::map_straight_run;
using test::shell_quoted;

nlohmann::json summary_in(const test::TestFolder& dir, const std::string& out) {
  return nlohmann::json::parse(dir.read(out + "/summary.json"));
}

// A robot driving 0.3 m along x, every beam reading `range_mm`.
void write_run(const test::TestFolder& dir, std::uint32_t range_mm = 800) {
  test::write_straight_run(dir, "run.log", 30, range_mm, [](double t_s) { return 0.1 * t_s; });
}

// A 4 m window: with the default mount the points of 0.8 m beams are in it.
std::string wide_window(const test::TestFolder& dir) {
  return "--config " + shell_quoted(dir.write("wide.yaml", "map:\n  cells_per_side: 400\n"));
}

TEST(EmptyRunCli, AGoodRunCountsTheScansRejectedInTheMapper) {
  test::TestFolder dir;
  write_run(dir);
  const auto r = map_straight_run(dir, "run.log", "out", wide_window(dir));
  ASSERT_EQ(r.exit_code, 0) << r.output;
  EXPECT_NE(r.output.find("map: 30 scans mapped of 30 (0 before the first pose, 0 after the last, 0 in pose gaps, "
                          "0 rejected as stale, 0 for a bad pose)"),
            std::string::npos)
      << r.output;
  const auto scans = summary_in(dir, "out")["scans"];
  EXPECT_EQ(scans["mapped"], 30);
  EXPECT_EQ(scans["rejected_for_time"], 0);
  EXPECT_EQ(scans["rejected_for_pose"], 0);
}

TEST(EmptyRunCli, ResumingWithALogNoNewerThanTheMapFailsNamingStaleTimesAndResume) {
  test::TestFolder dir;
  write_run(dir);
  const auto first = map_straight_run(dir, "run.log", "first", wide_window(dir));
  ASSERT_EQ(first.exit_code, 0) << first.output;
  // The same log again: every scan is at or before the map's last one.
  const auto r = map_straight_run(dir, "run.log", "second",
                                  wide_window(dir) + " --resume " + shell_quoted(dir / "first/map.smap"));
  EXPECT_EQ(r.exit_code, 1) << r.output;
  EXPECT_NE(r.output.find("map: 0 scans mapped of 30 (0 before the first pose, 0 after the last, 0 in pose gaps, "
                          "30 rejected as stale, 0 for a bad pose)"),
            std::string::npos)
      << r.output;
  EXPECT_NE(r.output.find("stridemap: error: no scan was mapped: 30 of the 30 scans with poses were rejected as "
                          "stale, their times not later than the last scan mapped: the scans span "),
            std::string::npos)
      << r.output;
  EXPECT_NE(r.output.find("so they are older than the map; resume from a map made before these scans, or leave out "
                          "--resume"),
            std::string::npos)
      << r.output;
  const auto scans = summary_in(dir, "second")["scans"];
  EXPECT_EQ(scans["rejected_for_time"], 30);
  EXPECT_EQ(scans["mapped"], 0);
}

TEST(EmptyRunCli, AWindowHoldingNoneOfThePointsFailsNamingWindow) {
  test::TestFolder dir;
  write_run(dir);
  const auto r = map_straight_run(dir, "run.log", "out", "--window 100,100");
  EXPECT_EQ(r.exit_code, 1) << r.output;
  EXPECT_NE(r.output.find("coverage 0.0 %"), std::string::npos) << r.output;
  EXPECT_NE(r.output.find("stridemap: error: the map is empty (coverage 0 %) although 30 scans were mapped: "),
            std::string::npos)
      << r.output;
  EXPECT_NE(r.output.find("; --window 100,100 holds none of the points: centre it on them, or use --window fit"),
            std::string::npos)
      << r.output;
  // The outputs are there to look at.
  EXPECT_EQ(summary_in(dir, "out")["map"]["coverage"], 0.0);
}

TEST(EmptyRunCli, NoMountForTheSensorFailsNamingConfig) {
  test::TestFolder dir;
  // 6 m along every beam: the default mount puts every point metres below
  // the ground and ahead of the 1 m window, as for a horizontal scanner
  // mapped without its mount.
  write_run(dir, 6000);
  auto r = map_straight_run(dir, "run.log", "out", "");
  EXPECT_EQ(r.exit_code, 1) << r.output;
  EXPECT_NE(r.output.find("stridemap: error: the map is empty (coverage 0 %) although 30 scans were mapped: "),
            std::string::npos)
      << r.output;
  EXPECT_NE(r.output.find("no --config was given, so the points were placed by the default mount (0.26 m high, "
                          "pitched 35 deg down): give the sensor's mount with --config (docs/config.md)"),
            std::string::npos)
      << r.output;
  // With a --config, its mount is named.
  const std::string config = dir.write("robot.yaml", "mount:\n  height_m: 0.26\n  pitch_deg: 35\n");
  r = map_straight_run(dir, "run.log", "out2", "--config " + shell_quoted(config));
  EXPECT_EQ(r.exit_code, 1) << r.output;
  EXPECT_NE(r.output.find("check the mount in --config " + config + " (height, pitch, offsets)"), std::string::npos)
      << r.output;
}

TEST(EmptyRunCli, LiveWithAWindowHoldingNoneOfThePointsFailsNamingWindow) {
  test::TestFolder dir;
  const std::string scene = std::string(STRIDEMAP_SOURCE_DIR) + "/scenes/cart_rail_boxes.yaml";
  test::BackgroundProcess emulator(shell_quoted(STRIDEMAP_CLI_PATH) + " emulate-urg --link " +
                                   shell_quoted(dir / "urg") + " --rate-hz 100 --duration-s 60 --scene " +
                                   shell_quoted(scene) + " --motion cart-rail --poses-clock sensor --poses-out " +
                                   shell_quoted(dir / "poses.txt"));
  ASSERT_TRUE(emulator.wait_for_output("emulating a URG-04LX on", 10.0)) << emulator.output();
  const std::string live = "live --device " + shell_quoted(dir / "urg") + " --poses " + shell_quoted(dir / "poses.txt") +
                           " --clock sensor --max-scans 20 --connect-timeout-s 10 --out ";
  auto r = test::run_cli(live + shell_quoted(dir / "near"));
  ASSERT_EQ(r.exit_code, 0) << r.output;
  EXPECT_NE(r.output.find("live: 20 scans mapped of 20 received (0 lost, 0 rejected as stale, 0 for a bad pose)"),
            std::string::npos)
      << r.output;
  r = test::run_cli(live + shell_quoted(dir / "far") + " --window 100,100");
  EXPECT_EQ(r.exit_code, 1) << r.output;
  EXPECT_NE(r.output.find("stridemap: error: the map is empty (coverage 0 %) although 20 scans were mapped: "),
            std::string::npos)
      << r.output;
  EXPECT_NE(r.output.find("; --window 100,100 holds none of the points: centre it on them"), std::string::npos)
      << r.output;
  EXPECT_EQ(r.output.find("--window fit"), std::string::npos) << "live cannot fit: " << r.output;
  EXPECT_TRUE(std::filesystem::exists(dir / "far/map.smap"));
}

}  // namespace
}  // namespace empty_run_cli_test
}  // namespace stridemap
