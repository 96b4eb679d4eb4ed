// `stridemap import`, `map` on what it wrote, then `export` and `map-info`
// on the map file `map` leaves: the whole path a user takes with a
// recording from elsewhere.
#include <cmath>
#include <filesystem>
#include <fstream>
#include <iterator>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "cli/cli_runner.hpp"
#include "live/test_folder.hpp"
#include "stridemap/mapfile/map_file.hpp"
#include "test_paths.hpp"

namespace stridemap {
namespace {

using test::run_cli;
using test::shell_quoted;
using test::TestFolder;

const std::filesystem::path kExp1 =
    std::filesystem::path(STRIDEMAP_SHARED_DATA_DIR) / "urg04lx_breezyslam" / "exp1.dat";

TEST(ImportCli, BreezySlamRecordingIsMappedThroughTheScanLog) {
  if (!std::filesystem::exists(kExp1)) GTEST_SKIP() << "no real recording at " << kExp1 << " (../shared/data absent)";
  TestFolder folder;
  const auto imported = run_cli("import breezyslam " + shell_quoted(kExp1.string()) + " --log " +
                                shell_quoted(folder / "exp1.log") + " --poses " + shell_quoted(folder / "exp1.poses"));
  ASSERT_EQ(imported.exit_code, 0) << imported.output;
  EXPECT_NE(imported.output.find("756 scans, 756 poses"), std::string::npos) << imported.output;

  // Without the rover's mount the default (pitched down) one puts every
  // point where the window is not: an empty map, exit 1, naming --config.
  const std::string map = "map --log " + shell_quoted(folder / "exp1.log") + " --poses " +
                          shell_quoted(folder / "exp1.poses") + " --out ";
  const auto unmounted = run_cli(map + shell_quoted(folder / "unmounted"));
  EXPECT_EQ(unmounted.exit_code, 1) << unmounted.output;
  EXPECT_NE(unmounted.output.find("the map is empty (coverage 0 %)"), std::string::npos) << unmounted.output;
  EXPECT_NE(unmounted.output.find("give the sensor's mount with --config"), std::string::npos) << unmounted.output;
  const auto mapped = run_cli(map + shell_quoted(folder / "out") + " --config " +
                              shell_quoted(std::string(STRIDEMAP_SOURCE_DIR) + "/configs/breezyslam_rover.yaml"));
  ASSERT_EQ(mapped.exit_code, 0) << mapped.output;
  std::ifstream summary_file(folder / "out/summary.json");
  const auto summary = nlohmann::json::parse(summary_file);
  EXPECT_EQ(summary["scans"]["received"], 756);
  EXPECT_EQ(summary["scans"]["rejected"], 0);  // the 683-value scans fit the imported PP
  // Every scan lies within the poses (they share the log's own clock).
  EXPECT_EQ(summary["scans"]["integrated"], 756) << summary.dump(1);
  EXPECT_GT(summary["beams"]["valid"].get<long>(), 756 * 300);

  // map leaves a map file beside the other outputs; it reloads whole.
  const io::MapFile file = io::load_map_file(folder / "out/map.smap");
  EXPECT_EQ(file.map.cells_per_side(), summary["map"]["cells_per_side"].get<int>());
  EXPECT_NE(file.metadata.created_by.find("map"), std::string::npos);
  ASSERT_TRUE(file.metadata.mount.has_value());

  const auto exported = run_cli("export " + shell_quoted(folder / "out/map.smap") + " --npy " +
                                shell_quoted(folder / "npy") + " --ply " + shell_quoted(folder / "map.ply") +
                                " --csv " + shell_quoted(folder / "csv"));
  ASSERT_EQ(exported.exit_code, 0) << exported.output;
  EXPECT_TRUE(std::filesystem::exists(folder / "npy/elevation.npy"));
  EXPECT_TRUE(std::filesystem::exists(folder / "csv/cells.csv"));
  EXPECT_NE(exported.output.find("vertices"), std::string::npos);

  // Outputs are never replaced unasked.
  const auto again = run_cli("export " + shell_quoted(folder / "out/map.smap") + " --ply " + shell_quoted(folder / "map.ply"));
  EXPECT_EQ(again.exit_code, 2) << again.output;
  EXPECT_NE(again.output.find("already exists"), std::string::npos) << again.output;

  const auto info = run_cli("map-info " + shell_quoted(folder / "out/map.smap"));
  ASSERT_EQ(info.exit_code, 0) << info.output;
  const auto header = nlohmann::json::parse(info.output);
  EXPECT_EQ(header["format"], "stridemap map");
  // The seven built-in layers and the five foothold layers (docs/foothold.md).
  EXPECT_EQ(header["layers"].size(), 12u);
}

TEST(ImportCli, ExistingOutputsAreNotReplacedAndBadLinesAreReported) {
  TestFolder folder;
  const std::string trajectory =
      folder.write("traj.txt", "# tum\n1.0 0 0 0 0 0 0 1\nbroken line\n2.0 1 0 0 0 0 0 1\n");
  const std::string poses = folder.write("poses.txt", "mine\n");
  const auto refused = run_cli("import tum " + shell_quoted(trajectory) + " --poses " + shell_quoted(poses));
  EXPECT_EQ(refused.exit_code, 2) << refused.output;
  EXPECT_NE(refused.output.find("already exists"), std::string::npos) << refused.output;
  EXPECT_EQ(folder.read("poses.txt"), "mine\n");

  const auto imported = run_cli("import tum " + shell_quoted(trajectory) + " --poses " + shell_quoted(folder / "new.txt"));
  ASSERT_EQ(imported.exit_code, 0) << imported.output;
  EXPECT_NE(imported.output.find("traj.txt:3: 2 fields, expected 8"), std::string::npos) << imported.output;
  EXPECT_NE(imported.output.find("2 poses"), std::string::npos) << imported.output;
  EXPECT_NE(imported.output.find("1 malformed lines skipped"), std::string::npos) << imported.output;

  const std::string empty = folder.write("empty.txt", "# nothing\n");
  const auto nothing = run_cli("import tum " + shell_quoted(empty) + " --poses " + shell_quoted(folder / "p2.txt"));
  EXPECT_EQ(nothing.exit_code, 2) << nothing.output;
  EXPECT_NE(nothing.output.find("nothing to import"), std::string::npos) << nothing.output;
  EXPECT_FALSE(std::filesystem::exists(folder / "p2.txt"));
}

TEST(ImportCli, DevicesBinaryFilesAndOutOfOrderTimesAreReported) {
  TestFolder folder;
  // A device has no size and /dev/zero never ends: refused before reading, exit 2.
  const auto device = run_cli("import tum /dev/zero --poses " + shell_quoted(folder / "z.txt"));
  EXPECT_EQ(device.exit_code, 2) << device.output;
  EXPECT_NE(device.output.find("/dev/zero: not a regular file"), std::string::npos) << device.output;
  const std::string blob = folder.write("blob.dat", std::string("1.0 0 0\0\0\x01", 10));
  const auto binary = run_cli("import tum " + shell_quoted(blob) + " --poses " + shell_quoted(folder / "b.txt"));
  EXPECT_EQ(binary.exit_code, 2) << binary.output;
  EXPECT_NE(binary.output.find("blob.dat: not a text file"), std::string::npos) << binary.output;
  EXPECT_FALSE(std::filesystem::exists(folder / "b.txt"));

  const std::string trajectory = folder.write(
      "late.txt", "\xEF\xBB\xBF" "1.0 0 0 0 0 0 0 1\n1e308 0 0 0 0 0 0 1\n2.0 0 0 0 0 0 0 1\n3.0 0 0 0 0 0 0 1\n");
  const auto imported = run_cli("import tum " + shell_quoted(trajectory) + " --poses " + shell_quoted(folder / "p.txt"));
  ASSERT_EQ(imported.exit_code, 0) << imported.output;
  EXPECT_NE(imported.output.find("late.txt:2: time 1e+308 is out of order"), std::string::npos) << imported.output;
  EXPECT_NE(imported.output.find("3 poses"), std::string::npos) << imported.output;
  EXPECT_NE(imported.output.find("0 malformed lines skipped, 1 out of time order skipped"), std::string::npos)
      << imported.output;
}

// A text point-pair log of a sensor standing still: the scans and one pose
// per scan, ready for `map`; without times the scan rate is asked for.
TEST(ImportCli, PointPairsOfAStandingSensorBecomeAScanLogAndPoses) {
  TestFolder folder;
  std::string text;
  const double step = 2.0 * 3.14159265358979323846 / 1024.0;
  for (int s = 0; s < 20; ++s) {
    for (int k = 0; k < 100; ++k) {
      const double angle = (k - 50) * step, r = 1000.0 + s;
      text += (k ? " " : "") + std::to_string(std::lround(r * std::cos(angle))) + " " +
              std::to_string(std::lround(r * std::sin(angle)));
    }
    text += "\n";
  }
  folder.write("pairs.txt", text);
  const auto asked = run_cli("import xy " + shell_quoted(folder / "pairs.txt") + " --encoding text --log " +
                             shell_quoted(folder / "run.log"));
  EXPECT_EQ(asked.exit_code, 2) << asked.output;
  EXPECT_NE(asked.output.find("--scan-rate-hz"), std::string::npos) << asked.output;
  EXPECT_FALSE(std::filesystem::exists(folder / "run.log"));
  const std::string base = "import xy " + shell_quoted(folder / "pairs.txt") + " --encoding text --scan-rate-hz 10 --log " +
                           shell_quoted(folder / "run.log");
  const auto four = run_cli(base + " --static-pose 1,2,3,4 --poses " + shell_quoted(folder / "run.poses"));
  EXPECT_EQ(four.exit_code, 2) << four.output;
  EXPECT_NE(four.output.find("--static-pose: expected X,Y,YAW or X,Y,Z,ROLL,PITCH,YAW, got 4 numbers"),
            std::string::npos)
      << four.output;
  const auto alone = run_cli(base + " --static-pose 1,2,3");
  EXPECT_EQ(alone.exit_code, 2) << alone.output;
  EXPECT_NE(alone.output.find("--static-pose and --poses go together"), std::string::npos) << alone.output;
  EXPECT_FALSE(std::filesystem::exists(folder / "run.log"));
  const auto made = run_cli("import xy " + shell_quoted(folder / "pairs.txt") + " --encoding text --scan-rate-hz 10 " +
                            "--static-pose 0.5,0,90 --log " + shell_quoted(folder / "run.log") + " --poses " +
                            shell_quoted(folder / "run.poses"));
  ASSERT_EQ(made.exit_code, 0) << made.output;
  EXPECT_NE(made.output.find("import xy: 20 scans, 20 poses"), std::string::npos) << made.output;
  EXPECT_NE(folder.read("run.log").find("ARES:1024"), std::string::npos);
  EXPECT_NE(folder.read("run.poses").find("\n1.9 0.5 0 1.5707963267948966"), std::string::npos) << folder.read("run.poses");
}

TEST(ExportCli, ADamagedMapFileIsAClearError) {
  TestFolder folder;
  const std::string damaged = folder.write("bad.smap", std::string("SMAP\r\n\x1a\n", 8) + std::string(40, 'x'));
  const auto info = run_cli("map-info " + shell_quoted(damaged));
  EXPECT_EQ(info.exit_code, 2) << info.output;
  EXPECT_NE(info.output.find("checksum mismatch"), std::string::npos) << info.output;
  const auto exported = run_cli("export " + shell_quoted(damaged) + " --npy " + shell_quoted(folder / "npy"));
  EXPECT_EQ(exported.exit_code, 2) << exported.output;
  EXPECT_FALSE(std::filesystem::exists(folder / "npy"));
}

}  // namespace
}  // namespace stridemap
