#include "stridemap/config/calibration_csv.hpp"

#include <gtest/gtest.h>

#include <chrono>
#include <filesystem>
#include <fstream>
#include <random>
#include <sstream>
#include <string>

#include "stridemap/core/error.hpp"
#include "test_paths.hpp"

namespace stridemap {
namespace {

namespace fs = std::filesystem;

class CalibrationCsv : public ::testing::Test {
 protected:
  void SetUp() override {
    const auto stamp = std::chrono::steady_clock::now().time_since_epoch().count();
    std::random_device entropy;
    directory_ = fs::temp_directory_path() /
                 ("stridemap_calibration_csv_" + std::to_string(stamp) + "_" +
                  std::to_string(entropy()));
    fs::create_directories(directory_);
  }
  void TearDown() override {
    std::error_code ignored;
    fs::remove_all(directory_, ignored);
  }

  fs::path write(const std::string& name, const std::string& text) {
    const fs::path path = directory_ / name;
    std::ofstream(path, std::ios::binary) << text;
    return path;
  }

  // Reads a bad file and checks that the message names the file and the line.
  std::string error_for(const std::string& text, int line) {
    const fs::path path = write("bad.csv", text);
    try {
      read_range_pairs_csv(path);
    } catch (const InputError& e) {
      const std::string message = e.what();
      EXPECT_NE(message.find(path.string() + ":" + std::to_string(line) + ":"),
                std::string::npos)
          << message;
      return message;
    }
    ADD_FAILURE() << "expected an InputError for:\n" << text;
    return {};
  }

  fs::path directory_;
};

TEST_F(CalibrationCsv, ReadsMetres) {
  const fs::path path = write("m.csv",
                              "# URG on grey paper, 30 deg incidence\n"
                              "measured_m,true_m\n"
                              "0.05,0.081\n"
                              "\n"
                              "0.25, 0.262  # spaces and a trailing comment\n"
                              "  0.5 ,0.5\n"
                              "+1.0,9.6e-1\n");
  const RangePairs pairs = read_range_pairs_csv(path);
  ASSERT_EQ(pairs.measured_m.size(), 4u);
  ASSERT_EQ(pairs.true_m.size(), 4u);
  EXPECT_EQ(pairs.measured_m[0], 0.05);
  EXPECT_EQ(pairs.true_m[0], 0.081);
  EXPECT_EQ(pairs.measured_m[1], 0.25);
  EXPECT_EQ(pairs.true_m[1], 0.262);
  EXPECT_EQ(pairs.measured_m[3], 1.0);
  EXPECT_EQ(pairs.true_m[3], 0.96);
  EXPECT_EQ(pairs.line, (std::vector<int>{3, 5, 6, 7}));
}

TEST_F(CalibrationCsv, ReadsMillimetresWithWindowsLineEndsAndSwappedColumns) {
  const fs::path path = write("mm.csv",
                              "\xEF\xBB\xBFtrue_mm,measured_mm\r\n"
                              "81,50\r\n"
                              "262,250\r\n"
                              "500,500\r\n"
                              "960,1000\r\n"
                              "1500,1510\r\n");
  const RangePairs pairs = read_range_pairs_csv(path);
  ASSERT_EQ(pairs.measured_m.size(), 5u);
  EXPECT_DOUBLE_EQ(pairs.measured_m[0], 0.050);
  EXPECT_DOUBLE_EQ(pairs.true_m[0], 0.081);
  EXPECT_DOUBLE_EQ(pairs.measured_m[4], 1.510);
  EXPECT_DOUBLE_EQ(pairs.true_m[4], 1.500);
}

TEST_F(CalibrationCsv, ShippedExampleIsReadable) {
  const fs::path path = fs::path(STRIDEMAP_SOURCE_DIR) / "configs" / "urg_calibration_example.csv";
  const RangePairs pairs = read_range_pairs_csv(path);
  EXPECT_GE(pairs.measured_m.size(), 20u);
  for (std::size_t i = 0; i < pairs.measured_m.size(); ++i) {
    EXPECT_GT(pairs.measured_m[i], 0.04);
    EXPECT_LT(pairs.measured_m[i], 1.1);
    EXPECT_NEAR(pairs.true_m[i], pairs.measured_m[i], 0.06);
  }
}

TEST_F(CalibrationCsv, MissingFileIsNamed) {
  const fs::path path = directory_ / "absent.csv";
  try {
    read_range_pairs_csv(path);
    FAIL() << "expected an InputError";
  } catch (const InputError& e) {
    const std::string message = e.what();
    EXPECT_NE(message.find(path.string()), std::string::npos) << message;
    EXPECT_NE(message.find("no such file"), std::string::npos) << message;
  }
  EXPECT_THROW(read_range_pairs_csv(directory_), InputError);
}

TEST_F(CalibrationCsv, NoHeader) {
  std::string message = error_for("", 1);
  EXPECT_NE(message.find("no header"), std::string::npos) << message;
  message = error_for("# only a comment\n\n", 2);
  EXPECT_NE(message.find("no header"), std::string::npos) << message;
}

TEST_F(CalibrationCsv, HeaderProblems) {
  std::string message = error_for("# c\nmeasured,true\n0.1,0.1\n", 2);
  EXPECT_NE(message.find("unknown column 'measured'"), std::string::npos) << message;
  message = error_for("0.1,0.11\n0.2,0.21\n", 1);
  EXPECT_NE(message.find("unknown column '0.1'"), std::string::npos) << message;
  message = error_for("measured_m,true_m,sigma_m\n", 1);
  EXPECT_NE(message.find("3 columns"), std::string::npos) << message;
  message = error_for("measured_m,measured_mm\n", 1);
  EXPECT_NE(message.find("measured_mm"), std::string::npos) << message;
  EXPECT_NE(message.find("repeats"), std::string::npos) << message;
}

TEST_F(CalibrationCsv, WrongColumnCount) {
  std::string message = error_for("measured_m,true_m\n0.1,0.1\n0.2\n", 3);
  EXPECT_NE(message.find("1 columns, expected 2"), std::string::npos) << message;
  message = error_for("measured_m,true_m\n0.1,0.1,0.3\n", 2);
  EXPECT_NE(message.find("3 columns, expected 2"), std::string::npos) << message;
}

TEST_F(CalibrationCsv, BadValues) {
  const std::string header = "measured_m,true_m\n0.1,0.1\n";
  std::string message = error_for(header + "0.2,abc\n", 3);
  EXPECT_NE(message.find("true value 'abc' is not a number"), std::string::npos) << message;
  message = error_for(header + "0.2m,0.2\n", 3);
  EXPECT_NE(message.find("measured value '0.2m' is not a number"), std::string::npos) << message;
  message = error_for(header + ",0.2\n", 3);
  EXPECT_NE(message.find("is not a number"), std::string::npos) << message;
  message = error_for(header + "nan,0.2\n", 3);
  EXPECT_NE(message.find("'nan' is not finite"), std::string::npos) << message;
  message = error_for(header + "0.2,inf\n", 3);
  EXPECT_NE(message.find("'inf' is not finite"), std::string::npos) << message;
  message = error_for(header + "0.2,1e999\n", 3);
  EXPECT_NE(message.find("1e999"), std::string::npos) << message;
  message = error_for(header + "-0.2,0.2\n", 3);
  EXPECT_NE(message.find("not a positive range"), std::string::npos) << message;
}

TEST_F(CalibrationCsv, TooFewRows) {
  const std::string message =
      error_for("measured_mm,true_mm\n100,101\n200,202\n\n300,303\n# end\n", 6);
  EXPECT_NE(message.find("only 3 data rows"), std::string::npos) << message;
  EXPECT_NE(message.find("at least 4"), std::string::npos) << message;
}

TEST_F(CalibrationCsv, StreamOverloadUsesTheGivenName) {
  std::istringstream input("measured_m,true_m\n0.1,x\n");
  try {
    read_range_pairs_csv(input, "pasted pairs");
    FAIL() << "expected an InputError";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("pasted pairs:2:"), std::string::npos) << e.what();
  }
}

}  // namespace
}  // namespace stridemap
