// `stridemap soak` as `make soak` runs it, on a few hundred scans.
#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <string>

#include <gtest/gtest.h>

#include "cli/cli_runner.hpp"
#include "test_paths.hpp"

namespace stridemap {
namespace soak_command_test {
namespace {

namespace fs = std::filesystem;
using test::CommandResult;
using test::run_cli;
using test::shell_quoted;

const std::string kScene = std::string(STRIDEMAP_SOURCE_DIR) + "/scenes/soak_circuit.yaml";

TEST(SoakCommand, RepeatedRunsAgreeAndTheSummaryIsWritten) {
  const fs::path dir = fs::temp_directory_path() / ("stridemap_soak_cli_" + std::to_string(::getpid()));
  fs::remove_all(dir);
  const CommandResult r = run_cli("soak --scene " + shell_quoted(kScene) + " --scans 400 --repeat 2 --out " +
                                  shell_quoted(dir.string()));
  ASSERT_EQ(r.exit_code, 0) << r.output;
  EXPECT_NE(r.output.find("Soak run (simulated URG-04LX): 400 scans, circuit of radius 3.00 m"), std::string::npos)
      << r.output;
  EXPECT_NE(r.output.find("2 runs with seed 1: bit-identical maps"), std::string::npos) << r.output;
  EXPECT_NE(r.output.find("soak passed"), std::string::npos) << r.output;
  std::ifstream in(dir / "soak" / "summary.json");
  const nlohmann::json summary = nlohmann::json::parse(in);
  ASSERT_EQ(summary["runs"].size(), 2u);
  EXPECT_EQ(summary["runs"][0]["run_hash"], summary["runs"][1]["run_hash"]);
  EXPECT_EQ(summary["runs"][0]["invalid_cells"], 0);
  EXPECT_TRUE(summary["runs"][0]["simulated"].get<bool>());
  EXPECT_TRUE(summary["failures"].empty());
  fs::remove_all(dir);
}

TEST(SoakCommand, BadSceneAndOptionsAreErrors) {
  CommandResult r = run_cli("soak --scene /nonexistent/scene.yaml --scans 10");
  EXPECT_EQ(r.exit_code, 2) << r.output;
  EXPECT_NE(r.output.find("stridemap: error: /nonexistent/scene.yaml: cannot read scene file"), std::string::npos)
      << r.output;
  r = run_cli("soak --scene " + shell_quoted(kScene) + " --scans 10 --radius-m -1");
  EXPECT_EQ(r.exit_code, 2) << r.output;
  EXPECT_NE(r.output.find("stridemap: error: --radius-m: expected a number from 0.05 to 1000 m, got '-1'"),
            std::string::npos)
      << r.output;
  r = run_cli("soak --scans 0");
  EXPECT_EQ(r.exit_code, 2) << r.output;
  r = run_cli("soak --scene " + shell_quoted(kScene) + " --scans 10 --motion fly");
  EXPECT_EQ(r.exit_code, 2) << r.output;
  EXPECT_NE(r.output.find("--motion: expected circuit or walk, got 'fly'"), std::string::npos) << r.output;
  const std::string no_path = std::string(STRIDEMAP_SOURCE_DIR) + "/scenes/cart_rail_boxes.yaml";
  r = run_cli("soak --scene " + shell_quoted(no_path) + " --scans 10 --motion walk");
  EXPECT_EQ(r.exit_code, 2) << r.output;
  EXPECT_NE(r.output.find("no walk_path section"), std::string::npos) << r.output;
}

}  // namespace
}  // namespace soak_command_test
}  // namespace stridemap
