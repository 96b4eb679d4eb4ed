// `stridemap scene random` and `stridemap experiment fidelity` as a user runs them.
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>

#include <unistd.h>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "cli/cli_runner.hpp"

namespace random_scenes_cli_test {
namespace {

namespace fs = std::filesystem;
using stridemap::test::CommandResult;
using stridemap::test::run_cli;

fs::path fresh_dir(const std::string& name) {
  const fs::path dir = fs::temp_directory_path() / ("stridemap_cli_" + name + "_" + std::to_string(::getpid()));
  fs::remove_all(dir);
  fs::create_directories(dir);
  return dir;
}

std::string read(const fs::path& path) {
  std::ifstream in(path);
  std::stringstream text;
  text << in.rdbuf();
  return text.str();
}

TEST(SceneRandomCommand, WritesALoadableSceneAndNeverOverwrites) {
  const fs::path dir = fresh_dir("scene_random");
  const fs::path scene = dir / "a.yaml";
  CommandResult r = run_cli("scene random --seed 4 --kind boxes --out " + scene.string());
  ASSERT_EQ(r.exit_code, 0) << r.output;
  const std::string first = read(scene);
  EXPECT_NE(first.find("seed 4"), std::string::npos);
  // The file is a scene the experiments read.
  r = run_cli("experiment cart-rail --sensor urg --scene " + scene.string() + " --out " + (dir / "out").string());
  EXPECT_EQ(r.exit_code, 0) << r.output;

  r = run_cli("scene random --seed 5 --kind boxes --out " + scene.string());
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_NE(r.output.find("exists already"), std::string::npos) << r.output;
  EXPECT_EQ(read(scene), first) << "the existing file is untouched";

  r = run_cli("scene random --seed 5 --kind hills --out " + (dir / "b.yaml").string());
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_NE(r.output.find("--kind"), std::string::npos) << r.output;
  EXPECT_FALSE(fs::exists(dir / "b.yaml"));
  r = run_cli("scene random --seed 5 --kind rocky --out " + (dir / "missing" / "c.yaml").string());
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_NE(r.output.find("cannot create"), std::string::npos) << r.output;
}

TEST(FidelityCommand, TwoScenesGiveDistributionsInSummary) {
  const fs::path dir = fresh_dir("fidelity");
  const CommandResult r =
      run_cli("experiment fidelity --scenes 2 --seed 2 --structured-light off --out " + dir.string());
  ASSERT_EQ(r.exit_code, 0) << r.output;
  EXPECT_NE(r.output.find("mixed_artifacts_removed_pct"), std::string::npos) << r.output;
  std::ifstream in(dir / "fidelity" / "summary.json");
  const nlohmann::json summary = nlohmann::json::parse(in);
  EXPECT_EQ(summary["experiment"], "fidelity");
  EXPECT_EQ(summary["scenes"].size(), 2u);
  ASSERT_FALSE(summary["figures"].empty());
  for (const auto& figure : summary["figures"]) {
    for (const char* key : {"median", "p90", "worst", "scenes"}) EXPECT_TRUE(figure.contains(key)) << key;
  }
  EXPECT_TRUE(fs::exists(dir / "fidelity" / "scenes" / "scene_2000.yaml"));
  EXPECT_EQ(run_cli("experiment fidelity --scenes 0 --out " + dir.string()).exit_code, 2);
  EXPECT_EQ(run_cli("experiment fidelity --kind rocky --out " + dir.string()).exit_code, 2);
  EXPECT_EQ(summary["bystanders"], false) << "auto: off without structured light";
}

TEST(FidelityCommand, StructuredLightOptionsAreCheckedBeforeAnyWork) {
  const fs::path dir = fresh_dir("fidelity_options");
  const CommandResult lux = run_cli("experiment fidelity --min-lux 2000 --max-lux 1000 --out " + dir.string());
  EXPECT_EQ(lux.exit_code, 2) << lux.output;
  EXPECT_NE(lux.output.find("--min-lux"), std::string::npos) << lux.output;
  const CommandResult steps = run_cli("experiment fidelity --kind steps --bystanders on --out " + dir.string());
  EXPECT_EQ(steps.exit_code, 2) << steps.output;
  EXPECT_NE(steps.output.find("--bystanders"), std::string::npos) << steps.output;
  EXPECT_EQ(run_cli("experiment fidelity --saturation-halo-dn 300 --out " + dir.string()).exit_code, 2);
  EXPECT_FALSE(fs::exists(dir / "fidelity" / "summary.json"));
}

}  // namespace
}  // namespace random_scenes_cli_test
