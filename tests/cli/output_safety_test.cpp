// A user's files are sacred (docs/outputs.md, "Overwriting"): no command
// truncates a log or one of its own inputs, the refusal names the option and
// exits 2 before anything is opened for writing, and an interrupted
// experiment leaves the previous results whole with no temporary behind.
#include <gtest/gtest.h>

#include <signal.h>

#include <chrono>
#include <filesystem>
#include <map>
#include <set>
#include <thread>
#include <utility>

#include "cli/background_process.hpp"
#include "cli/cli_runner.hpp"
#include "cli/straight_run_log.hpp"
#include "live/test_folder.hpp"
#include "stridemap/io/output_folder.hpp"
#include "stridemap/recordings/scan_log.hpp"
#include "test_paths.hpp"

namespace stridemap {
namespace output_safety_test {
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

// Every file under `root` (relative path -> content), folders as "<dir>".
std::map<std::string, std::string> tree(const fs::path& root) {
  std::map<std::string, std::string> files;
  for (const auto& entry : fs::recursive_directory_iterator(root)) {
    const std::string name = fs::relative(entry.path(), root).string();
    if (entry.is_directory()) {
      files[name] = "<dir>";
    } else {
      std::ifstream in(entry.path(), std::ios::binary);
      files[name] = {std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
    }
  }
  return files;
}

std::set<std::string> manifest_of(const fs::path& folder) {
  std::ifstream in(folder / io::kOutputManifest);
  std::set<std::string> names;
  for (std::string line; std::getline(in, line);) {
    if (!line.empty() && line[0] != '#') names.insert(line);
  }
  return names;
}

// A 4 m window: the points of this run's 0.8 m beams are in it.
std::string wide_window(const test::TestFolder& dir) {
  return "--config " + q(dir.write("wide.yaml", "map:\n  cells_per_side: 400\n"));
}

// The README's own example: a run's folder, then `export` beside the map,
// then the user's notes and plots. A second run into it must not lose any.
void make_run_folder_with_the_users_files(const test::TestFolder& dir) {
  test::write_straight_run(dir, "run.log", 20, 800, [](double t) { return 0.2 * t; });
  const auto first = test::map_straight_run(dir, "run.log", "exp1", wide_window(dir));
  ASSERT_EQ(first.exit_code, 0) << first.output;
  const auto exported = run_cli("export " + q(dir / "exp1/map.smap") + " --npy " + q(dir / "exp1/npy") + " --ply " +
                                q(dir / "exp1/map.ply"));
  ASSERT_EQ(exported.exit_code, 0) << exported.output;
  dir.write("exp1/NOTES.txt", "what I saw on the 3rd run\n");
  fs::create_directories(dir / "exp1/my_plots");
  dir.write("exp1/my_plots/fig1.pdf", "%PDF-1.4 my figure\n");
}

TEST(OutputSafety, AnOutputFolderHoldingTheUsersFilesIsRefusedAndLeftAsItWas) {
  test::TestFolder dir;
  make_run_folder_with_the_users_files(dir);
  const auto before = tree(dir / "exp1");
  ASSERT_TRUE(before.count("npy") && before.count("map.ply") && before.count("my_plots/fig1.pdf"));
  const auto again = test::map_straight_run(dir, "run.log", "exp1", wide_window(dir));
  EXPECT_EQ(again.exit_code, 2) << again.output;
  // The first foreign entry by name (upper case sorts first).
  EXPECT_NE(again.output.find("stridemap: error: --out: folder '" + dir / "exp1" +
                              "' holds 'NOTES.txt', which stridemap did not write there (it is not in the folder's "
                              ".stridemap-output); pass --overwrite"),
            std::string::npos)
      << again.output;
  EXPECT_EQ(tree(dir / "exp1"), before);
  // Each of the others alone refuses the folder too.
  for (const std::string& name : {"NOTES.txt", "my_plots", "map.ply"}) fs::remove_all(dir / ("exp1/" + name));
  const auto only_npy = test::map_straight_run(dir, "run.log", "exp1", wide_window(dir));
  EXPECT_EQ(only_npy.exit_code, 2) << only_npy.output;
  EXPECT_NE(only_npy.output.find("holds 'npy', which stridemap did not write there"), std::string::npos)
      << only_npy.output;
  // live refuses it before the device is even opened.
  const auto live = run_cli("live --device " + q(dir / "nothing") + " --poses " + q(dir / "poses.txt") + " --out " +
                            q(dir / "exp1") + " --connect-timeout-s 0.2");
  EXPECT_EQ(live.exit_code, 2) << live.output;
  EXPECT_NE(live.output.find("holds 'npy', which stridemap did not write there"), std::string::npos) << live.output;
  EXPECT_TRUE(fs::exists(dir / "exp1/npy/elevation.npy"));
}

TEST(OutputSafety, OverwriteReplacesOnlyTheManifestsFilesAndKeepsTheUsers) {
  test::TestFolder dir;
  make_run_folder_with_the_users_files(dir);
  // A file of the earlier set that this run does not write again: it goes.
  dir.write("exp1/old_layer.csv", "1,2\n");
  std::ofstream(dir / ("exp1/" + std::string(io::kOutputManifest)), std::ios::app) << "old_layer.csv\n";
  const std::set<std::string> set_before = manifest_of(dir / "exp1");
  auto users = tree(dir / "exp1");
  std::erase_if(users, [&](const auto& item) {
    const std::string top = fs::path(item.first).begin()->string();
    return set_before.count(top) != 0 || top == io::kOutputManifest;
  });
  ASSERT_EQ(users.count("NOTES.txt") + users.count("my_plots/fig1.pdf") + users.count("map.ply") +
                users.count("npy/elevation.npy"),
            4u);
  const std::string old_summary = dir.read("exp1/summary.json");
  test::write_straight_run(dir, "other.log", 30, 700, [](double t) { return 0.1 * t; });
  const auto again = test::map_straight_run(dir, "other.log", "exp1", wide_window(dir) + " --overwrite");
  ASSERT_EQ(again.exit_code, 0) << again.output;
  // The user's entries exactly as they were.
  auto after = tree(dir / "exp1");
  for (const auto& [name, content] : users) EXPECT_EQ(after[name], content) << name;
  // The set is the new one, whole, and listed; the old file not written again is gone.
  EXPECT_NE(dir.read("exp1/summary.json"), old_summary);
  EXPECT_NE(dir.read("exp1/summary.json").find("other.log"), std::string::npos);
  EXPECT_FALSE(fs::exists(dir / "exp1/old_layer.csv"));
  const std::set<std::string> set_after = manifest_of(dir / "exp1");
  EXPECT_EQ(set_after.count("old_layer.csv"), 0u);
  for (const char* name : {"summary.json", "map.smap", "elevation.png", "state.csv"}) {
    EXPECT_EQ(set_after.count(name), 1u) << name;
  }
  for (const auto& entry : fs::directory_iterator(dir / "exp1")) {
    const std::string name = entry.path().filename().string();
    EXPECT_TRUE(set_after.count(name) || users.count(name) || name == io::kOutputManifest) << name;
  }
  for (const auto& entry : fs::directory_iterator(dir.path())) {
    EXPECT_EQ(entry.path().filename().string().find(".tmp-"), std::string::npos) << entry.path();
  }
  // Once more without --overwrite: the user's files still refuse the folder.
  const auto third = test::map_straight_run(dir, "other.log", "exp1", wide_window(dir));
  EXPECT_EQ(third.exit_code, 2) << third.output;
}

TEST(OutputSafety, AFolderWithoutAManifestIsTheUsersWhateverItsFilesAreCalled) {
  test::TestFolder dir;
  test::write_straight_run(dir, "run.log", 20, 800, [](double t) { return 0.2 * t; });
  fs::create_directories(dir / "analysis");
  dir.write("analysis/results.csv", "trial,error\n1,0.2\n");
  dir.write("analysis/settings.json", "{\"mine\": true}\n");
  auto r = test::map_straight_run(dir, "run.log", "analysis", wide_window(dir));
  EXPECT_EQ(r.exit_code, 2) << r.output;
  EXPECT_NE(r.output.find("holds 'results.csv', which stridemap did not write there (the folder has no "
                          ".stridemap-output); pass --overwrite"),
            std::string::npos)
      << r.output;
  EXPECT_EQ(dir.read("analysis/results.csv"), "trial,error\n1,0.2\n");
  EXPECT_EQ(dir.read("analysis/settings.json"), "{\"mine\": true}\n");
  r = test::map_straight_run(dir, "run.log", "analysis", wide_window(dir) + " --overwrite");
  ASSERT_EQ(r.exit_code, 0) << r.output;
  EXPECT_EQ(dir.read("analysis/results.csv"), "trial,error\n1,0.2\n");
  EXPECT_EQ(dir.read("analysis/settings.json"), "{\"mine\": true}\n");
  EXPECT_TRUE(fs::exists(dir / "analysis/map.smap"));
  EXPECT_EQ(manifest_of(dir / "analysis").count("results.csv"), 0u);
  // A file of the user's with the name of an output is never replaced, not even with --overwrite.
  fs::create_directories(dir / "mine");
  dir.write("mine/elevation.png", "my own picture\n");
  r = test::map_straight_run(dir, "run.log", "mine", wide_window(dir) + " --overwrite");
  EXPECT_EQ(r.exit_code, 2) << r.output;
  EXPECT_NE(r.output.find("holds 'elevation.png', which stridemap did not write there, and this run writes a file "
                          "of that name; it is kept and nothing was written"),
            std::string::npos)
      << r.output;
  EXPECT_EQ(dir.read("mine/elevation.png"), "my own picture\n");
  EXPECT_FALSE(fs::exists(dir / "mine/map.smap"));
}

TEST(OutputSafety, ExperimentsAndLiveKeepTheUsersFilesInTheirOutputFolders) {
  test::TestFolder dir;
  const std::string run = "experiment cart-rail --scene " + q(kScene) + " --out " + q(dir / "out");
  ASSERT_EQ(run_cli(run).exit_code, 0);
  dir.write("out/cart-rail-urg/NOTES.txt", "mine\n");
  auto r = run_cli(run);
  EXPECT_EQ(r.exit_code, 2) << r.output;
  EXPECT_NE(r.output.find("holds 'NOTES.txt', which stridemap did not write there"), std::string::npos) << r.output;
  r = run_cli(run + " --overwrite --seed 2");
  EXPECT_EQ(r.exit_code, 0) << r.output;
  EXPECT_EQ(dir.read("out/cart-rail-urg/NOTES.txt"), "mine\n");
  EXPECT_TRUE(fs::exists(dir / "out/cart-rail-urg/summary.json"));

  BackgroundProcess emulator(std::string(q(STRIDEMAP_CLI_PATH)) + " emulate-urg --link " + q(dir / "urg") +
                             " --rate-hz 100 --duration-s 60 --scene " + q(kScene) + " --motion cart-rail --poses-out " +
                             q(dir / "poses.txt") + " --poses-clock sensor");
  ASSERT_TRUE(emulator.wait_for_output("emulating a URG-04LX on", 10.0)) << emulator.output();
  fs::create_directories(dir / "live/my_plots");
  dir.write("live/my_plots/fig1.pdf", "%PDF mine\n");
  const std::string live = "live --device " + q(dir / "urg") + " --poses " + q(dir / "poses.txt") +
                           " --clock sensor --out " + q(dir / "live") + " --max-scans 20 --connect-timeout-s 10";
  r = run_cli(live);
  EXPECT_EQ(r.exit_code, 2) << r.output;
  EXPECT_NE(r.output.find("holds 'my_plots', which stridemap did not write there"), std::string::npos) << r.output;
  r = run_cli(live + " --overwrite");
  EXPECT_EQ(r.exit_code, 0) << r.output;
  EXPECT_EQ(dir.read("live/my_plots/fig1.pdf"), "%PDF mine\n");
  EXPECT_TRUE(fs::exists(dir / "live/map.smap"));
  EXPECT_EQ(manifest_of(dir / "live").count("my_plots"), 0u);
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
  // What a run that gets to its commit leaves: a signal between the commit
  // and the exit finds the new set in place, whole.
  const std::string reference_run = "experiment cart-rail --scene " + q(kScene) + " --out " + q(dir / "ref") + " --seed 2";
  ASSERT_EQ(run_cli(reference_run).exit_code, 0);
  const std::string new_summary = dir.read("ref/cart-rail-urg/summary.json");
  const std::string new_elevation = dir.read("ref/cart-rail-urg/elevation.png");
  int interrupted = 0;
  // At different moments: while computing, and (on a slow machine) while writing.
  // An idle machine runs the experiment in about 0.3 s, a loaded one in seconds.
  for (const auto& [sig, delay_ms] : {std::pair{SIGTERM, 40}, std::pair{SIGINT, 120}, std::pair{SIGHUP, 250},
                                      std::pair{SIGTERM, 700}, std::pair{SIGINT, 1000}}) {
    BackgroundProcess second(std::string(q(STRIDEMAP_CLI_PATH)) + " " + run + "2");
    std::this_thread::sleep_for(std::chrono::milliseconds(delay_ms));
    second.signal(sig);
    const int status = second.wait(60.0);
    const bool committed = dir.read("out/cart-rail-urg/summary.json") == new_summary &&
                           dir.read("out/cart-rail-urg/elevation.png") == new_elevation;
    if (status == 0 || committed) {
      // Committed before the signal: its results are now the previous ones
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

// The commands that write one file (or a pair) of the user's naming: an
// existing file is refused before any work, naming the option, and kept
// byte for byte; --overwrite replaces it.
TEST(OutputSafety, AnExistingFileIsRefusedByEveryCommandThatWritesSingleFiles) {
  test::TestFolder dir;
  const std::string mine = "the user's own file\n";
  const std::string narrow = std::string(STRIDEMAP_SOURCE_DIR) + "/scenes/cart_rail_narrow.yaml";
  const std::string simulate =
      "simulate-stripe-image --config " + q(kSlConfig) + " --scene " + q(narrow) + " --x 0.3 --out ";
  const std::string image = dir.write("frame.png", mine);
  const auto simulated = run_cli(simulate + q(image));
  EXPECT_EQ(simulated.exit_code, 2) << simulated.output;
  EXPECT_NE(simulated.output.find("--out: '" + image + "' already exists"), std::string::npos) << simulated.output;
  EXPECT_EQ(dir.read("frame.png"), mine);
  const std::string truth = dir.write("truth.csv", mine);
  const auto with_truth = run_cli(simulate + q(dir / "new.png") + " --truth " + q(truth));
  EXPECT_EQ(with_truth.exit_code, 2) << with_truth.output;
  EXPECT_FALSE(fs::exists(dir / "new.png"));
  ASSERT_EQ(run_cli(simulate + q(image) + " --overwrite").exit_code, 0);
  EXPECT_NE(dir.read("frame.png"), mine);

  const std::string stripe_csv = dir.write("frame.stripe.csv", mine);
  const auto detected = run_cli("detect-stripe " + q(image) + " --config " + q(kSlConfig));
  EXPECT_EQ(detected.exit_code, 2) << detected.output;
  EXPECT_NE(detected.output.find("'" + stripe_csv + "' already exists"), std::string::npos) << detected.output;
  EXPECT_EQ(dir.read("frame.stripe.csv"), mine);
  EXPECT_FALSE(fs::exists(dir / "frame.overlay.png"));
  EXPECT_EQ(run_cli("detect-stripe " + q(image) + " --config " + q(kSlConfig) + " --overwrite").exit_code, 0);
  EXPECT_NE(dir.read("frame.stripe.csv"), mine);

  const std::string pairs = std::string(STRIDEMAP_SOURCE_DIR) + "/configs/urg_calibration_example.csv";
  const std::string json = dir.write("fit.json", mine);
  const auto calibrated = run_cli("calibrate-range --csv " + q(pairs) + " --json " + q(json));
  EXPECT_EQ(calibrated.exit_code, 2) << calibrated.output;
  EXPECT_NE(calibrated.output.find("--json: '" + json + "' already exists"), std::string::npos) << calibrated.output;
  EXPECT_EQ(dir.read("fit.json"), mine);
  EXPECT_EQ(run_cli("calibrate-range --csv " + q(pairs) + " --json /dev/null").exit_code, 0);
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
}  // namespace output_safety_test
}  // namespace stridemap
