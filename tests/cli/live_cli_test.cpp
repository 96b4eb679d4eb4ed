// The real-sensor commands as a user runs them, against the emulator on a
// pseudo-terminal: live mapping and replay give byte-identical maps, record
// keeps real scans bit for bit, SIGINT and SIGHUP end cleanly, bad pose
// lines are skipped and named, a run that maps nothing fails and says why,
// and bad devices, pose files and logs give clear errors.
#include <gtest/gtest.h>

#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <csignal>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <thread>

#include "cli/background_process.hpp"
#include "cli/cli_runner.hpp"
#include "live/test_folder.hpp"
#include "stridemap/devices/pseudo_terminal.hpp"
#include "stridemap/recordings/recorded_scans.hpp"
#include "stridemap/recordings/scan_log.hpp"
#include "test_paths.hpp"

namespace stridemap {
namespace {

using test::BackgroundProcess;
using test::run_cli;
using test::shell_quoted;

const std::string kScene = std::string(STRIDEMAP_SOURCE_DIR) + "/scenes/cart_rail_boxes.yaml";
const std::filesystem::path kBreezySlam = std::filesystem::path(STRIDEMAP_SHARED_DATA_DIR) / "urg04lx_breezyslam" / "exp1.dat";

std::string cli() { return shell_quoted(STRIDEMAP_CLI_PATH); }

std::unique_ptr<BackgroundProcess> start_emulator(const test::TestFolder& dir, const std::string& extra) {
  auto emulator = std::make_unique<BackgroundProcess>(cli() + " emulate-urg --link " + shell_quoted(dir / "urg") +
                                                      " --rate-hz 100 --duration-s 60 " + extra);
  EXPECT_TRUE(emulator->wait_for_output("emulating a URG-04LX on", 10.0)) << emulator->output();
  return emulator;
}

TEST(LiveCli, LiveAndReplayOfTheSameDataGiveByteIdenticalMaps) {
  test::TestFolder dir;
  auto emulator = start_emulator(dir, "--scene " + shell_quoted(kScene) + " --motion cart-rail --poses-out " +
                                          shell_quoted(dir / "poses.txt") + " --poses-clock sensor");
  const auto live = run_cli("live --device " + shell_quoted(dir / "urg") + " --poses " + shell_quoted(dir / "poses.txt") +
                            " --clock sensor --out " + shell_quoted(dir / "live") + " --record " +
                            shell_quoted(dir / "log.txt") + " --max-scans 100 --connect-timeout-s 10");
  ASSERT_EQ(live.exit_code, 0) << live.output;
  EXPECT_NE(live.output.find("live: 100 scans mapped of 100 received"), std::string::npos) << live.output;
  const auto replay = run_cli("map --log " + shell_quoted(dir / "log.txt") + " --poses " +
                              shell_quoted(dir / "poses.txt") + " --clock sensor --out " + shell_quoted(dir / "map"));
  ASSERT_EQ(replay.exit_code, 0) << replay.output;
  EXPECT_NE(replay.output.find("map: 100 scans mapped of 100"), std::string::npos) << replay.output;
  for (const char* file : {"elevation.csv", "certainty.csv", "state.csv", "elevation.png", "certainty.png"}) {
    const std::string a = dir.read(std::string("live/") + file), b = dir.read(std::string("map/") + file);
    EXPECT_FALSE(a.empty()) << file;
    EXPECT_TRUE(a == b) << file << " differs between live mapping and replay";
  }
  const std::string summary = dir.read("live/summary.json");
  EXPECT_NE(summary.find("\"scan_rate_hz\""), std::string::npos);
  EXPECT_NE(summary.find("\"latency_s\""), std::string::npos);
  EXPECT_NE(dir.read("map/summary.json").find("\"integrated\": 100"), std::string::npos);
}

TEST(LiveCli, RecordKeepsRealScansBitForBit) {
  if (!std::filesystem::exists(kBreezySlam)) GTEST_SKIP() << "BreezySLAM recording not found at " << kBreezySlam;
  test::TestFolder dir;
  auto emulator = start_emulator(dir, "--replay " + shell_quoted(kBreezySlam.string()) + " --variant ug01");
  const auto record = run_cli("record --device " + shell_quoted(dir / "urg") + " --out " + shell_quoted(dir / "log.txt") +
                              " --max-scans 40 --connect-timeout-s 10");
  ASSERT_EQ(record.exit_code, 0) << record.output;
  const io::ScanLog log = io::read_scan_log(dir / "log.txt");
  EXPECT_TRUE(log.damage.empty()) << log.damage;
  EXPECT_EQ(log.version.firmware, "3.4.03(17/Dec./2012)");
  ASSERT_EQ(log.scans.size(), 40u);
  const io::RecordedScans real = io::read_breezyslam_scans(kBreezySlam.string());
  for (const UrgScan& scan : log.scans) {
    const std::size_t n = scan.sensor_time_ms / 10;  // the emulator's scan number: one per 10 ms
    const std::vector<std::uint32_t>& line = real.scans[n % real.scans.size()];
    // The log holds steps 44..725: the first 682 of the recording's 683 values.
    ASSERT_EQ(scan.raw.values_mm, std::vector<std::uint32_t>(line.begin(), line.begin() + 682)) << "scan " << n;
  }
}

TEST(LiveCli, InterruptSavesTheMapAndExitsCleanly) {
  test::TestFolder dir;
  auto emulator = start_emulator(dir, "--scene " + shell_quoted(kScene) + " --x-m 0.3 --poses-out " +
                                          shell_quoted(dir / "poses.txt"));
  BackgroundProcess live(cli() + " live --device " + shell_quoted(dir / "urg") + " --poses " +
                         shell_quoted(dir / "poses.txt") + " --out " + shell_quoted(dir / "out") +
                         " --status-every-s 0.2 --connect-timeout-s 10");
  ASSERT_TRUE(live.wait_for_output("live: ", 15.0)) << live.output();  // the first status line: it maps
  live.signal(SIGINT);
  EXPECT_EQ(live.wait(15.0), 0) << live.output();
  EXPECT_NE(live.output().find("scans mapped of"), std::string::npos) << live.output();
  EXPECT_TRUE(std::filesystem::exists(dir / "out/elevation.png"));
  EXPECT_NE(dir.read("out/summary.json").find("\"command\": \"live\""), std::string::npos);
}

TEST(LiveCli, BadPoseArrivingLiveIsSkippedAndMappingGoesOn) {
  test::TestFolder dir;
  auto emulator = start_emulator(dir, "--scene " + shell_quoted(kScene) + " --x-m 0.3");
  const std::string fifo = dir / "poses.fifo";
  ASSERT_EQ(::mkfifo(fifo.c_str(), 0600), 0);
  BackgroundProcess live(cli() + " live --device " + shell_quoted(dir / "urg") + " --poses " + shell_quoted(fifo) +
                         " --out " + shell_quoted(dir / "out") + " --max-pose-gap-s 100000 --status-every-s 0.1" +
                         " --connect-timeout-s 10");
  ASSERT_TRUE(live.wait_for_output("connected", 15.0)) << live.output();  // its reader has the pipe open
  const int writer = ::open(fifo.c_str(), O_WRONLY | O_NONBLOCK);
  ASSERT_GE(writer, 0);
  const double now = static_cast<double>(std::chrono::duration_cast<std::chrono::milliseconds>(
                         std::chrono::system_clock::now().time_since_epoch()).count()) / 1000.0;
  const std::string good = std::to_string(now - 10) + " 0.3 0 0 0 0\n" + std::to_string(now + 1000) + " 0.3 0 0 0 0\n";
  ASSERT_EQ(::write(writer, good.data(), good.size()), static_cast<ssize_t>(good.size()));
  // A status line with scans in the map: "..., 12 mapped, ...".
  const auto mapped_some = [](const std::string& out) {
    for (std::size_t at = out.find(" mapped,"); at != std::string::npos; at = out.find(" mapped,", at + 1)) {
      std::size_t digits = at;
      while (digits > 0 && out[digits - 1] >= '0' && out[digits - 1] <= '9') --digits;
      if (digits < at && std::stoul(out.substr(digits, at - digits)) > 0) return true;
    }
    return false;
  };
  ASSERT_TRUE(live.wait_until(mapped_some, 15.0)) << live.output();
  // Earlier than the last pose, then garbage, then NaN: each skipped and named, mapping goes on.
  const std::string bad = std::to_string(now) + " 0.3 0 0 0 0\ngarbage\n" + std::to_string(now + 1001) +
                          " nan 0 0 0 0\n" + std::to_string(now + 1002) + " 0.3 0 0 0 0\n";
  ASSERT_EQ(::write(writer, bad.data(), bad.size()), static_cast<ssize_t>(bad.size()));
  ASSERT_TRUE(live.wait_for_output("poses.fifo:5: field 2 'nan'", 15.0)) << live.output();
  const std::size_t mapped_before = live.output().size();
  ASSERT_TRUE(live.wait_until([&](const std::string& out) { return mapped_some(out.substr(mapped_before)); }, 15.0))
      << live.output();  // still mapping
  live.signal(SIGINT);
  EXPECT_EQ(live.wait(15.0), 0) << live.output();
  ::close(writer);
  EXPECT_NE(live.output().find("poses.fifo:3: pose time"), std::string::npos) << live.output();
  EXPECT_NE(live.output().find("poses.fifo:4: field 1 'garbage' is not a finite number"), std::string::npos) << live.output();
  EXPECT_NE(live.output().find("3 pose lines skipped"), std::string::npos) << live.output();
  EXPECT_NE(dir.read("out/summary.json").find("\"pose_lines_skipped\": 3"), std::string::npos);
}

// An ssh session that drops sends SIGHUP: the map is saved, the log closed, exit 0.
TEST(LiveCli, HangUpSavesTheMapAndTheLog) {
  test::TestFolder dir;
  auto emulator = start_emulator(dir, "--scene " + shell_quoted(kScene) + " --x-m 0.3 --poses-out " +
                                          shell_quoted(dir / "poses.txt"));
  BackgroundProcess live(cli() + " live --device " + shell_quoted(dir / "urg") + " --poses " +
                         shell_quoted(dir / "poses.txt") + " --out " + shell_quoted(dir / "out") + " --record " +
                         shell_quoted(dir / "log.txt") + " --status-every-s 0.2 --connect-timeout-s 10");
  ASSERT_TRUE(live.wait_for_output("live: ", 15.0)) << live.output();
  live.signal(SIGHUP);
  EXPECT_EQ(live.wait(15.0), 0) << live.output();
  EXPECT_NE(dir.read("out/summary.json").find("\"command\": \"live\""), std::string::npos);
  const io::ScanLog log = io::read_scan_log(dir / "log.txt");
  EXPECT_TRUE(log.damage.empty()) << log.damage;
  EXPECT_GT(log.scans.size(), 0u);
}

// Poses on the sensor's clock, scans mapped on the host's: nothing can be
// mapped, and the run says why and fails.
TEST(LiveCli, PosesOnAnotherClockFailTheRunAndSayWhy) {
  test::TestFolder dir;
  auto emulator = start_emulator(dir, "--scene " + shell_quoted(kScene) + " --poses-out " +
                                          shell_quoted(dir / "poses.txt") + " --poses-clock sensor");
  const auto live = run_cli("live --device " + shell_quoted(dir / "urg") + " --poses " + shell_quoted(dir / "poses.txt") +
                            " --out " + shell_quoted(dir / "out") + " --max-scans 20 --connect-timeout-s 10" +
                            " --record " + shell_quoted(dir / "log.txt"));
  EXPECT_EQ(live.exit_code, 1) << live.output;
  EXPECT_NE(live.output.find("stridemap: error: 0 scans mapped of 20: the scans span "), std::string::npos)
      << live.output;
  EXPECT_NE(live.output.find("(host clock): they do not overlap"), std::string::npos) << live.output;
  const auto replay = run_cli("map --log " + shell_quoted(dir / "log.txt") + " --poses " +
                              shell_quoted(dir / "poses.txt") + " --out " + shell_quoted(dir / "map"));
  EXPECT_EQ(replay.exit_code, 1) << replay.output;
  EXPECT_NE(replay.output.find("0 scans mapped of 20"), std::string::npos) << replay.output;
  EXPECT_NE(replay.output.find("after the last"), std::string::npos) << replay.output;
}

TEST(LiveCli, LiveMappingSurvivesTheSensorVanishingAndComingBack) {
  test::TestFolder dir;
  auto emulator = start_emulator(dir, "--scene " + shell_quoted(kScene) + " --motion cart-rail --poses-out " +
                                          shell_quoted(dir / "poses.txt") + " --poses-rate-hz 200" +
                                          " --fault disconnect@30:0.5 --fault corrupt@80");
  const auto live = run_cli("live --device " + shell_quoted(dir / "urg") + " --poses " + shell_quoted(dir / "poses.txt") +
                            " --out " + shell_quoted(dir / "out") + " --max-scans 100 --connect-timeout-s 10");
  ASSERT_EQ(live.exit_code, 0) << live.output;
  EXPECT_NE(live.output.find("stridemap: link_lost: "), std::string::npos) << live.output;
  EXPECT_NE(live.output.find("stridemap: sensor_reset: "), std::string::npos) << live.output;
  EXPECT_NE(live.output.find("stridemap: corrupt_data: "), std::string::npos) << live.output;
  const std::string summary = dir.read("out/summary.json");
  EXPECT_NE(summary.find("\"connects\": 2"), std::string::npos) << summary;
  EXPECT_NE(summary.find("\"corrupt_frames\": 1"), std::string::npos) << summary;
}

TEST(LiveCli, MissingDeviceOrOneThatIsNoSerialPortIsAClearError) {
  test::TestFolder dir;
  dir.write("poses.txt", "0 0 0 0 0 0\n");
  auto result = run_cli("record --device " + shell_quoted(dir / "nothing") + " --out " + shell_quoted(dir / "log.txt") +
                        " --connect-timeout-s 0.5");
  EXPECT_EQ(result.exit_code, 2) << result.output;
  // No wait for the connect timeout: a missing path cannot start streaming.
  EXPECT_NE(result.output.find("stridemap: error: " + dir / "nothing" + ": cannot open the device: No such file or directory"),
            std::string::npos)
      << result.output;
  result = run_cli("live --device /dev/null --poses " + shell_quoted(dir / "poses.txt") + " --out " +
                   shell_quoted(dir / "out") + " --connect-timeout-s 0.5");
  EXPECT_EQ(result.exit_code, 2) << result.output;
  EXPECT_NE(result.output.find("/dev/null: it is not a serial device (not a terminal)"), std::string::npos) << result.output;
}

TEST(LiveCli, DeviceThatIsNoUrgIsAClearError) {
  test::TestFolder dir;
  io::PseudoTerminal pty(dir / "modem");
  std::atomic<bool> stop{false};
  // Something that answers, but not in SCIP: a modem, say.
  std::thread modem([&] {
    char buffer[256];
    while (!stop.load()) {
      if (pty.read(buffer, std::chrono::milliseconds(20)).bytes > 0) {
        pty.write("\r\nERROR\r\n\xfe\xff", std::chrono::milliseconds(100));
      }
    }
  });
  const auto result = run_cli("record --device " + shell_quoted(dir / "modem") + " --out " +
                              shell_quoted(dir / "log.txt") + " --connect-timeout-s 4");
  stop.store(true);
  modem.join();
  EXPECT_EQ(result.exit_code, 2) << result.output;
  EXPECT_NE(result.output.find("no reply to QT within 1.00 s (3 tries): is it a URG, and powered?; it sent"),
            std::string::npos)
      << result.output;
}

TEST(LiveCli, BadPoseFilesAndDamagedLogsAreNamed) {
  test::TestFolder dir;
  auto emulator = start_emulator(dir, "--scene " + shell_quoted(kScene) + " --poses-out " +
                                          shell_quoted(dir / "poses.txt") + " --poses-clock sensor");
  ASSERT_EQ(run_cli("record --device " + shell_quoted(dir / "urg") + " --out " + shell_quoted(dir / "log.txt") +
                    " --max-scans 20 --connect-timeout-s 10")
                .exit_code,
            0);
  const std::string map = "map --log " + shell_quoted(dir / "log.txt") + " --clock sensor --out " +
                          shell_quoted(dir / "out") + " --poses ";
  // One usable pose: almost nothing can be mapped; the bad line is named and the run fails.
  dir.write("bad.txt", "0.1 0 0 0 0 0\n0.2 0 0 zero 0 0\n");
  auto result = run_cli(map + shell_quoted(dir / "bad.txt"));
  EXPECT_EQ(result.exit_code, 1) << result.output;
  EXPECT_NE(result.output.find("warning: 1 bad pose lines skipped:\n  " + dir / "bad.txt" +
                               ":2: field 4 'zero' is not a finite number"),
            std::string::npos)
      << result.output;
  EXPECT_NE(result.output.find("stridemap: error: "), std::string::npos) << result.output;
  EXPECT_NE(result.output.find(" scans mapped of 20: the scans span "), std::string::npos) << result.output;
  // A pose out of time order: skipped, named, the rest mapped. The poses
  // bracket the recorded scans, whose sensor times depend on how long after
  // the emulator's start the recording began (later under a sanitizer).
  const io::ScanLog recorded = io::read_scan_log(dir / "log.txt");
  ASSERT_EQ(recorded.scans.size(), 20u);
  const double first_s =
      std::max(0.0, std::floor(sensor_time_seconds(recorded.scans.front().sensor_time_ms) * 10.0) / 10.0 - 0.1);
  const double last_s = std::ceil(sensor_time_seconds(recorded.scans.back().sensor_time_ms) * 10.0) / 10.0 + 0.1;
  const auto pose_line = [](double t) {
    char line[64];
    std::snprintf(line, sizeof line, "%.1f 0 0 0 0 0\n", t);
    return std::string(line);
  };
  dir.write("backwards.txt", pose_line(first_s) + pose_line(last_s) + pose_line((first_s + last_s) / 2.0));
  result = run_cli(map + shell_quoted(dir / "backwards.txt"));
  EXPECT_EQ(result.exit_code, 0) << result.output;
  EXPECT_NE(result.output.find("backwards.txt:3: pose time "), std::string::npos) << result.output;
  EXPECT_NE(result.output.find(" s is not later than the previous pose's "), std::string::npos) << result.output;

  // A log cut in the middle of a scan: the scans before it are mapped, with a warning.
  std::string log = dir.read("log.txt");
  log.resize(log.size() - 1000);
  dir.write("log.txt", log);
  result = run_cli(map + shell_quoted(dir / "poses.txt"));
  EXPECT_EQ(result.exit_code, 0) << result.output;
  EXPECT_NE(result.output.find("warning: 1 damaged scan-log lines skipped:\n  " + dir / "log.txt" + ":"),
            std::string::npos)
      << result.output;
  EXPECT_NE(result.output.find("truncated"), std::string::npos) << result.output;
  EXPECT_NE(result.output.find("map: 19 scans mapped of 19"), std::string::npos) << result.output;
  EXPECT_NE(dir.read("out/summary.json").find("\"log_damage\""), std::string::npos);
}

TEST(LiveCli, EmulatorOptionsAreChecked) {
  test::TestFolder dir;
  const std::string base = "emulate-urg --link " + shell_quoted(dir / "urg") + " ";
  auto result = run_cli(base + "--scene " + shell_quoted(kScene) + " --fault melt@3");
  EXPECT_EQ(result.exit_code, 2);
  EXPECT_NE(result.output.find("--fault 'melt@3': unknown fault 'melt'"), std::string::npos) << result.output;
  result = run_cli(base + "--scene " + shell_quoted(kScene) + " --fault stall@0:1");
  EXPECT_NE(result.output.find("frame '0' is not a whole number >= 1"), std::string::npos) << result.output;
  result = run_cli(base + "--scene " + shell_quoted(kScene) + " --rate-hz 7");
  EXPECT_NE(result.output.find("--rate-hz 7 does not give a whole number of milliseconds"), std::string::npos)
      << result.output;
  result = run_cli(base + "--scene " + shell_quoted(kScene) + " --motion fly");
  EXPECT_NE(result.output.find("--motion: 'fly' is not available"), std::string::npos) << result.output;
  result = run_cli(base + "--scene " + shell_quoted(kScene) + " --motion walk");
  EXPECT_EQ(result.exit_code, 2);
  EXPECT_NE(result.output.find("the scene has no walk_path section"), std::string::npos) << result.output;
  result = run_cli(base);
  EXPECT_NE(result.output.find("give either --scene"), std::string::npos) << result.output;
  result = run_cli(base + "--replay " + shell_quoted(dir.write("junk.dat", "1 2 3\n")));
  EXPECT_EQ(result.exit_code, 2);
  EXPECT_NE(result.output.find("junk.dat:1: 3 tokens; a BreezySLAM scan line has 707"), std::string::npos)
      << result.output;
}

}  // namespace
}  // namespace stridemap
