// Outputs that cannot be written, seen from the command line: the tool
// names the path and the reason and exits with status 2. Root-proof places
// only (CI runs as root): /dev/full, sysfs, a path below a regular file.
#include <sys/stat.h>
#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <string>

#include <gtest/gtest.h>

#include "cli/cli_runner.hpp"
#include "test_paths.hpp"

namespace stridemap {
namespace output_errors_test {
namespace {

namespace fs = std::filesystem;
using test::CommandResult;
using test::run_cli;
using test::shell_quoted;

const std::string kScene = std::string(STRIDEMAP_SOURCE_DIR) + "/scenes/cart_rail_boxes.yaml";
const std::string kPairs = std::string(STRIDEMAP_SOURCE_DIR) + "/configs/urg_calibration_example.csv";

TEST(CliOutputErrors, FullDiskForTheCalibrationJson) {
  if (::access("/dev/full", W_OK) != 0) GTEST_SKIP() << "no writable /dev/full";
  const CommandResult r = run_cli("calibrate-range --csv " + shell_quoted(kPairs) + " --json /dev/full");
  EXPECT_EQ(r.exit_code, 2) << r.output;
  EXPECT_NE(r.output.find("stridemap: error: cannot write calibration JSON '/dev/full': write failed (No space left "
                          "on device)"),
            std::string::npos)
      << r.output;
}

// ThreadSanitizer's runtime writes a file of its own before main runs, so
// under `make test-tsan` any file size limit kills the tool before it can
// ignore SIGXFSZ; the plain and ASan builds run the test.
#if defined(__SANITIZE_THREAD__)
#define STRIDEMAP_TOOL_UNDER_TSAN 1
#elif defined(__has_feature)
#if __has_feature(thread_sanitizer)
#define STRIDEMAP_TOOL_UNDER_TSAN 1
#endif
#endif

// `ulimit -f`: the limit binds root too. Only the tool's shell has it, so
// the pipe that reads its output is not cut short.
TEST(CliOutputErrors, AFileSizeLimitIsAnErrorNamingTheFileNotASilentKill) {
#ifdef STRIDEMAP_TOOL_UNDER_TSAN
  GTEST_SKIP() << "ThreadSanitizer's runtime writes a file before main, which the limit kills";
#endif
  const std::string folder = ::testing::TempDir() + "/stridemap_fsize_limit";
  fs::remove_all(folder);
  fs::create_directories(folder);
  const std::string json = folder + "/calibration.json";
  const std::string tool = shell_quoted(STRIDEMAP_CLI_PATH) + " calibrate-range --csv " + shell_quoted(kPairs) +
                           " --json " + shell_quoted(json);
  const CommandResult r = test::run_command("sh -c " + shell_quoted("ulimit -f 0; exec " + tool + " 2>&1"));
  EXPECT_EQ(r.exit_code, 2) << r.output;
  EXPECT_NE(r.output.find("stridemap: error: cannot write calibration JSON '" + json + "': write failed (File too large)"),
            std::string::npos)
      << r.output;
  EXPECT_FALSE(fs::exists(json));
  EXPECT_TRUE(fs::is_empty(folder)) << "no temporary left behind";
  fs::remove_all(folder);
}

TEST(CliOutputErrors, OutputFolderThatCannotBeCreated) {
  const fs::path dir = fs::temp_directory_path() / ("stridemap_cli_out_" + std::to_string(::getpid()));
  fs::remove_all(dir);
  fs::create_directories(dir);
  std::ofstream(dir / "plain.txt") << "x";
  struct Case {
    std::string out, reason;
  };
  std::vector<Case> cases = {{(dir / "plain.txt" / "out").string(), "Not a directory"}, {"/dev/full", "Not a directory"}};
  if (fs::is_directory("/sys/kernel")) cases.push_back({"/sys/stridemap_out", "cannot create the output folder"});
  for (const Case& c : cases) {
    const CommandResult r = run_cli("experiment cart-rail --scene " + shell_quoted(kScene) + " --out " + shell_quoted(c.out));
    EXPECT_EQ(r.exit_code, 2) << c.out << ": " << r.output;
    EXPECT_NE(r.output.find("stridemap: error: " + c.out), std::string::npos) << r.output;
    EXPECT_NE(r.output.find(c.reason), std::string::npos) << r.output;
  }
  fs::remove_all(dir);
}

}  // namespace
}  // namespace output_errors_test
}  // namespace stridemap
