// Runs the built `stridemap sensor-report` as a user would: the Ragno
// preset's numbers, Fig. 3's maps on disk, and bad configurations.
#include <gtest/gtest.h>
#include <sys/wait.h>

#include <array>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <random>
#include <string>

#include "cli/cli_runner.hpp"
#include "stridemap/mapfile/grid_csv.hpp"
#include "stridemap/render/png_image.hpp"
#include "test_paths.hpp"

namespace sensor_report_test {
namespace {

namespace fs = std::filesystem;

using stridemap::test::CommandResult;
using stridemap::test::run_cli;
const auto quoted = stridemap::test::shell_quoted;

std::string source_file(const std::string& relative) { return std::string(STRIDEMAP_SOURCE_DIR) + "/" + relative; }

class SensorReportCli : public ::testing::Test {
 protected:
  void SetUp() override {
    const auto stamp = std::chrono::steady_clock::now().time_since_epoch().count();
    std::random_device entropy;
    directory_ = fs::temp_directory_path() /
                 ("stridemap_cli_sensor_report_" + std::to_string(stamp) + "_" + std::to_string(entropy()));
    fs::create_directories(directory_);
  }
  void TearDown() override {
    std::error_code ignored;
    fs::remove_all(directory_, ignored);
  }
  fs::path write(const std::string& name, const std::string& text) {
    const fs::path path = directory_ / name;
    std::ofstream(path) << text;
    return path;
  }
  fs::path directory_;
};

void expect_contains(const CommandResult& result, const std::string& text) {
  EXPECT_NE(result.output.find(text), std::string::npos) << "missing \"" << text << "\" in:\n" << result.output;
}

TEST_F(SensorReportCli, RagnoPresetReport) {
  const CommandResult result =
      run_cli("sensor-report --config " + quoted(source_file("configs/ragno_structured_light.yaml")));
  ASSERT_EQ(result.exit_code, 0) << result.output;
  expect_contains(result, "b = 120.0 mm, beta = 45.00 deg, tau_c = 28.14 deg, gamma_c = 38.80 deg");
  expect_contains(result, "stripe at image row v = 475.2 of 480");
  expect_contains(result, "nearest ground point:  225.4 mm ahead");
  expect_contains(result, "slant range 284.8 mm");
  expect_contains(result, "farthest ground point: 303.2 mm");
  expect_contains(result, "stripe width on the ground: 405.6 mm");
  expect_contains(result, "image rows below v = 160.9 look down at the ground");
}

TEST_F(SensorReportCli, Fig3UncertaintyMaps) {
  const fs::path out = directory_ / "maps";  // created by the command
  const CommandResult result = run_cli("sensor-report --config " +
                                       quoted(source_file("configs/fig3_structured_light.yaml")) +
                                       " --uncertainty-out " + quoted(out.string()) + " --cell-size 0.01");
  ASSERT_EQ(result.exit_code, 0) << result.output;
  expect_contains(result, "crosses the optical axis at z_c = 274.7 mm");
  expect_contains(result, "z_c = 1000 mm: Delta z_c =   7.21 mm");
  expect_contains(result, "No mount section");
  stridemap::io::GridCsvOptions metadata;
  const Eigen::MatrixXf z = stridemap::io::read_grid_csv((out / "z_uncertainty.csv").string(), &metadata);
  EXPECT_EQ(z.rows(), 100);  // 1 m of depth in 1 cm cells
  EXPECT_EQ(metadata.units, "m");
  ASSERT_TRUE(metadata.cell_size_m.has_value());
  EXPECT_DOUBLE_EQ(*metadata.cell_size_m, 0.01);
  // Row 99 is 0.995 m deep: about 7.1 mm on the axis.
  EXPECT_NEAR(z(99, z.cols() / 2), 0.00714, 0.0001);
  EXPECT_TRUE(std::isnan(z(5, z.cols() / 2))) << "5 cm is nearer than the sheet's nearest visible point";
  const Eigen::MatrixXf x = stridemap::io::read_grid_csv((out / "x_uncertainty.csv").string());
  EXPECT_EQ(x.rows(), z.rows());
  for (const char* name : {"x_uncertainty.png", "z_uncertainty.png"}) {
    const stridemap::io::RgbImage image = stridemap::io::read_png((out / name).string());
    EXPECT_GT(image.width, 300) << name;
    EXPECT_GT(image.height, 300) << name;
  }
}

TEST_F(SensorReportCli, BadConfigurationIsAnErrorWithThePlace) {
  const fs::path config = write("bad.yaml",
                                "structured_light:\n  baseline_m: 0.1\n  sheet_angle_deg: 95\n  image_width_px: 640\n"
                                "  image_height_px: 480\n  half_fov_vertical_deg: 20\n  half_fov_horizontal_deg: 25\n");
  const CommandResult result = run_cli("sensor-report --config " + quoted(config.string()));
  EXPECT_EQ(result.exit_code, 2) << result.output;
  expect_contains(result, "stridemap: error: " + config.string() +
                              ":3: structured_light.sheet_angle_deg: must lie strictly between 0 and 90 deg, "
                              "got 95 deg");
}

TEST_F(SensorReportCli, GeometryThatCannotSeeTheGround) {
  std::ifstream preset(source_file("configs/ragno_structured_light.yaml"));
  std::string text((std::istreambuf_iterator<char>(preset)), std::istreambuf_iterator<char>());
  const auto at = text.find("pitch_deg: 10.0");
  ASSERT_NE(at, std::string::npos);
  text.replace(at, 15, "pitch_deg: 0.0");
  const fs::path config = write("untilted.yaml", text);
  const CommandResult result = run_cli("sensor-report --config " + quoted(config.string()));
  EXPECT_EQ(result.exit_code, 2) << result.output;
  expect_contains(result, "stridemap: error: " + config.string() +
                              ": structured light mount: this geometry cannot see the ground: the laser stripe on "
                              "flat ground lies 0.294 m ahead of the camera (z_c) but would be seen at image row");
  expect_contains(result, "below the image (rows 0 to 480)");
}

TEST_F(SensorReportCli, MissingConfigFile) {
  const CommandResult result = run_cli("sensor-report --config " + quoted((directory_ / "none.yaml").string()));
  EXPECT_EQ(result.exit_code, 2) << result.output;
  expect_contains(result, "cannot read structured-light config: No such file or directory");
}

}  // namespace
}  // namespace sensor_report_test
