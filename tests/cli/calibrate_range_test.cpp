// Runs the built `stridemap calibrate-range` as a user would and checks its
// exit code and output.
#include <gtest/gtest.h>

#include "cli/cli_runner.hpp"
#include "test_paths.hpp"

#include <array>
#include <chrono>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <random>
#include <regex>
#include <sstream>
#include <string>

namespace {

namespace fs = std::filesystem;

using stridemap::test::CommandResult;
using stridemap::test::run_cli;
const auto quoted = stridemap::test::shell_quoted;

class CalibrateRangeCli : public ::testing::Test {
 protected:
  void SetUp() override {
    const auto stamp = std::chrono::steady_clock::now().time_since_epoch().count();
    std::random_device entropy;
    directory_ = fs::temp_directory_path() / ("stridemap_cli_calibrate_" + std::to_string(stamp) +
                                              "_" + std::to_string(entropy()));
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

// Noise-free pairs of a known cubic, so that the printed coefficients are exact.
constexpr std::array<double, 4> known = {0.012, -0.045, 0.06, -0.03};

std::string known_cubic_csv() {
  std::ostringstream csv;
  csv.precision(17);
  csv << "# noise-free\nmeasured_m,true_m\n";
  for (int i = 0; i < 12; ++i) {
    const double r = 0.05 + 0.08 * i;
    csv << r << "," << r + known[0] + known[1] * r + known[2] * r * r + known[3] * r * r * r
        << "\n";
  }
  return csv.str();
}

TEST_F(CalibrateRangeCli, PrintsCoefficientsResidualsAndYaml) {
  const fs::path csv = write("pairs.csv", known_cubic_csv());
  const fs::path json_path = directory_ / "fit.json";
  const CommandResult result = run_cli("calibrate-range --csv " + quoted(csv.string()) +
                                       " --json " + quoted(json_path.string()));
  ASSERT_EQ(result.exit_code, 0) << result.output;
  for (const char* expected : {"c0 =", "[m]", "c1 =", "[-]", "c2 =", "[1/m]", "c3 =", "[1/m^2]",
                               "residual [mm]", "rms residual", "max |residual|"}) {
    EXPECT_NE(result.output.find(expected), std::string::npos) << expected << "\n" << result.output;
  }

  const std::regex yaml_line(
      R"(range_calibration: \{coefficients: \[([^,\]]+), ([^,\]]+), ([^,\]]+), ([^,\]]+)\]\})");
  std::smatch match;
  ASSERT_TRUE(std::regex_search(result.output, match, yaml_line)) << result.output;
  for (std::size_t k = 0; k < 4; ++k) {
    EXPECT_NEAR(std::stod(match[k + 1].str()), known[k], 1e-8) << k;
  }
  // One table row per pair: the source line number starts each row.
  EXPECT_NE(result.output.find("\n     3 "), std::string::npos) << result.output;
  EXPECT_NE(result.output.find("\n    14 "), std::string::npos) << result.output;

  std::ifstream json_file(json_path);
  ASSERT_TRUE(json_file) << "no JSON written to " << json_path;
  const nlohmann::json document = nlohmann::json::parse(json_file);
  ASSERT_EQ(document.at("coefficients").size(), 4u);
  for (std::size_t k = 0; k < 4; ++k) {
    EXPECT_NEAR(document.at("coefficients")[k].get<double>(), known[k], 1e-9) << k;
  }
  EXPECT_EQ(document.at("pairs").size(), 12u);
  EXPECT_LT(document.at("rms_residual_m").get<double>(), 1e-9);
  EXPECT_LT(document.at("max_abs_residual_m").get<double>(), 1e-9);
  EXPECT_EQ(document.at("pairs")[0].at("line").get<int>(), 3);
}

TEST_F(CalibrateRangeCli, ShippedExampleFitsWithinTheNoise) {
  const fs::path csv = fs::path(STRIDEMAP_SOURCE_DIR) / "configs" / "urg_calibration_example.csv";
  const fs::path json_path = directory_ / "example.json";
  const CommandResult result = run_cli("calibrate-range --csv " + quoted(csv.string()) +
                                       " --json " + quoted(json_path.string()));
  ASSERT_EQ(result.exit_code, 0) << result.output;
  const nlohmann::json document = nlohmann::json::parse(std::ifstream(json_path));
  // Generated with 2 mm noise (docs/urg04lx.md).
  EXPECT_GT(document.at("rms_residual_m").get<double>(), 0.001);
  EXPECT_LT(document.at("rms_residual_m").get<double>(), 0.003);
}

TEST_F(CalibrateRangeCli, BadCsvExitsWithCode2AndNamesTheLine) {
  const fs::path csv = write("bad.csv", "measured_mm,true_mm\n100,101\n200,two hundred\n");
  const CommandResult result = run_cli("calibrate-range --csv " + quoted(csv.string()));
  EXPECT_EQ(result.exit_code, 2) << result.output;
  EXPECT_NE(result.output.find("stridemap: error:"), std::string::npos) << result.output;
  EXPECT_NE(result.output.find(csv.string() + ":3:"), std::string::npos) << result.output;
  EXPECT_NE(result.output.find("'two hundred' is not a number"), std::string::npos)
      << result.output;
}

TEST_F(CalibrateRangeCli, MissingCsvExitsWithCode2) {
  const fs::path csv = directory_ / "nowhere.csv";
  const CommandResult result = run_cli("calibrate-range --csv " + quoted(csv.string()));
  EXPECT_EQ(result.exit_code, 2) << result.output;
  EXPECT_NE(result.output.find(csv.string()), std::string::npos) << result.output;
}

TEST_F(CalibrateRangeCli, DegenerateDataExitsWithCode2) {
  const fs::path csv = write("same.csv", "measured_m,true_m\n0.5,0.51\n0.5,0.52\n0.5,0.50\n0.6,0.6\n");
  const CommandResult result = run_cli("calibrate-range --csv " + quoted(csv.string()));
  EXPECT_EQ(result.exit_code, 2) << result.output;
  EXPECT_NE(result.output.find("distinct measured ranges"), std::string::npos) << result.output;
}

TEST_F(CalibrateRangeCli, MissingOptionIsAUsageError) {
  const CommandResult result = run_cli("calibrate-range");
  EXPECT_NE(result.exit_code, 0) << result.output;
  EXPECT_NE(result.output.find("--csv"), std::string::npos) << result.output;
}

}  // namespace
