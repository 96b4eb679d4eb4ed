// `map --resume` and `live --resume`: mapping a log in two halves, the
// second going on from the first's map file, gives the map of the whole log
// bit for bit; a map made with other settings is refused (exit 2) naming
// every setting that differs, and one that does not record them (mount,
// configuration) is refused naming what is missing; the map file resumed
// from is never an output.
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <optional>
#include <sstream>
#include <string>

#include "cli/background_process.hpp"
#include "cli/cli_runner.hpp"
#include "live/test_folder.hpp"
#include "stridemap/mapfile/map_file.hpp"
#include "test_paths.hpp"

namespace stridemap {
namespace map_resume_cli_test {
namespace {

using test::BackgroundProcess;
using test::run_cli;
using test::shell_quoted;

const std::string kScene = std::string(STRIDEMAP_SOURCE_DIR) + "/scenes/cart_rail_boxes.yaml";

std::string cli() { return shell_quoted(STRIDEMAP_CLI_PATH); }

// A moving sensor's log and poses on the sensor clock, recorded from the
// emulator: the travel term of Delta z_max depends on the motion between
// scans, so the resumed half must know where the first half ended.
void record_log(const test::TestFolder& dir, int scans) {
  BackgroundProcess emulator(cli() + " emulate-urg --link " + shell_quoted(dir / "urg") +
                             " --rate-hz 100 --duration-s 60 --scene " + shell_quoted(kScene) +
                             " --motion cart-rail --poses-clock sensor --poses-out " + shell_quoted(dir / "poses.txt"));
  ASSERT_TRUE(emulator.wait_for_output("emulating a URG-04LX on", 10.0)) << emulator.output();
  const auto recorded = run_cli("record --device " + shell_quoted(dir / "urg") + " --out " +
                                shell_quoted(dir / "whole.log") + " --max-scans " + std::to_string(scans) +
                                " --connect-timeout-s 10");
  ASSERT_EQ(recorded.exit_code, 0) << recorded.output;
}

// The log cut after `first_scans` scans: both halves keep the header and
// sensor block, as a recording stopped and restarted would.
void split_log(const test::TestFolder& dir, int first_scans) {
  std::ifstream in(dir / "whole.log");
  std::ofstream first(dir / "first.log"), second(dir / "second.log");
  std::string line;
  int scans = 0;
  while (std::getline(in, line)) {
    const bool scan = line.rfind("scan ", 0) == 0;
    if (!scan) {
      first << line << '\n';
      second << line << '\n';
      continue;
    }
    (scans++ < first_scans ? first : second) << line << '\n';
  }
}

std::string run_map(const test::TestFolder& dir, const std::string& log, const std::string& out,
                    const std::string& extra = "") {
  const auto result = run_cli("map --log " + shell_quoted(dir / log) + " --poses " + shell_quoted(dir / "poses.txt") +
                              " --clock sensor --out " + shell_quoted(dir / out) + extra);
  EXPECT_EQ(result.exit_code, 0) << result.output;
  return result.output;
}

TEST(MapResumeCli, TwoHalvesWithResumeGiveTheWholeLogsMapBitForBit) {
  test::TestFolder dir;
  record_log(dir, 120);
  split_log(dir, 50);
  run_map(dir, "whole.log", "whole");
  run_map(dir, "first.log", "first");
  const std::string second =
      run_map(dir, "second.log", "second", " --resume " + shell_quoted(dir / "first/map.smap"));
  EXPECT_NE(second.find("map: 70 scans mapped of 70"), std::string::npos) << second;

  const io::MapFile whole = io::load_map_file(dir / "whole/map.smap");
  const io::MapFile resumed = io::load_map_file(dir / "second/map.smap");
  // The layers, window and the last scan's pose and time; only created_by
  // (which names the log) may differ.
  EXPECT_EQ(io::encode_map_file(whole.map, {}), io::encode_map_file(resumed.map, {}));
  EXPECT_EQ(whole.metadata.last_scan_time_s, resumed.metadata.last_scan_time_s);
  ASSERT_TRUE(resumed.metadata.last_pose.has_value());
  EXPECT_EQ(whole.metadata.last_pose->x_m, resumed.metadata.last_pose->x_m);
  for (const char* file : {"elevation.csv", "certainty.csv", "state.csv", "elevation.png"}) {
    EXPECT_TRUE(dir.read(std::string("whole/") + file) == dir.read(std::string("second/") + file)) << file;
  }
  EXPECT_NE(dir.read("second/summary.json").find("\"resumed_from\""), std::string::npos);

  // Without the first half's map, the second half alone is a different map:
  // the comparison above can fail.
  run_map(dir, "second.log", "alone");
  EXPECT_FALSE(dir.read("whole/elevation.csv") == dir.read("alone/elevation.csv"));
}

// The config's height_fusion section keeps the fused layers in the map
// file; they go on across a resume as every other layer does.
TEST(MapResumeCli, FusedHeightLayersAreKeptAndResumedBitForBit) {
  test::TestFolder dir;
  record_log(dir, 80);
  split_log(dir, 30);
  dir.write("fused.yaml", "height_fusion:\n  enabled: true\n");
  const std::string config = " --config " + shell_quoted(dir / "fused.yaml");
  run_map(dir, "whole.log", "whole", config);
  run_map(dir, "first.log", "first", config);
  run_map(dir, "second.log", "second", config + " --resume " + shell_quoted(dir / "first/map.smap"));

  const io::MapFile whole = io::load_map_file(dir / "whole/map.smap");
  const std::optional<std::size_t> fused = whole.map.find_layer("fused_elevation");
  ASSERT_TRUE(fused.has_value());
  ASSERT_TRUE(whole.map.find_layer("fused_variance").has_value());
  const float* heights = reinterpret_cast<const float*>(whole.map.layer_bytes(*fused));
  std::size_t known = 0;
  const auto cells = static_cast<std::size_t>(whole.map.cells_per_side() * whole.map.cells_per_side());
  for (std::size_t s = 0; s < cells; ++s) known += std::isfinite(heights[s]) ? 1 : 0;
  EXPECT_GT(known, 500u);
  const io::MapFile resumed = io::load_map_file(dir / "second/map.smap");
  EXPECT_EQ(io::encode_map_file(whole.map, {}), io::encode_map_file(resumed.map, {}));

  // Without the section the map's fused layers would be left behind, stale.
  const auto dropped = run_cli("map --log " + shell_quoted(dir / "second.log") + " --poses " +
                               shell_quoted(dir / "poses.txt") + " --clock sensor --resume " +
                               shell_quoted(dir / "first/map.smap") + " --out " + shell_quoted(dir / "third"));
  EXPECT_EQ(dropped.exit_code, 2) << dropped.output;
  EXPECT_NE(dropped.output.find("height_fusion.enabled: the map has true"), std::string::npos) << dropped.output;
  EXPECT_FALSE(std::filesystem::exists(dir / "third"));
  // A plain map has none.
  run_map(dir, "whole.log", "plain");
  EXPECT_FALSE(io::load_map_file(dir / "plain/map.smap").map.find_layer("fused_elevation").has_value());
}

TEST(MapResumeCli, MapMadeWithOtherSettingsIsRefusedNamingWhatDiffers) {
  test::TestFolder dir;
  record_log(dir, 20);
  run_map(dir, "whole.log", "first");
  dir.write("coarse.yaml", "map:\n  cell_size_m: 0.02\nmount:\n  height_m: 0.5\n");
  const auto result = run_cli("map --log " + shell_quoted(dir / "whole.log") + " --poses " +
                              shell_quoted(dir / "poses.txt") + " --clock sensor --config " +
                              shell_quoted(dir / "coarse.yaml") + " --resume " + shell_quoted(dir / "first/map.smap") +
                              " --out " + shell_quoted(dir / "second"));
  EXPECT_EQ(result.exit_code, 2) << result.output;
  EXPECT_NE(result.output.find("cannot resume mapping from this map"), std::string::npos) << result.output;
  EXPECT_NE(result.output.find("map.cell_size_m: the map has 0.01, this run 0.02"), std::string::npos)
      << result.output;
  EXPECT_NE(result.output.find("mount.height_m"), std::string::npos) << result.output;
  EXPECT_FALSE(std::filesystem::exists(dir / "second"));

  // live checks before it opens the device (there is none here).
  const auto live = run_cli("live --device " + shell_quoted(dir / "no-such-device") + " --poses " +
                            shell_quoted(dir / "poses.txt") + " --config " + shell_quoted(dir / "coarse.yaml") +
                            " --resume " + shell_quoted(dir / "first/map.smap") + " --out " +
                            shell_quoted(dir / "live"));
  EXPECT_EQ(live.exit_code, 2) << live.output;
  EXPECT_NE(live.output.find("map.cell_size_m: the map has 0.01, this run 0.02"), std::string::npos) << live.output;
}

TEST(MapResumeCli, MapWithoutItsSettingsIsRefusedNamingWhatIsMissing) {
  test::TestFolder dir;
  record_log(dir, 20);
  run_map(dir, "whole.log", "first");
  // The same map saved without mount and configuration, as a bare Map from
  // Python used to be: nothing to check this run's settings against.
  const io::MapFile first = io::load_map_file(dir / "first/map.smap");
  io::MapFileMetadata bare;
  bare.created_by = "a script";
  io::save_map_file(dir / "bare.smap", first.map, bare);
  const auto result = run_cli("map --log " + shell_quoted(dir / "whole.log") + " --poses " +
                              shell_quoted(dir / "poses.txt") + " --clock sensor --resume " +
                              shell_quoted(dir / "bare.smap") + " --out " + shell_quoted(dir / "second"));
  EXPECT_EQ(result.exit_code, 2) << result.output;
  EXPECT_NE(result.output.find("--resume " + (dir / "bare.smap") + ": cannot resume mapping from this map"),
            std::string::npos)
      << result.output;
  EXPECT_NE(result.output.find("does not record the sensor mount or the mapper configuration"), std::string::npos)
      << result.output;
  EXPECT_FALSE(std::filesystem::exists(dir / "second"));
}

TEST(MapResumeCli, ResumedMapIsNeverAnOutputAndABadOneIsNamed) {
  test::TestFolder dir;
  record_log(dir, 20);
  run_map(dir, "whole.log", "first");
  const std::string before = dir.read("first/map.smap");
  // --out the folder that holds the map resumed from: refused, untouched.
  const auto same = run_cli("map --log " + shell_quoted(dir / "whole.log") + " --poses " +
                            shell_quoted(dir / "poses.txt") + " --clock sensor --resume " +
                            shell_quoted(dir / "first/map.smap") + " --out " + shell_quoted(dir / "first"));
  EXPECT_EQ(same.exit_code, 2) << same.output;
  EXPECT_NE(same.output.find("holds --resume"), std::string::npos) << same.output;
  EXPECT_TRUE(dir.read("first/map.smap") == before);

  dir.write("junk.smap", "not a map");
  const auto junk = run_cli("map --log " + shell_quoted(dir / "whole.log") + " --poses " +
                            shell_quoted(dir / "poses.txt") + " --resume " + shell_quoted(dir / "junk.smap") +
                            " --out " + shell_quoted(dir / "out"));
  EXPECT_EQ(junk.exit_code, 2) << junk.output;
  EXPECT_NE(junk.output.find("junk.smap"), std::string::npos) << junk.output;
}

}  // namespace
}  // namespace map_resume_cli_test
}  // namespace stridemap
