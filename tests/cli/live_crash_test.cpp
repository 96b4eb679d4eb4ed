// Crash consistency (docs/reliability.md): `live`, mapping from the emulator
// with --record and saving every 100 ms, is killed with SIGKILL at 50 random
// (seeded) moments (12 under a sanitizer), 0.05 to 0.6 s after it connected
// (stretched as far as this build's tool is slower). After each kill the output folder holds a complete set
// (its manifest lists exactly its files, each one readable) or does not
// exist yet, the leftovers of earlier kills are gone, and the recorded log
// replays (`stridemap map --log`) to the map of every scan in it.
#include <gtest/gtest.h>

#include <signal.h>

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <random>
#include <set>
#include <sstream>
#include <string>
#include <thread>

#include <nlohmann/json.hpp>

#include "cli/background_process.hpp"
#include "cli/cli_runner.hpp"
#include "live/test_folder.hpp"
#include "stridemap/core/error.hpp"
#include "stridemap/io/output_folder.hpp"
#include "stridemap/mapfile/grid_csv.hpp"
#include "stridemap/recordings/scan_log.hpp"
#include "stridemap/render/png_image.hpp"
#include "test_paths.hpp"

namespace stridemap {
namespace live_crash_test {
namespace {

namespace fs = std::filesystem;
using test::BackgroundProcess;
using test::run_cli;
using test::shell_quoted;

const std::string kScene = std::string(STRIDEMAP_SOURCE_DIR) + "/scenes/cart_rail_boxes.yaml";

std::string cli() { return shell_quoted(STRIDEMAP_CLI_PATH); }

// Every file of the set is listed in its manifest and reads back whole;
// nothing else is in the folder.
void expect_complete_set(const fs::path& out, int kill) {
  if (!fs::exists(out)) return;  // killed before the first save
  std::ifstream manifest(out / io::kOutputManifest);
  ASSERT_TRUE(manifest.good()) << "kill " << kill << ": an output folder without its manifest";
  std::set<std::string> listed{io::kOutputManifest};
  for (std::string line; std::getline(manifest, line);) {
    if (!line.empty() && line[0] != '#') listed.insert(line);
  }
  std::set<std::string> present;
  for (const auto& entry : fs::directory_iterator(out)) present.insert(entry.path().filename().string());
  EXPECT_EQ(present, listed) << "kill " << kill;
  for (const std::string& name : listed) {
    const std::string path = (out / name).string();
    try {
      if (name.ends_with(".png")) io::read_png(path);
      if (name.ends_with(".csv")) io::read_grid_csv(path);
      if (name.ends_with(".json")) {
        std::ifstream in(path);
        const nlohmann::json summary = nlohmann::json::parse(in);
        EXPECT_TRUE(summary.contains("scans")) << "kill " << kill << ": " << name;
      }
    } catch (const std::exception& e) {
      ADD_FAILURE() << "kill " << kill << ": torn output " << name << ": " << e.what();
    }
  }
}

std::size_t leftovers(const fs::path& folder) {
  std::size_t n = 0;
  for (const auto& entry : fs::directory_iterator(folder)) {
    const std::string name = entry.path().filename().string();
    n += name.starts_with(".out.tmp-") || name.find(".tmp-") != std::string::npos;
  }
  return n;
}

// The tool under test is built like this test: under a sanitizer it runs
// several times slower (how much depends on which layers are instrumented
// and on the machine's load), and kills within the Release build's window
// would all land before the first save, testing nothing. The window is
// stretched by the first run's time against a Release run's; kSlowdown
// bounds that stretch and sizes the emulator's lifetime.
constexpr double kReleaseFirstRunS = 0.5;
#if defined(__SANITIZE_THREAD__)
constexpr double kSlowdown = 10.0;
#elif defined(__SANITIZE_ADDRESS__)
constexpr double kSlowdown = 4.0;
#elif defined(__has_feature)
#if __has_feature(thread_sanitizer)
constexpr double kSlowdown = 10.0;
#elif __has_feature(address_sanitizer)
constexpr double kSlowdown = 4.0;
#else
constexpr double kSlowdown = 1.0;
#endif
#else
constexpr double kSlowdown = 1.0;
#endif

// Fifty kills in the Release build, which is where crash consistency is
// judged. Under a sanitizer each kill costs ten times as much; a dozen still
// drives every path (saving, recording, replay) that the sanitizer watches.
constexpr int kKills = kSlowdown > 1.0 ? 12 : 50;

TEST(LiveCrash, KilledAtFiftyRandomMomentsLeavesCompleteOutputsAndLogsThatReplay) {
  test::TestFolder dir;
  BackgroundProcess emulator(cli() + " emulate-urg --link " + shell_quoted(dir / "urg") +
                             " --rate-hz 100 --duration-s " + std::to_string(static_cast<int>(300 * kSlowdown)) + " --scene " + shell_quoted(kScene) +
                             " --motion cart-rail --poses-out " + shell_quoted(dir / "poses.txt") +
                             " --poses-clock host");
  ASSERT_TRUE(emulator.wait_for_output("emulating a URG-04LX on", 10.0)) << emulator.output();
  const fs::path out = dir.path() / "out";
  const std::string live_command = cli() + " live --device " + shell_quoted(dir / "urg") + " --poses " +
                                   shell_quoted(dir / "poses.txt") + " --out " + shell_quoted(out.string());
  // A first set, so that every kill may hit its replacement.
  const auto first_start = std::chrono::steady_clock::now();
  const auto first = run_cli(live_command.substr(cli().size() + 1) + " --max-scans 5 --connect-timeout-s 10");
  ASSERT_EQ(first.exit_code, 0) << first.output;
  const double first_run_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - first_start).count();
  const double stretch = std::clamp(first_run_s / kReleaseFirstRunS, 1.0, kSlowdown);
  std::printf("[ crash    ] first run %.2f s: kill window stretched %.1fx\n", first_run_s, stretch);
  std::mt19937 random(20261201);
  std::uniform_real_distribution<double> moment_s(0.05 * stretch, 0.6 * stretch);
  std::string previous_summary = dir.read("out/summary.json");
  std::size_t sets_replaced = 0, scans_replayed = 0;
  for (int kill = 1; kill <= kKills; ++kill) {
    const std::string log = dir / ("log" + std::to_string(kill) + ".txt");
    BackgroundProcess live(live_command + " --record " + shell_quoted(log) +
                           " --save-every-s 0.1 --stall-timeout-s 5 --status-every-s 10 --connect-timeout-s 10");
    ASSERT_TRUE(live.wait_for_output("connected", 15.0)) << live.output();
    std::this_thread::sleep_for(std::chrono::duration<double>(moment_s(random)));
    live.signal(SIGKILL);
    EXPECT_EQ(live.wait(10.0), -1) << "kill " << kill << ": not killed by the signal";
    expect_complete_set(out, kill);
    const std::string summary = dir.read("out/summary.json");
    sets_replaced += summary != previous_summary;
    previous_summary = summary;
    // Only the run just killed may have left a staging folder or temporary
    // file; the next run removes it.
    EXPECT_LE(leftovers(dir.path()), 1u) << "kill " << kill;

    if (!fs::exists(log)) continue;  // killed between connecting and creating the log
    io::ScanLog recorded;
    try {
      recorded = io::read_scan_log(log);
    } catch (const InputError& e) {
      // Killed before the sensor's parameters were written: nothing to replay.
      EXPECT_LT(fs::file_size(log), 2000u) << "kill " << kill << ": " << e.what();
      continue;
    }
    EXPECT_LE(recorded.skipped_line_numbers.size(), 1u) << "kill " << kill << ": more than the torn last line";
    EXPECT_TRUE(recorded.stop.empty()) << recorded.stop;
    if (recorded.scans.empty()) continue;
    const std::string replay_out = dir / ("replay" + std::to_string(kill));
    const auto replay = run_cli("map --log " + shell_quoted(log) + " --poses " + shell_quoted(dir / "poses.txt") +
                                " --out " + shell_quoted(replay_out));
    ASSERT_EQ(replay.exit_code, 0) << "kill " << kill << ":\n" << replay.output;
    const std::string all = std::to_string(recorded.scans.size());
    EXPECT_NE(replay.output.find("map: " + all + " scans mapped of " + all + " "), std::string::npos)
        << "kill " << kill << ":\n" << replay.output;
    expect_complete_set(replay_out, kill);
    scans_replayed += recorded.scans.size();
    fs::remove_all(replay_out);
  }
  std::printf("[ crash    ] %d kills: %zu left a set of their own, %zu scans replayed\n", kKills, sets_replaced, scans_replayed);
  // The killed runs did replace the set now and then (the rest were killed before or while saving).
  EXPECT_GT(sets_replaced, 0u) << "no killed run ever saved: the kills tested nothing but the first set";
  EXPECT_GT(scans_replayed, static_cast<std::size_t>(kKills));
  // A last clean run cleans the leftovers of the last kill.
  const auto last = run_cli("live --device " + shell_quoted(dir / "urg") + " --poses " + shell_quoted(dir / "poses.txt") +
                            " --out " + shell_quoted(out.string()) + " --max-scans 5 --connect-timeout-s 10");
  EXPECT_EQ(last.exit_code, 0) << last.output;
  EXPECT_EQ(leftovers(dir.path()), 0u);
  expect_complete_set(out, 51);
}

}  // namespace
}  // namespace live_crash_test
}  // namespace stridemap
