// Runs the built `stridemap experiment cart-rail` as a user would.
#include <array>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <sstream>
#include <string>

#include <sys/wait.h>
#include <unistd.h>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "cli/cli_runner.hpp"
#include "stridemap/mapfile/map_file.hpp"
#include "test_paths.hpp"

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

TEST(CartRailCommand, WritesMapsTablesAndSummary) {
  const fs::path out = fresh_dir("cart_rail");
  const std::string scene = std::string(STRIDEMAP_SOURCE_DIR) + "/scenes/cart_rail_boxes.yaml";
  const CommandResult r = run_cli("experiment cart-rail --sensor urg --scene " + scene + " --out " + out.string() + " --seed 3");
  ASSERT_EQ(r.exit_code, 0) << r.output;
  EXPECT_NE(r.output.find("RMS error"), std::string::npos) << r.output;
  const fs::path dir = out / "cart-rail-urg";
  for (const char* file : {"elevation.png", "certainty.png", "error.png", "truth.png", "elevation.csv",
                           "certainty.csv", "state.csv", "truth.csv", "summary.json", "table.txt"}) {
    EXPECT_TRUE(fs::exists(dir / file)) << file;
  }
  // The report page shows table.txt as the readable table: it is the one printed.
  std::ifstream table_file(dir / "table.txt");
  const std::string table((std::istreambuf_iterator<char>(table_file)), std::istreambuf_iterator<char>());
  EXPECT_NE(table.find("truth [mm]"), std::string::npos) << table;
  EXPECT_NE(r.output.find(table), std::string::npos) << "table.txt:\n" << table << "\nprinted:\n" << r.output;
  std::ifstream in(dir / "summary.json");
  const nlohmann::json summary = nlohmann::json::parse(in);
  EXPECT_EQ(summary["experiment"], "cart-rail");
  EXPECT_EQ(summary.value("tool_version", "").rfind("stridemap ", 0), 0u) << "the version that made it";
  EXPECT_EQ(summary["sensor"], "urg");
  EXPECT_EQ(summary["seed"], 3);
  for (const char* key : {"rms_error_m", "max_error_m", "coverage", "artifact_cells", "artifact_threshold_m"}) {
    EXPECT_TRUE(summary["map"].contains(key)) << key;
  }
  ASSERT_TRUE(summary["objects"].is_array());
  ASSERT_FALSE(summary["objects"].empty());
  for (const auto& object : summary["objects"]) {
    for (const char* part : {"truth_m", "measured_m", "error_pct"}) {
      for (const char* dim : {"length", "width", "height"}) EXPECT_TRUE(object[part].contains(dim)) << part << dim;
    }
    EXPECT_TRUE(object["kind"] == "box" || object["kind"] == "cylinder");
  }
  // The final map whole, in the manifest with the rest, readable by map-info
  // and holding what state.csv shows.
  std::ifstream manifest(dir / ".stridemap-output");
  const std::string listed{std::istreambuf_iterator<char>(manifest), std::istreambuf_iterator<char>()};
  EXPECT_NE(listed.find("\nmap.smap\n"), std::string::npos) << listed;
  const CommandResult info = run_cli("map-info " + (dir / "map.smap").string());
  ASSERT_EQ(info.exit_code, 0) << info.output;
  EXPECT_NE(info.output.find("experiment cart-rail --sensor urg"), std::string::npos) << info.output;
  const stridemap::io::MapFile map = stridemap::io::load_map_file((dir / "map.smap").string());
  std::ifstream state_csv(dir / "state.csv");
  std::string line;
  std::getline(state_csv, line);  // the header
  int row = 0, differing = 0;
  std::size_t known = 0;
  for (; std::getline(state_csv, line); ++row) {
    std::stringstream cells(line);
    std::string value;
    for (int col = 0; std::getline(cells, value, ','); ++col) {
      const auto state = static_cast<int>(map.map.state(map.map.cell_at_local(row, col)));
      differing += std::stoi(value) != state;
      known += state != 0;
    }
  }
  EXPECT_EQ(row, map.map.cells_per_side());
  EXPECT_EQ(differing, 0);
  EXPECT_GT(known, 1000u);
  fs::remove_all(out);
}

TEST(CartRailCommand, BadSceneFileIsReportedWithFileAndLine) {
  const fs::path dir = fresh_dir("bad_scene");
  const fs::path scene = dir / "bad.yaml";
  std::ofstream(scene) << "terrain:\n  kind: flat\nboxes:\n  - name: a\n    center_x_m: 1.0\n    center_y_m: 0.0\n"
                          "    length_m: -0.2\n    width_m: 0.1\n    height_m: 0.1\n";
  const CommandResult r = run_cli("experiment cart-rail --scene " + scene.string() + " --out " + (dir / "out").string());
  EXPECT_EQ(r.exit_code, 2) << r.output;
  EXPECT_NE(r.output.find("bad.yaml"), std::string::npos) << r.output;
  EXPECT_NE(r.output.find("length_m"), std::string::npos) << r.output;
  EXPECT_NE(r.output.find(":7"), std::string::npos) << r.output;  // the line of the bad field
  fs::remove_all(dir);
}

TEST(CartRailCommand, MissingSceneAndUnknownSensorAreClearErrors) {
  const fs::path dir = fresh_dir("missing");
  CommandResult r = run_cli("experiment cart-rail --scene " + (dir / "nope.yaml").string() + " --out " + dir.string());
  EXPECT_EQ(r.exit_code, 2) << r.output;
  EXPECT_NE(r.output.find("nope.yaml"), std::string::npos) << r.output;
  r = run_cli("experiment cart-rail --sensor kinect --scene x.yaml --out " + dir.string());
  EXPECT_EQ(r.exit_code, 2) << r.output;
  EXPECT_NE(r.output.find("kinect"), std::string::npos) << r.output;
  fs::remove_all(dir);
}

TEST(CartRailCommand, ConfigFileSetsTheMapperAndItsErrorsAreReported) {
  const fs::path dir = fresh_dir("config");
  const std::string scene = std::string(STRIDEMAP_SOURCE_DIR) + "/scenes/cart_rail_boxes.yaml";
  const fs::path config = dir / "robot.yaml";
  std::ofstream(config) << "map:\n  cell_size_m: 0.015\nupdate:\n  elevation_rule: gated\n";
  CommandResult r = run_cli("experiment cart-rail --scene " + scene + " --config " + config.string() + " --out " +
                            (dir / "out").string());
  ASSERT_EQ(r.exit_code, 0) << r.output;
  EXPECT_NE(r.output.find("15 mm cells"), std::string::npos) << r.output;
  std::ifstream in(dir / "out" / "cart-rail-urg" / "summary.json");
  EXPECT_EQ(nlohmann::json::parse(in)["elevation_rule"], "gated");

  std::ofstream(config) << "map:\n  cell_size_m: 0.015\nupdate:\n  certainty_incremnt: 3\n";
  r = run_cli("experiment cart-rail --scene " + scene + " --config " + config.string() + " --out " + dir.string());
  EXPECT_EQ(r.exit_code, 2) << r.output;
  EXPECT_NE(r.output.find("robot.yaml:4: update.certainty_incremnt: unknown field"), std::string::npos) << r.output;
  fs::remove_all(dir);
}

TEST(MixedPixelsCommand, WritesTheComparison) {
  const fs::path dir = fresh_dir("mixed");
  const fs::path scene = dir / "short.yaml";
  std::ofstream(scene) << "terrain: {kind: flat}\nboxes:\n  - {name: box, center_x_m: 0.6, center_y_m: 0.0, "
                          "length_m: 0.2, width_m: 0.15, height_m: 0.1}\n"
                          "cart_rail: {start_x_m: 0.1, end_x_m: 0.4, y_m: 0.0, step_m: 0.01}\n";
  const CommandResult r = run_cli("experiment mixed-pixels --scene " + scene.string() + " --out " + dir.string());
  ASSERT_EQ(r.exit_code, 0) << r.output;
  EXPECT_NE(r.output.find("range-clustering"), std::string::npos) << r.output;
  const fs::path out = dir / "mixed-pixels" / "short";
  for (const char* file : {"summary.json", "elevation_unfiltered.png", "elevation_paper_filters.png", "elevation_cas.png"}) {
    EXPECT_TRUE(fs::exists(out / file)) << file;
  }
  std::ifstream in(out / "summary.json");
  const nlohmann::json summary = nlohmann::json::parse(in);
  EXPECT_EQ(summary["experiment"], "mixed-pixels");
  EXPECT_EQ(summary.value("tool_version", "").rfind("stridemap ", 0), 0u) << "the version that made it";
  ASSERT_TRUE(summary["cases"].is_array());
  bool has_ideal = false;
  for (const auto& c : summary["cases"]) {
    EXPECT_TRUE(c["beams"].contains("mixed_recall"));
    EXPECT_TRUE(c["map"].contains("artifact_cells"));
    EXPECT_TRUE(c["map"].contains("mixed_artifact_reduction_pct"));
    has_ideal = has_ideal || c["drops_labelled_mixed"] == true;
  }
  EXPECT_TRUE(has_ideal);
  fs::remove_all(dir);
}

TEST(MixedPixelsCommand, ModelAndFilterOptionsAreCheckedBeforeAnyWork) {
  const std::string scene = std::string(STRIDEMAP_SOURCE_DIR) + "/scenes/cart_rail_boxes.yaml";
  CommandResult r = run_cli("experiment mixed-pixels --scene " + scene + " --out /tmp --texture-log-sigma -1");
  EXPECT_EQ(r.exit_code, 2) << r.output;
  EXPECT_NE(r.output.find("--texture-log-sigma: expected a number from 0 to 5, got '-1'"), std::string::npos) << r.output;
  r = run_cli("experiment mixed-pixels --scene " + scene + " --out /tmp --cluster-max-incidence-deg 95");
  EXPECT_EQ(r.exit_code, 2) << r.output;
  EXPECT_NE(r.output.find("--cluster-max-incidence-deg: expected a number from 0 to 90 deg, got '95'"), std::string::npos)
      << r.output;
}

TEST(CartRailCommand, TheReceiverCouplingIsOnWithMixedPixelsUnlessTurnedOff) {
  const fs::path dir = fs::temp_directory_path() / ("stridemap_cli_coupling_" + std::to_string(::getpid()));
  fs::remove_all(dir);
  const fs::path scene = dir / "short.yaml";
  fs::create_directories(dir);
  std::ofstream(scene) << "terrain: {kind: flat}\nboxes:\n  - {name: box, center_x_m: 0.6, center_y_m: 0.0, "
                          "length_m: 0.2, width_m: 0.15, height_m: 0.1}\n"
                          "cart_rail: {start_x_m: 0.1, end_x_m: 0.4, y_m: 0.0, step_m: 0.01}\n";
  const auto summary_of = [&](const std::string& options, const std::string& name) {
    const CommandResult r = run_cli("experiment cart-rail --scene " + scene.string() + " --out " +
                                    (dir / name).string() + " " + options);
    EXPECT_EQ(r.exit_code, 0) << r.output;
    std::ifstream in(dir / name / "cart-rail-urg" / "summary.json");
    return nlohmann::json::parse(in);
  };
  const nlohmann::json on = summary_of("--mixed-pixels on", "on");
  const nlohmann::json off = summary_of("--mixed-pixels on --coupling off", "off");
  const nlohmann::json ideal = summary_of("--mixed-pixels off", "ideal");
  const nlohmann::json ideal_off = summary_of("--mixed-pixels off --coupling off", "ideal_off");
  EXPECT_EQ(on["coupling"], true);
  EXPECT_EQ(off["coupling"], false);
  EXPECT_EQ(ideal["coupling"], false);  // the single ray takes no coupling
  // The lag moves beams at the box's edges: other readings, other labels.
  EXPECT_NE(on["beam_labels"], off["beam_labels"]);
  EXPECT_EQ(ideal["beam_labels"], ideal_off["beam_labels"]);
  EXPECT_EQ(ideal["map"], ideal_off["map"]);
  fs::remove_all(dir);
}

TEST(CartRailCommand, BadOnOffAndMapFilterValuesAreErrors) {
  const std::string scene = std::string(STRIDEMAP_SOURCE_DIR) + "/scenes/cart_rail_boxes.yaml";
  CommandResult r = run_cli("experiment cart-rail --scene " + scene + " --out /tmp --mixed-pixels maybe");
  EXPECT_EQ(r.exit_code, 2) << r.output;
  EXPECT_NE(r.output.find("--mixed-pixels"), std::string::npos) << r.output;
  r = run_cli("experiment cart-rail --scene " + scene + " --out /tmp --mixed-pixels on --coupling sometimes");
  EXPECT_EQ(r.exit_code, 2) << r.output;
  EXPECT_NE(r.output.find("--coupling"), std::string::npos) << r.output;
  r = run_cli("experiment cart-rail --scene " + scene + " --out /tmp --map-filter blur");
  EXPECT_EQ(r.exit_code, 2) << r.output;
  EXPECT_NE(r.output.find("blur"), std::string::npos) << r.output;
}

}  // namespace
