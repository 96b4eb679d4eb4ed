// The README's commands for a log of one's own, run as written: the lines
// are read from README.md itself, so a command the README shows that no
// longer works fails here.
#include <cmath>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <numbers>
#include <sstream>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "cli/cli_runner.hpp"
#include "live/test_folder.hpp"
#include "test_paths.hpp"

namespace stridemap {
namespace {

using test::run_command;
using test::shell_quoted;

// The shell lines of README.md from the line holding `marker` to the end
// of its code block, comments dropped.
std::vector<std::string> readme_commands(const std::string& marker) {
  std::ifstream in(std::string(STRIDEMAP_SOURCE_DIR) + "/README.md");
  std::vector<std::string> commands;
  std::string line;
  bool inside = false;
  while (std::getline(in, line)) {
    if (!inside) {
      inside = line.find(marker) != std::string::npos;
      continue;
    }
    if (line.starts_with("```")) break;
    const auto comment = line.find(" #");
    if (comment != std::string::npos) line.erase(comment);
    while (!line.empty() && line.back() == ' ') line.pop_back();
    if (!line.empty() && !line.starts_with("#")) commands.push_back(line);
  }
  return commands;
}

void replace_all(std::string& text, const std::string& from, const std::string& to) {
  for (auto at = text.find(from); at != std::string::npos; at = text.find(from, at + to.size())) {
    text.replace(at, from.size(), to);
  }
}

// A rover turning on the spot in a round room 2 m across, in BreezySLAM's
// format (docs/import.md): time in us, ticks at fields 2 and 3, 683 ranges.
std::string round_room_log() {
  std::ostringstream log;
  for (int k = 0; k < 60; ++k) {
    log << 1000000 + 100000 * k << " 0 " << -20 * k << " " << 20 * k;
    for (int f = 4; f < 24; ++f) log << " 0";
    for (int b = 0; b < 683; ++b) log << " " << (b % 97 == 0 ? 0 : 1000 + (b % 5));
    log << "\n";
  }
  return log.str();
}

TEST(ReadmeSnippets, ALogOfYourOwnIsImportedMappedExportedAndReported) {
  const std::vector<std::string> commands = readme_commands("# A BreezySLAM log of your own");
  ASSERT_GE(commands.size(), 5u) << "the README's BreezySLAM block was not found";
  test::TestFolder folder;
  std::ofstream(folder / "exp1.dat") << round_room_log();
  for (std::string command : commands) {
    replace_all(command, "build/bin/stridemap", shell_quoted(STRIDEMAP_CLI_PATH));
    replace_all(command, " configs/", " " + std::string(STRIDEMAP_SOURCE_DIR) + "/configs/");
    const auto result = run_command("cd " + shell_quoted(folder.path().string()) + " && " + command + " 2>&1");
    EXPECT_EQ(result.exit_code, 0) << command << "\n" << result.output;
  }
  EXPECT_TRUE(std::filesystem::exists(folder / "exp1/map.smap"));
  EXPECT_TRUE(std::filesystem::exists(folder / "exp1/npy/elevation.npy"));
  EXPECT_TRUE(std::filesystem::exists(folder / "exp1/map.ply"));
}

}  // namespace
}  // namespace stridemap
