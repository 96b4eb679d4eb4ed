#include "stridemap/config/walk_path_yaml.hpp"

#include <cmath>
#include <numbers>
#include <string>

#include <gtest/gtest.h>

#include "stridemap/config/scene_yaml.hpp"
#include "stridemap/core/error.hpp"
#include "test_paths.hpp"

namespace stridemap {
namespace walk_path_yaml_test {
namespace {

std::string error_of(const std::string& text, const HeightField* terrain = nullptr) {
  try {
    parse_walk_path_yaml(text, "path.yaml", terrain);
  } catch (const InputError& e) {
    return e.what();
  }
  return "";
}

TEST(WalkPathYaml, ReadsStartAndSegments) {
  const WalkPath path = parse_walk_path_yaml(
      "walk_path:\n"
      "  start: {x_m: 0.2, y_m: -0.3, yaw_deg: 90}\n"
      "  segments:\n"
      "    - straight_m: 0.5\n"
      "    - turn_deg: -45\n"
      "    - {turn_deg: 30, radius_m: 0.4}\n",
      "path.yaml");
  EXPECT_DOUBLE_EQ(path.start_x_m, 0.2);
  EXPECT_DOUBLE_EQ(path.start_y_m, -0.3);
  EXPECT_NEAR(path.start_yaw_rad, std::numbers::pi / 2, 1e-12);
  ASSERT_EQ(path.segments.size(), 3u);
  EXPECT_EQ(path.segments[0].kind, WalkSegment::Kind::straight);
  EXPECT_DOUBLE_EQ(path.segments[0].length_m, 0.5);
  EXPECT_NEAR(path.segments[1].turn_rad, -std::numbers::pi / 4, 1e-12);
  EXPECT_DOUBLE_EQ(path.segments[1].radius_m, 0.0);
  EXPECT_DOUBLE_EQ(path.segments[2].radius_m, 0.4);
}

TEST(WalkPathYaml, ErrorsNameFileLineAndField) {
  const std::string head = "walk_path:\n  segments:\n";
  EXPECT_EQ(error_of(head + "    - straight_m: 0.5\n    - straight_m: -1\n"),
            "path.yaml:4: walk_path.segments[1].straight_m: expected a positive number, got -1");
  EXPECT_NE(error_of(head + "    - {straight_m: 0.5, turn_deg: 10}\n").find("path.yaml:3: walk_path.segments[0]: expected exactly one"),
            std::string::npos);
  EXPECT_NE(error_of(head + "    - {straight_m: 0.5, radius_m: 0.1}\n").find("radius_m: only allowed with turn_deg"),
            std::string::npos);
  EXPECT_NE(error_of(head + "    - {turn_deg: 10, radius: 0.1}\n").find("path.yaml:3: walk_path.segments[0].radius: unknown field"),
            std::string::npos);
  EXPECT_NE(error_of(head + "    - turn_deg: 0\n").find("path.yaml:3: walk_path.segments[0].turn_deg"), std::string::npos);
  EXPECT_NE(error_of(head + "    - {turn_deg: 10, radius_m: -0.1}\n").find("radius_m: expected a number >= 0"),
            std::string::npos);
  EXPECT_NE(error_of("walk_path:\n  start: {x_m: 0}\n  segments: [{straight_m: 1}]\n").find("path.yaml:2: walk_path.start.y_m: required"),
            std::string::npos);
  EXPECT_NE(error_of("walk_path:\n  segments: []\n").find("expected at least one segment"), std::string::npos);
  EXPECT_NE(error_of("other: 1\n").find("path.yaml:1: other: unknown field"), std::string::npos);
  EXPECT_NE(error_of("walk_path:\n  segments:\n    - straight_m: \"1\"\n").find("quoted"), std::string::npos);
}

TEST(WalkPathYaml, APathLeavingTheSceneIsReportedAtItsSegment) {
  HeightField terrain;  // x -1..3, y -1..1
  const std::string text = "walk_path:\n  segments:\n    - straight_m: 1.0\n    - turn_deg: 90\n    - straight_m: 2.0\n";
  EXPECT_NE(error_of(text, &terrain).find("path.yaml:5: walk_path.segments[2]: the path leaves the scene's terrain extent"),
            std::string::npos)
      << error_of(text, &terrain);
  EXPECT_EQ(error_of(text), "");  // without a terrain only the path itself is checked
}

TEST(WalkPathYaml, ScenesCarryAPathAndRocks) {
  const Scene scene = parse_scene_yaml(
      "terrain:\n"
      "  kind: procedural\n"
      "  seed: 3\n"
      "  extent: {min_x_m: 0, min_y_m: -1, max_x_m: 2, max_y_m: 1}\n"
      "  amplitude_m: 0.01\n"
      "  wavelength_m: 0.5\n"
      "  rocks_area: {min_x_m: 1.0, min_y_m: -0.5, max_x_m: 1.5, max_y_m: 0.5}\n"
      "  rocks:\n"
      "    - {count: 2, min_radius_m: 0.1, max_radius_m: 0.2, min_height_m: 0.05, max_height_m: 0.08}\n"
      "walk_path:\n"
      "  start: {x_m: 0.2, y_m: 0.0}\n"
      "  segments: [{straight_m: 1.0}]\n",
      "scene.yaml");
  ASSERT_TRUE(scene.walk_path);
  EXPECT_DOUBLE_EQ(scene.walk_path->start_x_m, 0.2);
  EXPECT_GT(scene.terrain.max_sample_height_m(), 0.05);

  const auto scene_error = [](const std::string& text) {
    try {
      parse_scene_yaml(text, "scene.yaml");
    } catch (const InputError& e) {
      return std::string(e.what());
    }
    return std::string();
  };
  const std::string flat = "terrain:\n  kind: flat\n";
  EXPECT_NE(scene_error(flat + "walk_path:\n  segments: [{straight_m: 9}]\n").find("scene.yaml:4: walk_path.segments[0]: the path leaves"),
            std::string::npos)
      << scene_error(flat + "walk_path:\n  segments: [{straight_m: 9}]\n");
  EXPECT_NE(scene_error(flat + "  rocks: []\n").find("only allowed with kind: procedural"), std::string::npos);
  EXPECT_NE(scene_error("terrain:\n  kind: procedural\n  seed: 1\n  amplitude_m: 0.01\n  wavelength_m: 0.5\n  rocks:\n"
                        "    - {count: 1, min_radius_m: 0.2, max_radius_m: 0.1, min_height_m: 0.01, max_height_m: 0.02}\n")
                .find("scene.yaml:7: terrain.rocks[0].max_radius_m"),
            std::string::npos);
}

TEST(WalkPathYaml, TheShippedMockUpLoadsWithItsPath) {
  const Scene scene = load_scene_yaml(std::string(STRIDEMAP_SOURCE_DIR) + "/scenes/rocky_mockup.yaml");
  ASSERT_TRUE(scene.walk_path);
  EXPECT_DOUBLE_EQ(scene.terrain.max_x_m - scene.terrain.min_x_m, 2.0);
  EXPECT_DOUBLE_EQ(scene.terrain.max_y_m - scene.terrain.min_y_m, 2.0);
  // Rocks of several sizes, all climbable (section 4.2: up to +0.15 m).
  EXPECT_GT(scene.terrain.max_sample_height_m(), 0.08);
  EXPECT_LT(scene.terrain.max_sample_height_m(), 0.15);
  EXPECT_THROW(load_walk_path_yaml(std::string(STRIDEMAP_SOURCE_DIR) + "/scenes/missing.yaml"), InputError);
}

}  // namespace
}  // namespace walk_path_yaml_test
}  // namespace stridemap
