// `map --global-map DIR` as a user runs it: a robot drives 4 m out (four
// times the 1 m window) and back over the same ground. The tiles are map
// files; merge-tiles gives the window's cells on the overlap; the window the
// robot comes back to holds what it left, so the run ends with the map of a
// window that never moved (--window fit), where without the global map it
// does not. A folder that is a file, cannot be made, or holds another run's
// global map is refused (exit 2) naming it, and nothing in it is changed.
// `live --global-map` makes the same tiles as replaying its recording.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <map>
#include <string>

#include "cli/background_process.hpp"
#include "cli/cli_runner.hpp"
#include "cli/straight_run_log.hpp"
#include "live/test_folder.hpp"
#include "stridemap/mapfile/map_file.hpp"
#include "stridemap/recordings/scan_log.hpp"
#include "test_paths.hpp"

namespace stridemap {
namespace {

namespace fs = std::filesystem;
using test::run_cli;
using test::shell_quoted;

constexpr int kOutAndBackScans = 400;         // 40 s at 10 Hz
constexpr double kOutAndBackSpeed_mps = 0.2;  // 4 m out in 20 s, 4 m back in 20 s
constexpr double kTurn_s = 20.0;

double robot_x_m(double t_s) {
  const double t = std::clamp(t_s, 0.0, 2.0 * kTurn_s);
  return kOutAndBackSpeed_mps * (t < kTurn_s ? t : 2.0 * kTurn_s - t);
}

// Short beams, so every point falls inside the window around the robot:
// the run with the following window and the one with a window holding the
// whole run then integrate the same readings.
void write_out_and_back(const test::TestFolder& dir) {
  test::write_straight_run(dir, "run.log", kOutAndBackScans, 300, robot_x_m);
}

test::CommandResult map_out_and_back(const test::TestFolder& dir, const std::string& out, const std::string& extra) {
  return test::map_straight_run(dir, "run.log", out, extra);
}

bool same_value(float a, float b) { return a == b || (std::isnan(a) && std::isnan(b)); }

// Cells of `a`'s window whose elevation, certainty or state differ from
// `b`'s; `measured` counts a's measured cells.
std::size_t differing_cells(const ElevationMap& a, const ElevationMap& b, std::size_t* measured = nullptr) {
  std::size_t differ = 0;
  for (int i = 0; i < a.cells_per_side(); ++i) {
    for (int j = 0; j < a.cells_per_side(); ++j) {
      const CellIndex c = a.cell_at_local(i, j);
      if (measured) *measured += a.state(c) == CellState::measured;
      if (!b.contains(c)) {
        differ += a.state(c) != CellState::unknown;
        continue;
      }
      differ += !same_value(a.elevation(c), b.elevation(c)) || !same_value(a.certainty(c), b.certainty(c)) ||
                a.state(c) != b.state(c);
    }
  }
  return differ;
}

TEST(GlobalMapCli, TheWindowGetsBackTheCellsItLeftAndTheTilesAreMapFiles) {
  test::TestFolder dir;
  write_out_and_back(dir);
  const auto with = map_out_and_back(dir, "with", "--global-map " + shell_quoted(dir / "tiles"));
  ASSERT_EQ(with.exit_code, 0) << with.output;
  const auto without = map_out_and_back(dir, "without", "");
  ASSERT_EQ(without.exit_code, 0) << without.output;
  const auto fit = map_out_and_back(dir, "fit", "--window fit");  // a window that never moves: the truth here
  ASSERT_EQ(fit.exit_code, 0) << fit.output;
  ASSERT_NE(fit.output.find("grown from 100"), std::string::npos) << fit.output;

  const io::MapFile window = io::load_map_file(dir / "with/map.smap");
  const io::MapFile forgetful = io::load_map_file(dir / "without/map.smap");
  const io::MapFile whole = io::load_map_file(dir / "fit/map.smap");
  ASSERT_EQ(window.map.cells_per_side(), 100);
  ASSERT_EQ(window.map.min_cell(), forgetful.map.min_cell()) << "both windows end where the robot does";
  // Back at the start: the cells measured on the way out came back, so the
  // window is the whole run's map there; forgotten, they were mapped anew.
  std::size_t measured = 0;
  EXPECT_EQ(differing_cells(window.map, whole.map, &measured), 0u);
  EXPECT_GT(measured, 1000u);
  EXPECT_GT(differing_cells(forgetful.map, whole.map), 100u) << "the test cannot tell a window that forgot";

  // Every tile is a whole map file (checksum) and `map-info` reads it.
  std::size_t tiles = 0;
  for (const auto& e : fs::directory_iterator(dir / "tiles")) {
    const std::string name = e.path().filename().string();
    if (name == "global_map.json") continue;
    ASSERT_EQ(name.rfind("tile_", 0), 0u) << name;
    ASSERT_EQ(e.path().extension(), ".smap") << name;
    EXPECT_NO_THROW(io::load_map_file(e.path().string())) << name;
    ++tiles;
  }
  EXPECT_GE(tiles, 5u) << "4 m of path and beams around it, 1 m tiles";
  const auto info = run_cli("map-info " + shell_quoted(dir / "tiles/tile_0_0.smap"));
  EXPECT_EQ(info.exit_code, 0) << info.output;

  // One map of all tiles: the window's cells on the overlap, and the whole
  // run's map everywhere.
  const auto merged_run = run_cli("merge-tiles " + shell_quoted(dir / "tiles") + " --out " + shell_quoted(dir / "all.smap"));
  ASSERT_EQ(merged_run.exit_code, 0) << merged_run.output;
  const io::MapFile merged = io::load_map_file(dir / "all.smap");
  EXPECT_EQ(differing_cells(window.map, merged.map), 0u);
  std::size_t merged_measured = 0;
  EXPECT_EQ(differing_cells(merged.map, whole.map, &merged_measured), 0u);
  std::size_t whole_measured = 0;
  differing_cells(whole.map, merged.map, &whole_measured);
  EXPECT_EQ(merged_measured, whole_measured) << "every measured cell of the run is in a tile";
}

// Hashes a folder's files by name, to show nothing in it changed.
std::string folder_listing(const fs::path& folder) {
  std::string all;
  std::vector<fs::path> files;
  for (const auto& e : fs::directory_iterator(folder)) files.push_back(e.path());
  std::sort(files.begin(), files.end());
  for (const fs::path& f : files) {
    std::ifstream in(f, std::ios::binary);
    all += f.filename().string() + ":" + std::string(std::istreambuf_iterator<char>(in), {}) + "\n";
  }
  return all;
}

TEST(GlobalMapCli, AFolderThatIsAFileCannotBeMadeOrHoldsAnotherRunIsRefusedNamingIt) {
  test::TestFolder dir;
  write_out_and_back(dir);
  const auto refused = [&](const std::string& folder, const std::string& reason, const std::string& out) {
    const auto r = map_out_and_back(dir, out, "--global-map " + shell_quoted(folder));
    EXPECT_EQ(r.exit_code, 2) << folder << ": " << r.output;
    EXPECT_NE(r.output.find("stridemap: error: "), std::string::npos) << r.output;
    EXPECT_NE(r.output.find(folder), std::string::npos) << r.output;
    EXPECT_NE(r.output.find(reason), std::string::npos) << r.output;
    EXPECT_FALSE(fs::exists(dir / out)) << "refused before any output: " << r.output;
  };
  // A file: refused, and left as it was.
  dir.write("plain", "a user's file");
  refused(dir / "plain", "is a file, not a folder", "out1");
  EXPECT_EQ(dir.read("plain"), "a user's file");
  // A folder that cannot be made (below a file; sysfs refuses even root).
  refused(dir / "plain/tiles", "cannot be created", "out2");
  if (fs::is_directory("/sys/kernel")) refused("/sys/stridemap_tiles", "cannot be created", "out3");
  // Another run's global map, at 2 cm cells: named with both resolutions,
  // and not one of its files replaced.
  dir.write("coarse.yaml", "map:\n  cell_size_m: 0.02\n");
  const auto coarse = map_out_and_back(dir, "coarse", "--config " + shell_quoted(dir / "coarse.yaml") + " --global-map " +
                                                 shell_quoted(dir / "old"));
  ASSERT_EQ(coarse.exit_code, 0) << coarse.output;
  const std::string before = folder_listing(dir / "old");
  ASSERT_NE(before.find("tile_0_0.smap"), std::string::npos) << "the earlier run made tiles";
  refused(dir / "old", "already holds a global map (global_map.json: tiles of 100 cells of 0.02 m; this run's: 100 "
                       "cells of 0.01 m)",
          "out4");
  EXPECT_EQ(folder_listing(dir / "old"), before);
  // Also with the same settings: an earlier run's tiles are never replaced.
  const auto again = map_out_and_back(dir, "again", "--config " + shell_quoted(dir / "coarse.yaml") + " --global-map " +
                                                shell_quoted(dir / "old"));
  EXPECT_EQ(again.exit_code, 2) << again.output;
  EXPECT_NE(again.output.find("already holds a global map"), std::string::npos) << again.output;
  EXPECT_EQ(folder_listing(dir / "old"), before);
  // A folder holding a user's file.
  fs::create_directories(dir / "mine");
  dir.write("mine/notes.txt", "keep");
  refused(dir / "mine", "is not empty (it holds 'notes.txt')", "out5");
  EXPECT_EQ(dir.read("mine/notes.txt"), "keep");
}

// The tile files of a folder, loaded, by name.
std::map<std::string, io::MapFile> tiles_of(const fs::path& folder) {
  std::map<std::string, io::MapFile> tiles;
  for (const auto& e : fs::directory_iterator(folder)) {
    if (e.path().extension() == ".smap") tiles.emplace(e.path().filename().string(), io::load_map_file(e.path().string()));
  }
  return tiles;
}

// Found before the mapping, not when the outputs are written after it.
TEST(GlobalMapCli, TilesInsideTheOutFolderOrTheOtherWayRoundAreRefusedBeforeMapping) {
  test::TestFolder dir;
  write_out_and_back(dir);
  const auto inside = map_out_and_back(dir, "out", "--global-map " + shell_quoted(dir / "out/tiles"));
  EXPECT_EQ(inside.exit_code, 2) << inside.output;
  EXPECT_NE(inside.output.find("lie one inside the other"), std::string::npos) << inside.output;
  EXPECT_EQ(inside.output.find("scans mapped"), std::string::npos) << inside.output;
  EXPECT_FALSE(fs::exists(dir / "out"));
  fs::create_directories(dir / "tiles");
  const auto around = map_out_and_back(dir, "tiles/out", "--global-map " + shell_quoted(dir / "tiles/"));
  EXPECT_EQ(around.exit_code, 2) << around.output;
  EXPECT_NE(around.output.find("lie one inside the other"), std::string::npos) << around.output;
  EXPECT_TRUE(fs::is_empty(dir / "tiles"));
}

TEST(GlobalMapCli, LiveMakesTheTilesItsReplayMakesAndRefusesAFile) {
  test::TestFolder dir;
  const std::string scene = std::string(STRIDEMAP_SOURCE_DIR) + "/scenes/cart_rail_boxes.yaml";
  test::BackgroundProcess emulator(shell_quoted(STRIDEMAP_CLI_PATH) + " emulate-urg --link " + shell_quoted(dir / "urg") +
                                   " --rate-hz 100 --duration-s 60 --scene " + shell_quoted(scene) +
                                   " --motion cart-rail --poses-clock sensor --poses-out " + shell_quoted(dir / "poses.txt"));
  ASSERT_TRUE(emulator.wait_for_output("emulating a URG-04LX on", 10.0)) << emulator.output();
  const std::string device = " --device " + shell_quoted(dir / "urg") + " --poses " + shell_quoted(dir / "poses.txt") +
                             " --clock sensor --connect-timeout-s 10 ";
  dir.write("plain", "a user's file");
  const auto refused = run_cli("live" + device + "--out " + shell_quoted(dir / "refused") + " --max-scans 10 --global-map " +
                               shell_quoted(dir / "plain"));
  EXPECT_EQ(refused.exit_code, 2) << refused.output;
  EXPECT_NE(refused.output.find("global map folder '" + dir / "plain" + "' is a file"), std::string::npos) << refused.output;
  EXPECT_EQ(dir.read("plain"), "a user's file");
  // Refused before the sensor is opened, not after it streams.
  EXPECT_EQ(refused.output.find("connected:"), std::string::npos) << refused.output;
  // Refused before the sensor is opened, not after it streams.
  EXPECT_EQ(refused.output.find("connected:"), std::string::npos) << refused.output;

  const auto live = run_cli("live" + device + "--out " + shell_quoted(dir / "live") + " --record " +
                            shell_quoted(dir / "log.txt") + " --max-scans 200 --global-map " + shell_quoted(dir / "live_tiles"));
  ASSERT_EQ(live.exit_code, 0) << live.output;
  const auto again = run_cli("live" + device + "--out " + shell_quoted(dir / "again") + " --max-scans 10 --global-map " +
                             shell_quoted(dir / "live_tiles"));
  EXPECT_EQ(again.exit_code, 2) << again.output;
  EXPECT_NE(again.output.find("already holds a global map (global_map.json: tiles of 100 cells of 0.01 m; this run's: "
                              "100 cells of 0.01 m)"),
            std::string::npos)
      << again.output;
  EXPECT_EQ(again.output.find("connected:"), std::string::npos) << again.output;
  EXPECT_FALSE(fs::exists(dir / "again"));
  const auto replay = run_cli("map --log " + shell_quoted(dir / "log.txt") + " --poses " + shell_quoted(dir / "poses.txt") +
                              " --clock sensor --out " + shell_quoted(dir / "map") + " --global-map " +
                              shell_quoted(dir / "map_tiles"));
  ASSERT_EQ(replay.exit_code, 0) << replay.output;
  const auto live_tiles = tiles_of(dir / "live_tiles"), map_tiles = tiles_of(dir / "map_tiles");
  ASSERT_FALSE(live_tiles.empty());
  ASSERT_EQ(live_tiles.size(), map_tiles.size());
  for (const auto& [name, tile] : live_tiles) {
    ASSERT_TRUE(map_tiles.count(name)) << name;
    EXPECT_EQ(differing_cells(tile.map, map_tiles.at(name).map), 0u) << name;
  }
}

}  // namespace
}  // namespace stridemap
