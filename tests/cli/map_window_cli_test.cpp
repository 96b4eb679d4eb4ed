// `map --window CENTER|fit` and `live --window CENTER`: a long log that the
// robot-following window cuts off is mapped whole with fit (no point falls
// outside the map), a centre puts the window where asked, and bad values
// are refused naming the option.
#include <gtest/gtest.h>

#include <cstdio>
#include <filesystem>
#include <fstream>
#include <string>

#include <nlohmann/json.hpp>

#include "cli/cli_runner.hpp"
#include "cli/straight_run_log.hpp"
#include "live/test_folder.hpp"
#include "stridemap/mapfile/map_file.hpp"
#include "stridemap/recordings/scan_log.hpp"

namespace stridemap {
namespace {

using test::run_cli;
using test::shell_quoted;

constexpr int kScans = 200;          // 20 s at 10 Hz
constexpr double kSpeed_mps = 0.2;   // 4 m in all: four times the 1 m window

// A robot driving straight along +x with every beam at 0.8 m: the points
// form a band around the path, far longer than the default window.
void write_long_run(const test::TestFolder& dir) {
  test::write_straight_run(dir, "long.log", kScans, 800, [](double t_s) { return kSpeed_mps * std::max(0.0, t_s); });
}

test::CommandResult map_long_run(const test::TestFolder& dir, const std::string& out, const std::string& extra) {
  return test::map_straight_run(dir, "long.log", out, extra);
}

nlohmann::json summary_of(const test::TestFolder& dir, const std::string& out) {
  return nlohmann::json::parse(dir.read(out + "/summary.json"));
}

// The map-frame x extent of the measured cells.
std::pair<double, double> measured_x_extent(const io::MapFile& file) {
  const ElevationMap& map = file.map;
  double lo = 1e9, hi = -1e9;
  for (int i = 0; i < map.cells_per_side(); ++i)
    for (int j = 0; j < map.cells_per_side(); ++j) {
      const CellIndex c = map.cell_at_local(i, j);
      if (map.state(c) != CellState::measured) continue;
      lo = std::min(lo, map.cell_center(c).x());
      hi = std::max(hi, map.cell_center(c).x());
    }
  return {lo, hi};
}

TEST(MapWindowCli, FitHoldsEveryPointOfALogTheFollowingWindowCutsOff) {
  test::TestFolder dir;
  write_long_run(dir);

  const auto follow = map_long_run(dir, "follow", "");
  // The reason for fit: the run is lost, and the run says so (exit 1,
  // after writing its outputs) and names the way out.
  ASSERT_EQ(follow.exit_code, 1) << follow.output;
  EXPECT_NE(follow.output.find("stridemap: error: the map is empty (coverage 0 %)"), std::string::npos)
      << follow.output;
  EXPECT_NE(follow.output.find("or see the whole run with --window fit"), std::string::npos) << follow.output;
  const auto followed = summary_of(dir, "follow");
  EXPECT_GT(followed["beams"]["outside_map"].get<std::size_t>(), 10000u) << followed.dump();
  const auto [follow_lo, follow_hi] = measured_x_extent(io::load_map_file(dir / "follow/map.smap"));
  EXPECT_GT(follow_lo, 2.0) << "the window followed the robot to the end of the run";

  const auto fit = map_long_run(dir, "fit", "--window fit");
  ASSERT_EQ(fit.exit_code, 0) << fit.output;
  EXPECT_NE(fit.output.find("--window fit:"), std::string::npos) << fit.output;
  EXPECT_NE(fit.output.find("grown from 100"), std::string::npos) << fit.output;
  RecordProperty("fit_message", fit.output);  // what docs/cli.md quotes
  const auto fitted = summary_of(dir, "fit");
  EXPECT_EQ(fitted["beams"]["outside_map"].get<std::size_t>(), 0u) << fitted.dump();
  EXPECT_EQ(fitted["beams"]["integrated"], followed["beams"]["integrated"].get<std::size_t>() +
                                               followed["beams"]["outside_map"].get<std::size_t>());
  const int cells = fitted["map"]["cells_per_side"].get<int>();
  EXPECT_GT(cells, 400);   // 4 m of path and 0.8 m of beams each side, 1 cm cells
  EXPECT_LT(cells, 600);   // ... and no more than that needs
  const io::MapFile whole = io::load_map_file(dir / "fit/map.smap");
  const auto [lo, hi] = measured_x_extent(whole);
  EXPECT_LT(lo, 0.0);
  EXPECT_GT(hi, 3.9);
  EXPECT_TRUE(std::filesystem::exists(dir / "fit/elevation.png"));
}

TEST(MapWindowCli, CentrePutsTheWindowWhereAsked) {
  test::TestFolder dir;
  write_long_run(dir);
  const auto result = map_long_run(dir, "centre", "--window 1.5,-0.2");
  ASSERT_EQ(result.exit_code, 0) << result.output;
  const io::MapFile file = io::load_map_file(dir / "centre/map.smap");
  EXPECT_EQ(file.map.cells_per_side(), 100);
  // 1.5 m and -0.2 m lie in cells 150 and -20, the window's centre cell (N / 2 from its corner).
  EXPECT_EQ(file.map.min_cell().x, 150 - 50);
  EXPECT_EQ(file.map.min_cell().y, -20 - 50);
  const auto [lo, hi] = measured_x_extent(file);
  EXPECT_GE(lo, 1.0);
  EXPECT_LE(hi, 2.0);
  EXPECT_GT(summary_of(dir, "centre")["map"]["measured_cells"].get<std::size_t>(), 1000u);
}

TEST(MapWindowCli, BadValuesAreRefusedNamingTheOption) {
  test::TestFolder dir;
  write_long_run(dir);
  for (const char* bad : {"1.5", "fit2", "a,b", "1,2,3", "nan,0", "1e9,0", ",1"}) {
    const auto result = map_long_run(dir, "bad", std::string("--window ") + shell_quoted(bad));
    EXPECT_NE(result.exit_code, 0) << bad;
    EXPECT_NE(result.output.find("--window"), std::string::npos) << bad << ": " << result.output;
    EXPECT_FALSE(std::filesystem::exists(dir / "bad")) << bad;
  }
  const auto fine = map_long_run(dir, "first", "");
  ASSERT_TRUE(std::filesystem::exists(dir / "first/map.smap")) << fine.output;  // empty (exit 1), but resumable
  const auto resumed = map_long_run(dir, "second", "--window 0,0 --resume " + shell_quoted(dir / "first/map.smap"));
  EXPECT_EQ(resumed.exit_code, 2) << resumed.output;
  EXPECT_NE(resumed.output.find("--window: a resumed map keeps the window of its map file"), std::string::npos)
      << resumed.output;
  // Finer cells than any map may hold for this run: said, with what to do.
  dir.write("fine.yaml", "map:\n  cell_size_m: 0.0005\n");
  const auto too_large = map_long_run(dir, "large", "--window fit --config " + shell_quoted(dir / "fine.yaml"));
  EXPECT_EQ(too_large.exit_code, 2) << too_large.output;
  EXPECT_NE(too_large.output.find("--window fit: the run's points span"), std::string::npos) << too_large.output;
  EXPECT_NE(too_large.output.find("beyond the limit of 4096"), std::string::npos) << too_large.output;
  const auto live = run_cli("live --device " + shell_quoted(dir / "no-device") + " --poses " +
                            shell_quoted(dir / "poses.txt") + " --out " + shell_quoted(dir / "live") + " --window fit");
  EXPECT_EQ(live.exit_code, 2) << live.output;
  EXPECT_NE(live.output.find("--window fit: live cannot know"), std::string::npos) << live.output;
}

}  // namespace
}  // namespace stridemap
