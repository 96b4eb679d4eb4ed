// A user's files are sacred (docs/outputs.md, "Overwriting"): no command
// truncates a log or one of its own inputs, the refusal names the option and
// exits 2 before anything is opened for writing, and an interrupted
// experiment leaves the previous results whole with no temporary behind.
#include <gtest/gtest.h>

#include <signal.h>

#include <chrono>
#include <filesystem>
#include <thread>
#include <utility>

#include "cli/background_process.hpp"
#include "cli/cli_runner.hpp"
#include "live/test_folder.hpp"
#include "stridemap/io/output_folder.hpp"
#include "stridemap/io/scan_log.hpp"
#include "test_paths.hpp"

namespace stridemap {
namespace {

namespace fs = std::filesystem;
using test::BackgroundProcess;
using test::run_cli;
using test::shell_quoted;

const std::string kScene = std::string(STRIDEMAP_SOURCE_DIR) + "/scenes/cart_rail_boxes.yaml";
const std::string kSlConfig = std::string(STRIDEMAP_SOURCE_DIR) + "/configs/ragno_structured_light.yaml";

std::string q(const std::string& path) { return shell_quoted(path); }

TEST(OutputSafety, AnExistingLogIsNeverTruncatedWithoutOverwriteOrAppend) {
  test::TestFolder dir;
  const std::string precious = "five thousand pose lines, say\n";
  const std::string log = dir.write("run.urglog", precious);
  // A wrong device too: before, the log was truncated before the device was even tried.
  for (const std::string& command :
       {"record --device " + q(dir / "nothing") + " --out " + q(log) + " --connect-timeout-s 0.2",
        "live --device " + q(dir / "nothing") + " --poses " + q(dir.write("p.txt", "0 0 0 0 0 0\n")) + " --out " +
            q(dir / "out") + " --record " + q(log) + " --connect-timeout-s 0.2"}) {
    const auto r = run_cli(command);
    EXPECT_EQ(r.exit_code, 2) << r.output;
    EXPECT_NE(r.output.find("stridemap: error: " + std::string(command[0] == 'r' ? "--out: '" : "--record: '") + log +
                            "' exists (30 bytes); pass --overwrite to replace it or --append to add to it"),
              std::string::npos)
        << r.output;
    EXPECT_EQ(dir.read("run.urglog"), precious);
  }
  // With --overwrite, still nothing is touched while the device cannot be opened.
  auto r = run_cli("record --device " + q(dir / "nothing") + " --out " + q(log) + " --overwrite --connect-timeout-s 0.2");
  EXPECT_EQ(r.exit_code, 2) << r.output;
  EXPECT_EQ(dir.read("run.urglog"), precious);
  // --append onto something that is no scan log is refused.
  r = run_cli("record --device " + q(dir / "nothing") + " --out " + q(log) + " --append --connect-timeout-s 0.2");
  EXPECT_EQ(r.exit_code, 2) << r.output;
  EXPECT_NE(r.output.find("is not a stridemap-urg-log file; --append would mix two formats"), std::string::npos)
      << r.output;
  r = run_cli("record --device x --out " + q(log) + " --append --overwrite");
  EXPECT_NE(r.output.find("--overwrite and --append exclude each other"), std::string::npos) << r.output;
  EXPECT_EQ(dir.read("run.urglog"), precious);
}

TEST(OutputSafety, AnOutputThatIsAnInputIsRefusedByDeviceAndInode) {
  test::TestFolder dir;
  const std::string poses = dir.write("poses.txt", "1 0 0 0 0 0\n2 0 0 0 0 0\n");
  fs::create_hard_link(poses, dir / "poses-link.txt");  // the same file under another name
  auto r = run_cli("live --device " + q(dir / "nothing") + " --poses " + q(poses) + " --out " + q(dir / "out") +
                   " --record " + q(dir / "poses-link.txt") + " --overwrite --connect-timeout-s 0.2");
  EXPECT_EQ(r.exit_code, 2) << r.output;
  EXPECT_NE(r.output.find("stridemap: error: --record: '" + dir / "poses-link.txt" + "' is the same file as --poses '" +
                          poses + "'; writing it would destroy the input"),
            std::string::npos)
      << r.output;
  EXPECT_EQ(dir.read("poses.txt"), "1 0 0 0 0 0\n2 0 0 0 0 0\n");

  const std::string csv = dir.write("pairs.csv", "measured_m,true_m\n1,1\n2,2\n3,3\n4,4\n5,5\n");
  r = run_cli("calibrate-range --csv " + q(csv) + " --json " + q(csv));
  EXPECT_EQ(r.exit_code, 2) << r.output;
  EXPECT_NE(r.output.find("--json: '" + csv + "' is the same file as --csv"), std::string::npos) << r.output;
  EXPECT_EQ(dir.read("pairs.csv"), "measured_m,true_m\n1,1\n2,2\n3,3\n4,4\n5,5\n");

  fs::copy_file(kScene, dir / "scene.yaml");
  const std::string scene_text = dir.read("scene.yaml");
  r = run_cli("simulate-stripe-image --config " + q(kSlConfig) + " --scene " + q(dir / "scene.yaml") + " --out " +
              q(dir / "scene.yaml"));
  EXPECT_EQ(r.exit_code, 2) << r.output;
  EXPECT_NE(r.output.find("--out: '" + dir / "scene.yaml" + "' is the same file as --scene"), std::string::npos)
      << r.output;
  EXPECT_EQ(dir.read("scene.yaml"), scene_text);

  // An output folder that holds an input (or anything stridemap did not write) would be replaced whole.
  r = run_cli("map --log " + q(dir / "x.log") + " --poses " + q(poses) + " --out " + q(dir.path().string()));
  EXPECT_EQ(r.exit_code, 2) << r.output;
  EXPECT_NE(r.output.find("--out: folder '" + dir.path().string() + "' holds --log"), std::string::npos) << r.output;
  fs::create_directories(dir / "mine");
  dir.write("mine/notes.txt", "mine\n");
  r = run_cli("map --log " + q(dir / "x.log") + " --poses " + q(poses) + " --out " + q(dir / "mine"));
  EXPECT_EQ(r.exit_code, 2) << r.output;
  EXPECT_NE(r.output.find("--out: folder '" + dir / "mine" + "' holds 'notes.txt', which stridemap did not write"),
            std::string::npos)
      << r.output;
  EXPECT_EQ(dir.read("mine/notes.txt"), "mine\n");
}

// SIGTERM (or SIGINT, SIGHUP) while an experiment writes over a previous
// run: the previous results stay whole and no temporary is left.
TEST(OutputSafety, InterruptedExperimentLeavesThePreviousResultsWhole) {
  test::TestFolder dir;
  const std::string run = "experiment cart-rail --scene " + q(kScene) + " --out " + q(dir / "out") + " --seed ";
  ASSERT_EQ(run_cli(run + "1").exit_code, 0);
  std::string summary = dir.read("out/cart-rail-urg/summary.json");
  std::string elevation = dir.read("out/cart-rail-urg/elevation.png");
  ASSERT_TRUE(fs::exists(dir / ("out/cart-rail-urg/" + std::string(io::kOutputManifest))));
  int interrupted = 0;
  // At different moments: while computing, and (on a slow machine) while writing.
  // An idle machine runs the experiment in about 0.3 s, a loaded one in seconds.
  for (const auto& [sig, delay_ms] : {std::pair{SIGTERM, 40}, std::pair{SIGINT, 120}, std::pair{SIGHUP, 250},
                                      std::pair{SIGTERM, 700}, std::pair{SIGINT, 1000}}) {
    BackgroundProcess second(std::string(q(STRIDEMAP_CLI_PATH)) + " " + run + "2");
    std::this_thread::sleep_for(std::chrono::milliseconds(delay_ms));
    second.signal(sig);
    const int status = second.wait(60.0);
    if (status == 0) {
      // Finished before the signal: its results are now the previous ones
      // the next interrupted run must leave whole.
      summary = dir.read("out/cart-rail-urg/summary.json");
      elevation = dir.read("out/cart-rail-urg/elevation.png");
      continue;
    }
    ++interrupted;
    EXPECT_EQ(dir.read("out/cart-rail-urg/summary.json"), summary) << "signal " << sig;
    EXPECT_EQ(dir.read("out/cart-rail-urg/elevation.png"), elevation) << "signal " << sig;
    for (const auto& entry : fs::directory_iterator(dir / "out")) {
      EXPECT_EQ(entry.path().filename().string(), "cart-rail-urg") << "left behind after signal " << sig;
    }
  }
  EXPECT_GT(interrupted, 0) << "every run ended before its signal; the test checks nothing";
}

TEST(OutputSafety, RecordAppendsToItsOwnLog) {
  test::TestFolder dir;
  BackgroundProcess emulator(std::string(q(STRIDEMAP_CLI_PATH)) + " emulate-urg --link " + q(dir / "urg") +
                             " --rate-hz 100 --duration-s 60 --scene " + q(kScene));
  ASSERT_TRUE(emulator.wait_for_output("emulating a URG-04LX on", 10.0)) << emulator.output();
  const std::string record = "record --device " + q(dir / "urg") + " --out " + q(dir / "log.txt") +
                             " --max-scans 5 --connect-timeout-s 10";
  ASSERT_EQ(run_cli(record).exit_code, 0);
  auto again = run_cli(record);
  EXPECT_EQ(again.exit_code, 2) << again.output;
  again = run_cli(record + " --append");
  ASSERT_EQ(again.exit_code, 0) << again.output;
  const io::ScanLog log = io::read_scan_log(dir / "log.txt");
  EXPECT_EQ(log.scans.size(), 10u);
  EXPECT_EQ(log.connects, 2u);
  EXPECT_TRUE(log.damage.empty()) << log.damage;
  again = run_cli(record + " --overwrite");
  ASSERT_EQ(again.exit_code, 0) << again.output;
  EXPECT_EQ(io::read_scan_log(dir / "log.txt").scans.size(), 5u);
}

}  // namespace
}  // namespace stridemap
