// What the tool says on stderr besides errors: no progress bar when stderr
// is not a terminal (a pipe here, as in every script and CI log), notes
// only with --verbose, --quiet and --verbose anywhere on the line, and a
// default scene that is nowhere named with every place looked in.
#include <gtest/gtest.h>

#include <filesystem>
#include <string>

#include "cli/cli_runner.hpp"
#include "live/test_folder.hpp"
#include "test_paths.hpp"

namespace stridemap {
namespace terminal_output_test {
namespace {

using test::run_cli;
using test::shell_quoted;

const std::string kScene = std::string(STRIDEMAP_SOURCE_DIR) + "/scenes/cart_rail_boxes.yaml";

// run_cli in another working folder (the tool's own --version first: the
// runner puts the tool's path at the front of the line).
test::CommandResult run_cli_in(const std::filesystem::path& folder, const std::string& arguments) {
  return run_cli("--version >/dev/null && cd " + shell_quoted(folder.string()) + " && " +
                 shell_quoted(STRIDEMAP_CLI_PATH) + " " + arguments);
}

TEST(TerminalOutput, PipedStderrGetsNoProgressBar) {
  test::TestFolder dir;
  // A run of about a second or more, long enough for a bar on a terminal.
  const auto result = run_cli("experiment cart-rail --scene " + shell_quoted(kScene) + " --out " +
                              shell_quoted(dir / "out") + " --mixed-pixels on");
  ASSERT_EQ(result.exit_code, 0) << result.output;
  EXPECT_EQ(result.output.find('\r'), std::string::npos) << result.output;
  EXPECT_EQ(result.output.find("scans/s"), std::string::npos) << result.output;
  EXPECT_EQ(result.output.find("\x1b["), std::string::npos) << result.output;
  EXPECT_EQ(result.output.find("stridemap: wrote"), std::string::npos) << "a note without --verbose";
}

// A folder name is the user's text: an escape byte in it reaches stdout
// written out, not obeyed by the terminal.
TEST(TerminalOutput, AnEscapeInTheOutputFolderIsPrintedWrittenOut) {
  test::TestFolder dir;
  const std::string out = dir / "o\x1b[31mred";
  const auto result = run_cli("experiment cart-rail --scene " + shell_quoted(kScene) + " --out " + shell_quoted(out));
  ASSERT_EQ(result.exit_code, 0) << result.output;
  EXPECT_EQ(result.output.find('\x1b'), std::string::npos) << result.output;
  EXPECT_NE(result.output.find("o\\x1b[31mred/cart-rail-urg"), std::string::npos) << result.output;
}

TEST(TerminalOutput, VerboseNotesAndQuietAnywhereOnTheLine) {
  test::TestFolder dir;
  const auto verbose = run_cli("experiment cart-rail --scene " + shell_quoted(kScene) + " --out " +
                               shell_quoted(dir / "out") + " --verbose");
  ASSERT_EQ(verbose.exit_code, 0) << verbose.output;
  EXPECT_NE(verbose.output.find("stridemap: wrote " + (dir / "out") + "/cart-rail-urg"), std::string::npos)
      << verbose.output;

  const auto quiet = run_cli("--quiet experiment cart-rail --scene " + shell_quoted(kScene) + " --out " +
                             shell_quoted(dir / "out2"));
  ASSERT_EQ(quiet.exit_code, 0) << quiet.output;
  EXPECT_NE(quiet.output.find("outputs: "), std::string::npos) << "stdout stays: " << quiet.output;
  EXPECT_EQ(quiet.output.find("stridemap: "), std::string::npos) << quiet.output;

  const auto both = run_cli("map --quiet --log a.log --poses b.txt --out c --verbose");
  EXPECT_EQ(both.exit_code, 2) << both.output;
  EXPECT_NE(both.output.find("--quiet excludes --verbose"), std::string::npos) << both.output;
}

TEST(TerminalOutput, DefaultSceneNowhereIsNamedWithWhereItWasLookedFor) {
  test::TestFolder dir;  // no scenes/ here, and the build tree has no share/stridemap
  const auto result = run_cli_in(dir.path(), "soak --scans 1");
  EXPECT_EQ(result.exit_code, 2) << result.output;
  EXPECT_NE(result.output.find("--scene: the default file scenes/soak_circuit.yaml was not found"), std::string::npos)
      << result.output;
  EXPECT_NE(result.output.find((dir / "scenes/soak_circuit.yaml")), std::string::npos) << result.output;
  EXPECT_NE(result.output.find("share/stridemap/scenes/soak_circuit.yaml"), std::string::npos) << result.output;

  // A scene given explicitly is used as given, wherever the tool runs.
  const auto given = run_cli_in(dir.path(), "soak --scans 20 --scene " +
                                                shell_quoted(std::string(STRIDEMAP_SOURCE_DIR) + "/scenes/soak_circuit.yaml"));
  EXPECT_EQ(given.exit_code, 0) << given.output;
}

}  // namespace
}  // namespace terminal_output_test
}  // namespace stridemap
