// The structured-light commands as a user runs them: simulate an image,
// detect its stripe, calibrate from target images, the cart-rail and
// lighting experiments, and bad input.
#include <gtest/gtest.h>

#include <chrono>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <random>
#include <sstream>
#include <string>

#include <nlohmann/json.hpp>

#include "cli/cli_runner.hpp"
#include "stridemap/render/png_image.hpp"
#include "test_paths.hpp"

namespace structured_light_cli_test {
namespace {

namespace fs = std::filesystem;
using stridemap::test::CommandResult;
using stridemap::test::run_cli;
const auto quoted = stridemap::test::shell_quoted;

std::string source_file(const std::string& relative) { return std::string(STRIDEMAP_SOURCE_DIR) + "/" + relative; }
const std::string kRagno = source_file("configs/ragno_structured_light.yaml");

const char* kBenchConfig = R"(structured_light:
  baseline_m: 0.120
  sheet_angle_deg: 45.0
  image_width_px: 640
  image_height_px: 480
  half_fov_vertical_deg: 28.14
  half_fov_horizontal_deg: 38.8
)";

// One box and a 3-frame rail, so that the experiments run in a second.
const char* kShortScene = R"(terrain:
  kind: flat
  extent: {min_x_m: -0.5, min_y_m: -1.0, max_x_m: 2.0, max_y_m: 1.0}
  base_elevation_m: 0.0
  reflectance: 0.5
boxes:
  - name: box
    center_x_m: 0.45
    center_y_m: 0.0
    length_m: 0.1
    width_m: 0.1
    height_m: 0.06
    reflectance: 0.6
cart_rail:
  start_x_m: 0.1
  end_x_m: 0.32
  y_m: 0.0
  step_m: 0.11
)";

class StructuredLightCli : public ::testing::Test {
 protected:
  void SetUp() override {
    const auto stamp = std::chrono::steady_clock::now().time_since_epoch().count();
    std::random_device entropy;
    dir_ = fs::temp_directory_path() / ("stridemap_cli_sl_" + std::to_string(stamp) + "_" + std::to_string(entropy()));
    fs::create_directories(dir_);
  }
  void TearDown() override {
    std::error_code ignored;
    fs::remove_all(dir_, ignored);
  }
  std::string write(const std::string& name, const std::string& text) {
    std::ofstream(dir_ / name) << text;
    return (dir_ / name).string();
  }
  std::string file(const std::string& name) const { return (dir_ / name).string(); }
  fs::path dir_;
};

void expect_contains(const CommandResult& result, const std::string& text) {
  EXPECT_NE(result.output.find(text), std::string::npos) << "missing \"" << text << "\" in:\n" << result.output;
}

int count_lines(const std::string& path) {
  std::ifstream in(path);
  int lines = 0;
  for (std::string line; std::getline(in, line);) lines += !line.empty() && line[0] != '#';
  return lines;
}

TEST_F(StructuredLightCli, SimulatedImageIsDetectedColumnByColumn) {
  const CommandResult sim = run_cli("simulate-stripe-image --config " + quoted(kRagno) + " --scene " +
                                    quoted(source_file("scenes/cart_rail_narrow.yaml")) + " --x 0.3 --out " +
                                    quoted(file("frame.png")) + " --truth " + quoted(file("truth.csv")));
  ASSERT_EQ(sim.exit_code, 0) << sim.output;
  expect_contains(sim, "stripe visible in 640 columns");
  const CommandResult detect = run_cli("detect-stripe " + quoted(file("frame.png")) + " --config " + quoted(kRagno));
  ASSERT_EQ(detect.exit_code, 0) << detect.output;
  expect_contains(detect, "stripe found in 6");  // 6xx of 640
  EXPECT_EQ(count_lines(file("frame.stripe.csv")), 641);  // header + one line per column
  EXPECT_EQ(count_lines(file("truth.csv")), 641);
  const stridemap::io::RgbImage overlay = stridemap::io::read_png(file("frame.overlay.png"));
  EXPECT_EQ(overlay.width, 640);
  EXPECT_EQ(overlay.height, 480);
  // At x = 0.3 m the stripe crosses the large box (0.10 m high): its points
  // lie on the floor or on the box's top within a few mm.
  std::ifstream csv(file("frame.stripe.csv"));
  std::string line;
  int on_floor = 0, on_box = 0;
  while (std::getline(csv, line)) {
    if (line.empty() || line[0] == '#' || line[0] == 'u') continue;
    std::stringstream fields(line);
    std::string field;
    std::vector<std::string> f;
    while (std::getline(fields, field, ',')) f.push_back(field);
    if (f.size() != 10 || f[1] != "1") continue;
    on_floor += std::abs(std::stod(f[9])) < 0.003;
    on_box += std::abs(std::stod(f[9]) - 0.10) < 0.003;
  }
  EXPECT_GT(on_floor, 250);
  EXPECT_GT(on_box, 200);
  EXPECT_GT(on_floor + on_box, 600);
}

TEST_F(StructuredLightCli, DetectStripeRejectsBadInput) {
  const CommandResult missing = run_cli("detect-stripe " + quoted(file("none.png")) + " --config " + quoted(kRagno));
  EXPECT_EQ(missing.exit_code, 2);
  expect_contains(missing, "none.png': the file does not exist");
  const CommandResult empty = run_cli("detect-stripe " + quoted(write("empty.png", "")) + " --config " + quoted(kRagno));
  EXPECT_EQ(empty.exit_code, 2);
  expect_contains(empty, "not a PNG file (only 0 bytes long)");
  stridemap::io::write_png(file("small.png"), stridemap::io::RgbImage(320, 240, 90, 90, 90));
  const CommandResult small = run_cli("detect-stripe " + quoted(file("small.png")) + " --config " + quoted(kRagno));
  EXPECT_EQ(small.exit_code, 2);
  expect_contains(small, "small.png: the image is 320 x 240 pixels, the configuration describes a 640 x 480");
  std::string level = kBenchConfig;
  level += "mount:\n  pitch_deg: 0.0\n  height_m: 0.174\n";
  stridemap::io::write_png(file("blank.png"), stridemap::io::RgbImage(640, 480, 90, 90, 90));
  const CommandResult blind =
      run_cli("detect-stripe " + quoted(file("blank.png")) + " --config " + quoted(write("level.yaml", level)));
  EXPECT_EQ(blind.exit_code, 2);
  expect_contains(blind, "level.yaml: structured light mount: this geometry cannot see the ground");
  const CommandResult none = run_cli("detect-stripe " + quoted(file("blank.png")) + " --config " + quoted(kRagno));
  EXPECT_EQ(none.exit_code, 0) << none.output;
  expect_contains(none, "stripe found in 0 of 640 columns");
}

TEST_F(StructuredLightCli, CalibrationFromSimulatedTargetsRecoversBaselineAndSheetAngle) {
  const std::string config = write("bench.yaml", kBenchConfig);
  std::string targets;
  for (const char* d : {"0.09", "0.12", "0.15", "0.18", "0.21", "0.24"}) {
    const std::string image = file(std::string("target_") + d + ".png");
    const CommandResult sim = run_cli("simulate-stripe-image --config " + quoted(config) + " --wall-distance-m " + d +
                                      " --seed 4 --out " + quoted(image));
    ASSERT_EQ(sim.exit_code, 0) << sim.output;
    targets += " --target " + quoted(std::string(d) + "=" + image);
  }
  const CommandResult fit = run_cli("calibrate-structured-light --config " + quoted(config) + targets + " --json " +
                                    quoted(file("fit.json")));
  ASSERT_EQ(fit.exit_code, 0) << fit.output;
  std::ifstream json_file(file("fit.json"));
  const nlohmann::json result = nlohmann::json::parse(json_file);
  const double b = result["baseline_m"], b_sigma = result["baseline_sigma_m"];
  const double beta = result["sheet_angle_deg"], beta_sigma = result["sheet_angle_sigma_deg"];
  EXPECT_NEAR(b, 0.120, 0.0003);
  EXPECT_NEAR(beta, 45.0, 0.05);
  EXPECT_LT(std::abs(b - 0.120), 4 * b_sigma + 1e-5);
  EXPECT_LT(std::abs(beta - 45.0), 4 * beta_sigma + 1e-3);
  EXPECT_LT(result["rms_residual_px"].get<double>(), 0.2);
  EXPECT_EQ(result["targets"].size(), 6u);

  const CommandResult too_few = run_cli("calibrate-structured-light --config " + quoted(config) + " --target " +
                                        quoted("0.12=" + file("target_0.12.png")) + " --target " +
                                        quoted("0.15=" + file("target_0.15.png")));
  EXPECT_EQ(too_few.exit_code, 2);
  expect_contains(too_few, "at least 3 targets");
  const CommandResult bad_spec = run_cli("calibrate-structured-light --config " + quoted(config) + " --target abc");
  EXPECT_EQ(bad_spec.exit_code, 2);
  expect_contains(bad_spec, "expected DISTANCE_M=IMAGE.png");
  const CommandResult too_far = run_cli("simulate-stripe-image --config " + quoted(config) +
                                        " --wall-distance-m 0.4 --out " + quoted(file("far.png")));
  EXPECT_EQ(too_far.exit_code, 2);
  expect_contains(too_far, "sees it on a target from 78.2 mm to 258.0 mm");
}

TEST_F(StructuredLightCli, CartRailAndLightingExperiments) {
  const std::string scene = write("short.yaml", kShortScene);
  const CommandResult rail = run_cli("experiment cart-rail --sensor structured-light --pipeline geometric --scene " +
                                     quoted(scene) + " --out " + quoted(dir_.string()));
  ASSERT_EQ(rail.exit_code, 0) << rail.output;
  expect_contains(rail, "sensor structured-light-geometric (simulated), 3 scans, 5 mm cells");
  std::ifstream summary_file(dir_ / "cart-rail-structured-light-geometric" / "summary.json");
  const nlohmann::json summary = nlohmann::json::parse(summary_file);
  EXPECT_EQ(summary["structured_light"]["pipeline"], "geometric");
  EXPECT_EQ(summary["map_filter"], "cas");

  const CommandResult mixed = run_cli("experiment cart-rail --sensor structured-light --mixed-pixels on --scene " +
                                      quoted(scene) + " --out " + quoted(dir_.string()));
  EXPECT_EQ(mixed.exit_code, 2);
  expect_contains(mixed, "apply to the URG only");
  const CommandResult pipeline = run_cli("experiment cart-rail --sensor structured-light --pipeline magic --scene " +
                                         quoted(scene) + " --out " + quoted(dir_.string()));
  EXPECT_EQ(pipeline.exit_code, 2);
  expect_contains(pipeline, "--pipeline: 'magic' is not a pipeline");

  const CommandResult lighting = run_cli("experiment lighting --levels 300,30000 --scene " + quoted(scene) +
                                         " --out " + quoted(dir_.string()));
  ASSERT_EQ(lighting.exit_code, 0) << lighting.output;
  expect_contains(lighting, "same at every level by construction");
  for (const char* name : {"lighting.png", "lighting.csv", "summary.json", "image_300lx.png", "image_30000lx_overlay.png"}) {
    EXPECT_TRUE(fs::exists(dir_ / "lighting" / name)) << name;
  }
  EXPECT_EQ(count_lines((dir_ / "lighting" / "lighting.csv").string()), 3);
  const CommandResult no_scene = run_cli("experiment lighting --scene " + quoted(file("nowhere.yaml")) + " --out " +
                                         quoted(dir_.string()));
  EXPECT_EQ(no_scene.exit_code, 2);
  expect_contains(no_scene, "nowhere.yaml: the scene file does not exist");
}

}  // namespace
}  // namespace structured_light_cli_test
