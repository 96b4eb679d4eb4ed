#include "stridemap/io/text_file.hpp"

#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>

#include <unistd.h>

#include <gtest/gtest.h>

#include "stridemap/core/error.hpp"

namespace stridemap {
namespace {

namespace fs = std::filesystem;

TEST(TextFile, WritesTheWholeTextAndLeavesNoTemporaryFile) {
  const fs::path dir = fs::temp_directory_path() / ("stridemap_text_file_" + std::to_string(::getpid()));
  fs::remove_all(dir);
  fs::create_directories(dir);
  io::write_text_file((dir / "summary.json").string(), "{\"a\": 1}\n", "summary");
  std::ifstream in(dir / "summary.json");
  std::stringstream text;
  text << in.rdbuf();
  EXPECT_EQ(text.str(), "{\"a\": 1}\n");
  EXPECT_EQ(std::distance(fs::directory_iterator(dir), fs::directory_iterator()), 1);
  fs::remove_all(dir);
}

TEST(TextFile, MissingFolderIsAnErrorNamingThePath) {
  try {
    io::write_text_file("/nonexistent/folder/summary.json", "x", "summary");
    FAIL();
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("/nonexistent/folder/summary.json"), std::string::npos) << e.what();
  }
}

}  // namespace
}  // namespace stridemap
