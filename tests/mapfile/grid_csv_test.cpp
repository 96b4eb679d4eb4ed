#include "stridemap/mapfile/grid_csv.hpp"

#include <gtest/gtest.h>
#include <unistd.h>

#include <cmath>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <limits>
#include <sstream>
#include <string>
#include <vector>

#include "stridemap/core/error.hpp"

namespace stridemap::io {
namespace {

namespace fs = std::filesystem;
constexpr float kNaN = std::numeric_limits<float>::quiet_NaN();
constexpr float kInf = std::numeric_limits<float>::infinity();

class GridCsvTest : public ::testing::Test {
 protected:
  void SetUp() override {
    folder_ = fs::temp_directory_path() /
              ("stridemap_csv_test_" + std::to_string(::getpid()) + "_" +
               ::testing::UnitTest::GetInstance()->current_test_info()->name());
    fs::remove_all(folder_);
    fs::create_directories(folder_);
  }
  void TearDown() override { fs::remove_all(folder_); }
  std::string path(const std::string& name) const { return (folder_ / name).string(); }
  std::string write_text(const std::string& name, const std::string& text) const {
    std::ofstream(path(name), std::ios::binary) << text;
    return path(name);
  }
  std::string read_text(const std::string& name) const {
    std::ifstream in(path(name), std::ios::binary);
    std::stringstream buffer;
    buffer << in.rdbuf();
    return buffer.str();
  }
  fs::path folder_;
};

template <typename Function>
void expect_input_error(Function&& function, const std::vector<std::string>& fragments) {
  try {
    function();
    ADD_FAILURE() << "no InputError thrown";
  } catch (const InputError& error) {
    const std::string message = error.what();
    for (const auto& fragment : fragments) {
      EXPECT_NE(message.find(fragment), std::string::npos) << "'" << fragment << "' missing from: " << message;
    }
  }
}

bool same_bits(float a, float b) {
  if (std::isnan(a) || std::isnan(b)) return std::isnan(a) && std::isnan(b);
  return std::memcmp(&a, &b, sizeof a) == 0;
}

TEST_F(GridCsvTest, RoundTripIsExactIncludingUnknownAndInfinity) {
  Eigen::MatrixXf values(3, 4);
  values << 0.1F, -0.0123456789F, 1e-30F, 3.4e38F,  //
      kNaN, 0.0F, -kInf, kInf,                      //
      12345.678F, std::nextafter(1.0F, 2.0F), -7.0F, kNaN;
  GridCsvOptions options;
  options.layer_name = "elevation";
  options.units = "m";
  options.cell_size_m = 0.01;
  options.origin_x_m = -0.495;
  options.origin_y_m = 0.125;
  write_grid_csv(path("grid.csv"), values, options);

  GridCsvOptions metadata;
  const Eigen::MatrixXf back = read_grid_csv(path("grid.csv"), &metadata);
  ASSERT_EQ(back.rows(), 3);
  ASSERT_EQ(back.cols(), 4);
  for (int i = 0; i < 3; ++i) {
    for (int j = 0; j < 4; ++j) EXPECT_TRUE(same_bits(back(i, j), values(i, j))) << i << "," << j;
  }
  EXPECT_EQ(metadata.layer_name, "elevation");
  EXPECT_EQ(metadata.units, "m");
  EXPECT_EQ(metadata.cell_size_m, 0.01);
  EXPECT_EQ(metadata.origin_x_m, -0.495);
  EXPECT_EQ(metadata.origin_y_m, 0.125);
  EXPECT_EQ(std::distance(fs::directory_iterator(folder_), fs::directory_iterator{}), 1) << "temporary file left";
}

TEST_F(GridCsvTest, FormatIsAHeaderThenOneLinePerRow) {
  Eigen::MatrixXf values(2, 3);
  values << 0.5F, kNaN, 2.0F, -1.25F, 0.1F, 3.0F;
  GridCsvOptions options;
  options.layer_name = "certainty";
  options.cell_size_m = 0.02;
  write_grid_csv(path("grid.csv"), values, options);
  EXPECT_EQ(read_text("grid.csv"),
            "# stridemap grid; layer=certainty; rows=2; cols=3; cell_size_m=0.02; rows_along=+x; cols_along=+y; "
            "unknown=nan\n"
            "0.5,nan,2\n"
            "-1.25,0.1,3\n");
}

TEST_F(GridCsvTest, ReadsPlainTablesWithSpacesCrLfAndComments) {
  const std::string file = write_text("plain.csv", "# made by hand\r\n1, 2 ,3\r\n# between\r\n4,NaN, -5e-1\r\n\r\n\n");
  GridCsvOptions metadata;
  metadata.units = "stale";
  const Eigen::MatrixXf grid = read_grid_csv(file, &metadata);
  ASSERT_EQ(grid.rows(), 2);
  ASSERT_EQ(grid.cols(), 3);
  EXPECT_EQ(grid(0, 1), 2.0F);
  EXPECT_TRUE(std::isnan(grid(1, 1)));
  EXPECT_EQ(grid(1, 2), -0.5F);
  EXPECT_TRUE(metadata.units.empty()) << "metadata of a file without header must be reset";
}

TEST_F(GridCsvTest, ReaderErrorsNameFileLineAndField) {
  expect_input_error([&] { read_grid_csv(write_text("ragged.csv", "# h\n1,2,3\n4,5\n")); },
                     {"ragged.csv", "line 3", "2 fields", "first row (line 2) has 3"});
  expect_input_error([&] { read_grid_csv(write_text("word.csv", "1,2\n3,abc\n")); },
                     {"word.csv", "line 2", "field 2", "'abc' is not a number"});
  expect_input_error([&] { read_grid_csv(write_text("tail.csv", "1,2\n3,4x\n")); }, {"line 2", "'4x'"});
  expect_input_error([&] { read_grid_csv(write_text("empty_field.csv", "1,,3\n")); },
                     {"line 1", "field 2", "empty"});
  expect_input_error([&] { read_grid_csv(write_text("gap.csv", "1,2\n\n3,4\n")); },
                     {"gap.csv", "line 2", "blank line"});
  expect_input_error([&] { read_grid_csv(write_text("huge.csv", "1e60\n")); }, {"'1e60'", "out of float range"});
  expect_input_error([&] { read_grid_csv(write_text("nothing.csv", "# only a comment\n")); },
                     {"nothing.csv", "no data rows"});
  expect_input_error([&] { read_grid_csv(write_text("short.csv", "# stridemap grid; rows=3; cols=2\n1,2\n3,4\n")); },
                     {"short.csv", "rows=3", "2 data rows"});
  expect_input_error(
      [&] { read_grid_csv(write_text("badhead.csv", "# stridemap grid; cell_size_m=ten\n1\n")); },
      {"badhead.csv", "line 1", "cell_size_m='ten'"});
  expect_input_error([&] { read_grid_csv(path("missing.csv")); }, {"missing.csv", "does not exist"});
  expect_input_error([&] { read_grid_csv(folder_.string()); }, {"is a folder"});
}

TEST_F(GridCsvTest, WriterErrorsNameThePath) {
  const Eigen::MatrixXf values = Eigen::MatrixXf::Zero(2, 2);
  const std::string missing = path("absent/grid.csv");
  expect_input_error([&] { write_grid_csv(missing, values, GridCsvOptions{}); }, {missing, "does not exist"});
  expect_input_error([&] { write_grid_csv(path("e.csv"), Eigen::MatrixXf(0, 0), GridCsvOptions{}); },
                     {"e.csv", "empty"});
  GridCsvOptions options;
  options.units = "m; evil=1";
  expect_input_error([&] { write_grid_csv(path("u.csv"), values, options); }, {"u.csv", "units", "';'"});
  options = {};
  options.cell_size_m = std::numeric_limits<double>::infinity();
  expect_input_error([&] { write_grid_csv(path("c.csv"), values, options); }, {"cell_size_m", "not finite"});
  EXPECT_EQ(std::distance(fs::directory_iterator(folder_), fs::directory_iterator{}), 0);
}

}  // namespace
}  // namespace stridemap::io
