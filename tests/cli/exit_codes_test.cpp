// The exit codes the docs promise (README.md, docs/reliability.md), for every
// command: 0 done (also --help, --version, a bare `stridemap`), 2 bad input
// or usage with one `stridemap: error:` line, never CLI11's own 104-109.
// Every refusal here happens before any work, so each row runs in moments.
#include <gtest/gtest.h>

#include <chrono>
#include <string>
#include <vector>

#include "cli/cli_runner.hpp"
#include "live/test_folder.hpp"
#include "test_paths.hpp"

namespace {

using stridemap::test::run_cli;
using stridemap::test::shell_quoted;

const std::string kSource = STRIDEMAP_SOURCE_DIR;
const std::string kScene = shell_quoted(kSource + "/scenes/cart_rail_boxes.yaml");
const std::string kLightConfig = shell_quoted(kSource + "/configs/ragno_structured_light.yaml");

struct Row {
  std::string arguments;  ///< after `stridemap`; OUT, POSES and DIR are replaced by paths in the test folder
  int exit_code;
  std::string expected;   ///< must appear in the output
};

std::string with_paths(std::string text, const stridemap::test::TestFolder& dir) {
  const std::pair<std::string, std::string> names[] = {
      {"OUT", shell_quoted(dir / "out")}, {"POSES", shell_quoted(dir / "poses.txt")}, {"DIR", shell_quoted(dir / "folder")}};
  for (const auto& [name, path] : names) {
    for (std::size_t at = text.find(name); at != std::string::npos; at = text.find(name, at + path.size())) {
      text.replace(at, name.size(), path);
    }
  }
  return text;
}

void check_rows(const std::vector<Row>& rows) {
  stridemap::test::TestFolder dir;
  dir.write("poses.txt", "0 0 0 0 0 0 0\n");
  std::filesystem::create_directories(dir / "folder");
  for (const Row& row : rows) {
    const std::string arguments = with_paths(row.arguments, dir);
    const auto result = run_cli(arguments);
    EXPECT_EQ(result.exit_code, row.exit_code) << "stridemap " << arguments << "\n" << result.output;
    EXPECT_NE(result.output.find(row.expected), std::string::npos)
        << "stridemap " << arguments << "\nexpected: " << row.expected << "\ngot: " << result.output;
    if (row.exit_code == 2) {
      EXPECT_EQ(result.output.rfind("stridemap: error: "), result.output.find("stridemap: error: "))
          << "one error line: " << result.output;
      EXPECT_NE(result.output.find("stridemap: error: "), std::string::npos) << result.output;
    }
  }
}

const std::vector<std::string> kCommands = {
    "calibrate-range",         "calibrate-structured-light", "detect-stripe",         "experiment cart-rail",
    "experiment mixed-pixels", "experiment lighting",        "experiment rocky-walk", "experiment mount-analysis",
    "sensor-report",           "simulate-stripe-image",      "emulate-urg",           "record",
    "live",                    "map",                        "soak"};

TEST(ExitCodes, HelpVersionAndBareCommandExitZero) {
  check_rows({{"", 0, "Subcommands:"},
              {"--help", 0, "Subcommands:"},
              {"--version", 0, "stridemap 0.1.0"}});
  for (const std::string& command : kCommands) check_rows({{command + " --help", 0, "Options:"}});
}

TEST(ExitCodes, EveryCommandRefusesAnUnknownOptionWithCodeTwoAndThePrefix) {
  std::vector<Row> rows = {{"frobnicate", 2, "stridemap: error: "},
                           {"experiment", 2, "stridemap: error: A subcommand is required"}};
  for (const std::string& command : kCommands) {
    rows.push_back({command + " --no-such-option 1", 2, "stridemap: error: "});
  }
  check_rows(rows);
}

TEST(ExitCodes, MissingRequiredOptionsAreUsageErrors) {
  check_rows({
      {"calibrate-range", 2, "--csv is required"},
      {"calibrate-structured-light --config x.yaml", 2, "--target is required"},
      {"detect-stripe --config x.yaml", 2, "image is required"},
      {"experiment cart-rail --out OUT", 2, "--scene is required"},
      {"experiment mixed-pixels --out OUT", 2, "--scene is required"},
      {"experiment lighting", 2, "--out is required"},
      {"experiment rocky-walk", 2, "--out is required"},
      {"experiment mount-analysis", 2, "--out is required"},
      {"sensor-report", 2, "--config is required"},
      {"simulate-stripe-image --config x.yaml", 2, "--out is required"},
      {"emulate-urg", 2, "--link is required"},
      {"record --out OUT", 2, "--device is required"},
      {"live --device /dev/null --out OUT", 2, "--poses is required"},
      {"map --log x --out OUT", 2, "--poses is required"},
      {"soak --help-me", 2, "stridemap: error: "},
  });
}

TEST(ExitCodes, BadNumbersAreRefusedNamingTheOptionAndWhatItAccepts) {
  const std::string rail = "experiment cart-rail --scene " + kScene + " --out OUT ";
  const std::string live = "live --device /dev/null --poses POSES --out OUT ";
  check_rows({
      {rail + "--seed abc", 2, "--seed: expected a whole number from 0 to 18446744073709551615, got 'abc'"},
      {rail + "--seed -1", 2, "--seed: expected a whole number from 0 to 18446744073709551615, got '-1'"},
      {rail + "--seed 0x10", 2, "got '0x10'"},
      {rail + "--cell-size-m 0", 2, "--cell-size-m: expected a number from 0.0001 to 10 m, got '0'"},
      {rail + "--cell-size-m nan", 2, "--cell-size-m: expected a number from 0.0001 to 10 m, got 'nan'"},
      {rail + "--cell-size-m 1e300", 2, "got '1e300'"},
      {rail + "--cells -5", 2, "--cells: expected a whole number from 0 to 4096, got '-5'"},
      {rail + "--cells 20000", 2, "20000 x 20000 cells need 8.0 GB"},
      {"experiment rocky-walk --out OUT --cells 20000", 2, "--cells: map options: cells_per_side must be"},
      {"experiment rocky-walk --out OUT --cell-size-m -1", 2, "--cell-size-m: expected a number"},
      {"experiment mixed-pixels --scene x --out OUT --cluster-min-points 0", 2, "--cluster-min-points"},
      {"experiment mixed-pixels --scene x --out OUT --texture-log-sigma inf", 2, "--texture-log-sigma"},
      {rail + "--sensor structured-light --exposure bright", 2, "--exposure: expected auto, highlight or a fixed gain"},
      {rail + "--sensor structured-light --exposure 0", 2, "--exposure: expected auto, highlight or a fixed gain"},
      {rail + "--exposure 0.2", 2, "--exposure apply to --sensor structured-light only"},
      {"experiment lighting --out OUT --levels 300,nan", 2, "--levels: expected a number from 0 to 1e+06 lux"},
      {"experiment mount-analysis --out OUT --fields 0", 2, "--fields: expected a whole number from 1 to 10000"},
      {"calibrate-structured-light --config x --target 1=x.png --min-confidence 2", 2, "--min-confidence"},
      {"detect-stripe x.png --config x --min-red -3", 2, "--min-red: expected a whole number from 0 to 65535"},
      {"sensor-report --config x --cell-size 0", 2, "--cell-size: expected a number"},
      {"simulate-stripe-image --config x --out OUT --lux -1", 2, "--lux: expected a number from 0 to 1e+06 lux"},
      {"emulate-urg --link OUT --rate-hz 0", 2, "--rate-hz: expected a whole number from 1 to 1000"},
      {"emulate-urg --link OUT --drop-probability 1.5", 2, "--drop-probability"},
      {"soak --scans 0", 2, "--scans: expected a whole number from 1 to 100000000, got '0'"},
      {"soak --repeat 11", 2, "--repeat"},
      {live + "--duration-s -1", 2, "--duration-s: expected a number from 0 to 3.1536e+07 s, got '-1'"},
      {live + "--cluster 0", 2, "--cluster: expected a whole number from 1 to 99, got '0'"},
      {live + "--save-every-s nan", 2, "--save-every-s"},
      {"record --device /dev/null --out OUT --max-scans -1", 2, "--max-scans"},
      {"map --log x --poses POSES --out OUT --max-pose-gap-s 0", 2, "--max-pose-gap-s"},
  });
}

TEST(ExitCodes, AMapTooFineForMemoryIsRefusedBeforeAnythingIsAllocatedWithTheMemoryItNeeds) {
  // The rail scene spans 1.73 m: 0.1 mm cells would need 17339 cells a side, 6.0 GB.
  check_rows({{"experiment cart-rail --scene " + kScene + " --out OUT --cell-size-m 0.0001", 2,
               "stridemap: error: --cell-size-m 0.0001: map options: a 0.1 mm map of this "},
              {"experiment cart-rail --scene " + kScene + " --out OUT --cell-size-m 0.0001", 2, " GB; the limit is 4096"}});
}

TEST(ExitCodes, InputsThatAreFoldersAreClearErrorsNamingTheFile) {
  check_rows({{"map --log DIR --poses POSES --out OUT", 2, "folder: cannot open the scan log: it is a folder, not a file"},
              {"map --log " + kScene + " --poses DIR --out OUT", 2, "stridemap: error: "},
              {"experiment cart-rail --scene DIR --out OUT", 2, "it is a folder, not a file"},
              {"emulate-urg --link OUT --replay DIR", 2, "cannot open the recording: it is a folder"}});
}

TEST(ExitCodes, DevicesThatCanNeverBeAUrgFailAtOnceNotAfterTheConnectTimeout) {
  const auto start = std::chrono::steady_clock::now();
  check_rows({{"record --device DIR --out OUT --connect-timeout-s 30", 2, "folder: it is a folder, not a serial device"},
              {"record --device /dev/null --out OUT --connect-timeout-s 30", 2,
               "/dev/null: it is not a serial device (not a terminal)"},
              {"record --device POSES --out OUT --connect-timeout-s 30", 2, "it is a regular file, not a serial device"},
              {"live --device DIR/missing --poses POSES --out OUT --connect-timeout-s 30", 2,
               "missing: cannot open the device: No such file or directory"}});
  const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  EXPECT_LT(seconds, 20.0) << "a permanent device problem waited for the 30 s connect timeout";
}

TEST(ExitCodes, ControlBytesFromTheInputAreEscapedInTheMessage) {
  // An ESC sequence in an option value (here: clear the screen) reaches the
  // terminal as text, not as a command.
  const auto result = run_cli("experiment cart-rail --scene " + kScene + " --out /nonexistent --sensor \"$(printf '\\033[2J\\007')\"");
  EXPECT_EQ(result.exit_code, 2) << result.output;
  EXPECT_EQ(result.output.find('\x1b'), std::string::npos) << result.output;
  EXPECT_EQ(result.output.find('\x07'), std::string::npos) << result.output;
  EXPECT_NE(result.output.find("'\\x1b[2J\\x07' is not a sensor"), std::string::npos) << result.output;
}

}  // namespace
