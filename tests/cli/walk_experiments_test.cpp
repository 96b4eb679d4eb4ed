// Runs the built `stridemap experiment rocky-walk` and `mount-analysis` as a
// user would.
#include <filesystem>
#include <fstream>
#include <iterator>
#include <string>

#include <unistd.h>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "cli/cli_runner.hpp"
#include "test_paths.hpp"

namespace walk_experiments_test {
namespace {

namespace fs = std::filesystem;
using stridemap::test::CommandResult;
using stridemap::test::run_cli;
using stridemap::test::shell_quoted;

fs::path fresh_dir(const std::string& name) {
  const fs::path dir = fs::temp_directory_path() / ("stridemap_cli_" + name + "_" + std::to_string(::getpid()));
  fs::remove_all(dir);
  fs::create_directories(dir);
  return dir;
}

const std::string kScene = std::string(STRIDEMAP_SOURCE_DIR) + "/scenes/rocky_mockup.yaml";

std::string text_of(const fs::path& path) {
  std::ifstream in(path);
  return std::string((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
}

TEST(RockyWalkCommand, WritesMapsViewsSummaryAndTable) {
  const fs::path out = fresh_dir("rocky_walk");
  const CommandResult r =
      run_cli("experiment rocky-walk --sensor urg --scene " + shell_quoted(kScene) + " --out " + shell_quoted(out.string()) +
              " --sweep 0,2 --seed 2 --calibrate-range on");
  ASSERT_EQ(r.exit_code, 0) << r.output;
  EXPECT_NE(r.output.find("whole walk: RMS error"), std::string::npos) << r.output;
  EXPECT_NE(r.output.find("unknown cells behind obstacles"), std::string::npos) << r.output;
  const fs::path dir = out / "rocky-walk-urg";
  for (const char* file : {"elevation.png", "certainty.png", "error.png", "truth.png", "local_elevation.png",
                           "local_certainty.png", "local_error.png", "view3d.png", "truth_view3d.png", "elevation.csv",
                           "swept_area.csv", "map.smap", "summary.json", "table.txt"}) {
    EXPECT_TRUE(fs::exists(dir / file)) << file;
  }
  EXPECT_NE(r.output.find(text_of(dir / "table.txt")), std::string::npos) << "table.txt is the table printed";
  std::ifstream in(dir / "summary.json");
  const nlohmann::json summary = nlohmann::json::parse(in);
  EXPECT_EQ(summary["experiment"], "rocky-walk");
  EXPECT_EQ(summary.value("tool_version", "").rfind("stridemap ", 0), 0u) << "the version that made it";
  EXPECT_EQ(summary["seed"], 2);
  EXPECT_EQ(summary["coupling"], false);  // mixed pixels off: the ideal single ray
  EXPECT_EQ(summary["pose_error_sweep"].size(), 8u);  // 2 levels x 4 h_ref sources
  EXPECT_GT(summary["walk"]["scans"].get<int>(), 400);
  // With --calibrate-range on the URG's range is calibrated on a wall
  // first: the correction undoes the simulator's systematic error.
  ASSERT_TRUE(summary.contains("range_calibration")) << summary.dump(2);
  EXPECT_EQ(summary["range_calibration"]["coefficients"].size(), 4u);
  EXPECT_NE(r.output.find("range calibration on a wall: correction"), std::string::npos) << r.output;
  EXPECT_GT(summary["range_calibration"]["coefficients"][0].get<double>(), -0.008);
  EXPECT_LT(summary["range_calibration"]["coefficients"][0].get<double>(), -0.004);  // the simulator's c0 is +6 mm
  const CommandResult info = run_cli("map-info " + shell_quoted((dir / "map.smap").string()));
  EXPECT_EQ(info.exit_code, 0) << info.output;
  EXPECT_NE(info.output.find("experiment rocky-walk --sensor urg"), std::string::npos) << info.output;
  fs::remove_all(out);
}

TEST(RockyWalkCommand, EachPoseErrorCanBeSetAlone) {
  const fs::path out = fresh_dir("rocky_walk_errors");
  const CommandResult r = run_cli("experiment rocky-walk --scene " + shell_quoted(kScene) + " --out " +
                                  shell_quoted(out.string()) +
                                  " --sweep none --imu-pitch-noise-deg 0.1 --imu-roll-noise-deg 0 "
                                  "--camera-position-noise-m 0.001 --camera-yaw-noise-deg 0.5 --leg-height-noise-m 0 "
                                  "--pose-error-scale 2");
  ASSERT_EQ(r.exit_code, 0) << r.output;
  std::ifstream in(out / "rocky-walk-urg" / "summary.json");
  const nlohmann::json e = nlohmann::json::parse(in)["pose_error_options"];
  // Set first, then scaled with every other error by --pose-error-scale.
  EXPECT_NEAR(e["imu_pitch_noise_sigma_deg"].get<double>(), 0.2, 1e-12);
  EXPECT_EQ(e["imu_roll_noise_sigma_deg"].get<double>(), 0.0);
  EXPECT_NEAR(e["camera_position_noise_sigma_m"].get<double>(), 0.002, 1e-15);
  EXPECT_NEAR(e["camera_yaw_noise_sigma_deg"].get<double>(), 1.0, 1e-12);
  EXPECT_EQ(e["leg_height_noise_sigma_m"].get<double>(), 0.0);
  EXPECT_NEAR(e["imu_pitch_bias_deg"].get<double>(), -0.6, 1e-12);  // the default, scaled
  fs::remove_all(out);
}

TEST(RockyWalkCommand, StructuredLightVariantUsesFineCellsAndCas) {
  const fs::path out = fresh_dir("rocky_walk_sl");
  const CommandResult r = run_cli("experiment rocky-walk --sensor structured-light --scene " + shell_quoted(kScene) +
                                  " --out " + shell_quoted(out.string()) + " --sweep none");
  ASSERT_EQ(r.exit_code, 0) << r.output;
  EXPECT_NE(r.output.find("5 mm cells"), std::string::npos) << r.output;
  std::ifstream in(out / "rocky-walk-structured-light" / "summary.json");
  const nlohmann::json summary = nlohmann::json::parse(in);
  EXPECT_EQ(summary["sensor"], "structured-light");
  EXPECT_FALSE(summary.contains("coupling"));  // a URG matter
  EXPECT_EQ(summary["cells_per_side"], 200);
  // Its own defaults: h_ref from the footholds carried by leg odometry,
  // after the wide-stance calibration; the error by cause in the summary,
  // per scan beside it, and in the printed table.
  EXPECT_EQ(summary["pose_error_options"]["reference"], "map-footholds");
  EXPECT_TRUE(summary.contains("attitude_calibration"));
  const nlohmann::json& h = summary["h_ref_error"];
  EXPECT_NEAR(h["mean_from_odometry_m"].get<double>() + h["mean_from_map_m"].get<double>() +
                  h["mean_from_placement_m"].get<double>() + h["mean_from_kinematics_m"].get<double>(),
              h["mean_error_m"].get<double>(), 1e-9);
  EXPECT_EQ(h["scans"], summary["walk"]["scans"]);
  EXPECT_TRUE(fs::exists(out / "rocky-walk-structured-light" / "h_ref_error.csv"));
  EXPECT_NE(r.output.find("sensor height's mean error by cause: odometry"), std::string::npos) << r.output;
  const CommandResult bad = run_cli("experiment rocky-walk --sensor structured-light --mixed-pixels on --out " +
                                    shell_quoted(out.string()));
  EXPECT_EQ(bad.exit_code, 2) << bad.output;
  EXPECT_NE(bad.output.find("apply to the URG only"), std::string::npos) << bad.output;
  const CommandResult coupling = run_cli("experiment rocky-walk --sensor urg --mixed-pixels on --coupling maybe --out " +
                                         shell_quoted(out.string()));
  EXPECT_EQ(coupling.exit_code, 2) << coupling.output;
  EXPECT_NE(coupling.output.find("--coupling"), std::string::npos) << coupling.output;
  const CommandResult range = run_cli("experiment rocky-walk --sensor structured-light --calibrate-range on --out " +
                                      shell_quoted(out.string()));
  EXPECT_EQ(range.exit_code, 2) << range.output;
  EXPECT_NE(range.output.find("--calibrate-range applies to the URG only"), std::string::npos) << range.output;
  EXPECT_FALSE(summary.contains("range_calibration"));
  fs::remove_all(out);
}

TEST(RockyWalkCommand, BadInputIsAClearErrorBeforeAnyWork) {
  const fs::path dir = fresh_dir("rocky_bad");
  const std::string out = " --out " + shell_quoted((dir / "out").string());
  CommandResult r = run_cli("experiment rocky-walk --sweep 1,-2" + out);
  EXPECT_EQ(r.exit_code, 2) << r.output;
  EXPECT_NE(r.output.find("--sweep"), std::string::npos) << r.output;
  r = run_cli("experiment rocky-walk --pose-error-scale -1" + out);
  EXPECT_EQ(r.exit_code, 2) << r.output;
  r = run_cli("experiment rocky-walk --camera-position-noise-m -0.001" + out);
  EXPECT_EQ(r.exit_code, 2) << r.output;
  EXPECT_NE(r.output.find("--camera-position-noise-m"), std::string::npos) << r.output;
  r = run_cli("experiment rocky-walk --leg-height-noise-m nan" + out);
  EXPECT_EQ(r.exit_code, 2) << r.output;
  EXPECT_NE(r.output.find("--leg-height-noise-m"), std::string::npos) << r.output;
  r = run_cli("experiment rocky-walk --imu-pitch-noise-deg 91" + out);
  EXPECT_EQ(r.exit_code, 2) << r.output;
  EXPECT_NE(r.output.find("--imu-pitch-noise-deg"), std::string::npos) << r.output;
  r = run_cli("experiment rocky-walk --calibrate-range maybe" + out);
  EXPECT_EQ(r.exit_code, 2) << r.output;
  EXPECT_NE(r.output.find("--calibrate-range"), std::string::npos) << r.output;
  r = run_cli("experiment rocky-walk --foothold-odometry maybe" + out);
  EXPECT_EQ(r.exit_code, 2) << r.output;
  EXPECT_NE(r.output.find("--foothold-odometry"), std::string::npos) << r.output;
  r = run_cli("experiment rocky-walk --sensor lidar" + out);
  EXPECT_EQ(r.exit_code, 2) << r.output;
  EXPECT_NE(r.output.find("--sensor: 'lidar' is not a sensor; expected one of: urg, structured-light"), std::string::npos)
      << r.output;
  r = run_cli("experiment rocky-walk --reference feet" + out);
  EXPECT_EQ(r.exit_code, 2) << r.output;
  EXPECT_NE(r.output.find("--reference: 'feet' is not a reference elevation source; expected one of: map, map-mean, "
                          "truth, map-fused"),
            std::string::npos)
      << r.output;

  const fs::path path = dir / "path.yaml";
  std::ofstream(path) << "walk_path:\n  start: {x_m: 0.3, y_m: 0.0}\n  segments:\n    - straight_m: 1.0\n"
                         "    - straight_m: 5.0\n";
  r = run_cli("experiment rocky-walk --scene " + shell_quoted(kScene) + " --path " + shell_quoted(path.string()) + out);
  EXPECT_EQ(r.exit_code, 2) << r.output;
  EXPECT_NE(r.output.find("path.yaml:5: walk_path.segments[1]: the path leaves the scene's terrain extent"),
            std::string::npos)
      << r.output;
  EXPECT_FALSE(fs::exists(dir / "out"));  // nothing was written
  fs::remove_all(dir);
}

TEST(MountAnalysisCommand, WritesHeatMapsAndNamesTheBestMount) {
  const fs::path out = fresh_dir("mount_analysis");
  const CommandResult r = run_cli("experiment mount-analysis --sensor urg --out " + shell_quoted(out.string()) +
                                  " --fields 1 --heights-cm 20:30:10 --pitches-deg 30,40");
  ASSERT_EQ(r.exit_code, 0) << r.output;
  for (const char* name : {"fig7a", "fig7b", "fig7c", "best of the sweep"}) {
    EXPECT_NE(r.output.find(name), std::string::npos) << name << "\n" << r.output;
  }
  const fs::path dir = out / "mount-analysis-urg";
  for (const char* file : {"unobserved.png", "uncertainty.png", "stripe_width.png", "look_ahead.png",
                           "range_share.png", "score.png", "mounts.csv", "summary.json", "table.txt"}) {
    EXPECT_TRUE(fs::exists(dir / file)) << file;
  }
  EXPECT_NE(r.output.find(text_of(dir / "table.txt")), std::string::npos) << "table.txt is the table printed";
  std::ifstream in(dir / "summary.json");
  const nlohmann::json summary = nlohmann::json::parse(in);
  EXPECT_EQ(summary["sweep"].size(), 4u);
  EXPECT_EQ(summary["named"].size(), 3u);
  EXPECT_TRUE(summary["best"].contains("score"));
  fs::remove_all(out);
}

TEST(MountAnalysisCommand, AnEmptySweepGridIsAClearError) {
  const fs::path dir = fresh_dir("mount_bad");
  CommandResult r = run_cli("experiment mount-analysis --out " + shell_quoted(dir.string()) + " --heights-cm 30:20:2");
  EXPECT_EQ(r.exit_code, 2) << r.output;
  EXPECT_NE(r.output.find("the sweep grid is empty"), std::string::npos) << r.output;
  r = run_cli("experiment mount-analysis --out " + shell_quoted(dir.string()) + " --pitches-deg 10:x:5");
  EXPECT_EQ(r.exit_code, 2) << r.output;
  r = run_cli("experiment mount-analysis --out " + shell_quoted(dir.string()) + " --pitches-deg 10:20:0");
  EXPECT_EQ(r.exit_code, 2) << r.output;
  EXPECT_NE(r.output.find("step must be positive"), std::string::npos) << r.output;
  fs::remove_all(dir);
}

}  // namespace
}  // namespace walk_experiments_test
