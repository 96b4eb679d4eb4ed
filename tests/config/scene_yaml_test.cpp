#include "stridemap/config/scene_yaml.hpp"

#include <sstream>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "stridemap/core/error.hpp"
#include "stridemap/core/sensor_transform.hpp"
#include "stridemap/sensors/urg04lx.hpp"
#include "stridemap/sim/cart_rail.hpp"
#include "stridemap/sim/scene_ray_caster.hpp"
#include "test_paths.hpp"

namespace stridemap {
namespace scene_yaml_test {
namespace {

// A valid scene; the tests below break one line of it at a time, so the
// line numbers in the expected messages are the ones on the left.
const std::vector<std::string> base_lines = {
    /*  1 */ "terrain:",
    /*  2 */ "  kind: flat",
    /*  3 */ "  reflectance: 0.5",
    /*  4 */ "boxes:",
    /*  5 */ "  - name: a",
    /*  6 */ "    center_x_m: 1.0",
    /*  7 */ "    center_y_m: 0.0",
    /*  8 */ "    length_m: 0.2",
    /*  9 */ "    width_m: 0.1",
    /* 10 */ "    height_m: 0.1",
    /* 11 */ "cylinders:",
    /* 12 */ "  - name: c",
    /* 13 */ "    center_x_m: 1.5",
    /* 14 */ "    center_y_m: 0.0",
    /* 15 */ "    radius_m: 0.05",
    /* 16 */ "    height_m: 0.12",
    /* 17 */ "cart_rail:",
    /* 18 */ "  start_x_m: 0.0",
    /* 19 */ "  end_x_m: 1.2",
    /* 20 */ "  step_m: 0.01",
};

// The base scene with line `number` replaced by `text` (empty: deleted).
std::string with_line(int number, const std::string& text) {
  std::ostringstream out;
  for (int k = 1; k <= static_cast<int>(base_lines.size()); ++k) {
    if (k != number) {
      out << base_lines[k - 1] << "\n";
    } else if (!text.empty()) {
      out << text << "\n";
    }
  }
  return out.str();
}

std::string error_of(const std::string& text) {
  try {
    parse_scene_yaml(text, "test.yaml");
  } catch (const InputError& error) {
    return error.what();
  }
  return "(no error)";
}

TEST(SceneYaml, ReadsEveryField) {
  const Scene scene = parse_scene_yaml(with_line(0, ""), "test.yaml");
  EXPECT_TRUE(scene.terrain.is_flat());
  ASSERT_EQ(scene.boxes.size(), 1u);
  EXPECT_EQ(scene.boxes[0].name, "a");
  EXPECT_EQ(scene.boxes[0].length_m, 0.2);
  EXPECT_EQ(scene.boxes[0].yaw_rad, 0.0);
  EXPECT_EQ(scene.boxes[0].reflectance, 0.5);
  ASSERT_EQ(scene.cylinders.size(), 1u);
  EXPECT_EQ(scene.cylinders[0].radius_m, 0.05);
  ASSERT_TRUE(scene.cart_rail);
  EXPECT_EQ(scene.cart_rail->end_x_m, 1.2);
  EXPECT_EQ(scene.cart_rail->y_m, 0.0);

  const Scene full = parse_scene_yaml(
      "terrain: {kind: flat, extent: {min_x_m: -2, min_y_m: -3, max_x_m: 4, max_y_m: 5}, base_elevation_m: 0.02,"
      " reflectance: 0.3}\n"
      "boxes:\n"
      "  - {name: turned, center_x_m: 1, center_y_m: 2, base_elevation_m: 0.1, length_m: 0.3, width_m: 0.2,"
      " height_m: 0.1, yaw_rad: 0.5, reflectance: 0.8}\n"
      "cylinders: []\n"
      "cart_rail: {start_x_m: 1, end_x_m: 0, y_m: 0.1, step_m: 0.02, yaw_rad: 3.14}\n",
      "full.yaml");
  EXPECT_EQ(full.terrain.min_y_m, -3.0);
  EXPECT_EQ(full.terrain.max_x_m, 4.0);
  EXPECT_EQ(full.terrain.base_elevation_m, 0.02);
  EXPECT_EQ(full.terrain.reflectance, 0.3);
  EXPECT_EQ(full.boxes[0].base_elevation_m, 0.1);
  EXPECT_EQ(full.boxes[0].yaw_rad, 0.5);
  EXPECT_EQ(full.boxes[0].reflectance, 0.8);
  EXPECT_TRUE(full.cylinders.empty());
  EXPECT_EQ(full.cart_rail->yaw_rad, 3.14);

  const Scene bare = parse_scene_yaml("terrain: {kind: flat}\nboxes:\n", "bare.yaml");
  EXPECT_TRUE(bare.boxes.empty());
  EXPECT_FALSE(bare.cart_rail);
}

TEST(SceneYaml, BadValuesNameFileLineAndField) {
  EXPECT_EQ(error_of(with_line(8, "    length_m: -0.1")),
            "test.yaml:8: boxes[0].length_m: expected a positive number, got -0.1");
  EXPECT_EQ(error_of(with_line(8, "    length_m: 0")), "test.yaml:8: boxes[0].length_m: expected a positive number, got 0");
  EXPECT_EQ(error_of(with_line(8, "    length_m: .nan")),
            "test.yaml:8: boxes[0].length_m: expected a positive number, got nan");
  EXPECT_EQ(error_of(with_line(15, "    radius_m: .inf")),
            "test.yaml:15: cylinders[0].radius_m: expected a positive number, got inf");
  EXPECT_EQ(error_of(with_line(7, "    center_y_m: -.inf")),
            "test.yaml:7: boxes[0].center_y_m: expected a finite number, got -inf");
  EXPECT_EQ(error_of(with_line(3, "  reflectance: 1.5")),
            "test.yaml:3: terrain.reflectance: expected a reflectance in (0, 1], got 1.5");
  EXPECT_EQ(error_of(with_line(16, "    reflectance: 0\n    height_m: 0.12")),
            "test.yaml:16: cylinders[0].reflectance: expected a reflectance in (0, 1], got 0");
  EXPECT_EQ(error_of(with_line(20, "  step_m: 0")), "test.yaml:20: cart_rail.step_m: expected a positive number, got 0");
  EXPECT_EQ(error_of(with_line(12, "  - name: a")),
            "test.yaml:12: cylinders[0].name: duplicate name \"a\" (also boxes[0].name)");
  EXPECT_EQ(error_of(with_line(5, "  - name: \"\"")), "test.yaml:5: boxes[0].name: expected a non-empty name");
}

// Every beam is tested against every object, so the counts are capped like
// the rocks: 10^5 boxes took 314 s and 719 MB before. The list is counted
// before any object in it is read.
TEST(SceneYaml, ObjectCountsAreCappedWithFileAndLine) {
  const auto objects = [](const char* section, std::size_t count, const char* fields) {
    std::string text = "terrain:\n  kind: flat\n  reflectance: 0.5\n" + std::string(section) + ":\n";
    for (std::size_t k = 0; k < count; ++k) text += "  - {name: o" + std::to_string(k) + ", " + fields + "}\n";
    return text;
  };
  const char* box = "center_x_m: 1, center_y_m: 0, length_m: 0.1, width_m: 0.1, height_m: 0.1";
  const char* cylinder = "center_x_m: 1, center_y_m: 0, radius_m: 0.1, height_m: 0.1";
  EXPECT_EQ(parse_scene_yaml(objects("boxes", kMaxSceneBoxes, box), "test.yaml").boxes.size(), kMaxSceneBoxes);
  EXPECT_EQ(error_of(objects("boxes", kMaxSceneBoxes + 1, box)), "test.yaml:5: boxes: expected at most 1000 boxes, got 1001");
  EXPECT_EQ(parse_scene_yaml(objects("cylinders", kMaxSceneCylinders, cylinder), "test.yaml").cylinders.size(),
            kMaxSceneCylinders);
  // Ten times the cap: yaml-cpp reads the whole list before the count is
  // checked, at about 0.1 ms an object in the Release build.
  EXPECT_EQ(error_of(objects("cylinders", 10 * kMaxSceneCylinders, cylinder)),
            "test.yaml:5: cylinders: expected at most 1000 cylinders, got 10000");
}

TEST(SceneYaml, BoxesComeAndGo) {
  const std::string text =
      "terrain: {kind: flat, extent: {min_x_m: -1, min_y_m: -1, max_x_m: 1, max_y_m: 1}}\n"
      "boxes:\n"
      "  - {name: always, center_x_m: 0, center_y_m: 0, length_m: 0.1, width_m: 0.1, height_m: 0.1}\n"
      "  - {name: gone, center_x_m: 0.5, center_y_m: 0, length_m: 0.1, width_m: 0.1, height_m: 0.1,\n"
      "     present_until_s: 2.0}\n"
      "  - {name: step, center_x_m: -0.5, center_y_m: 0, length_m: 0.1, width_m: 0.1, height_m: 0.1,\n"
      "     present_from_s: 1.0, present_until_s: 1.5}\n";
  const Scene scene = parse_scene_yaml(text, "test.yaml");
  EXPECT_TRUE(scene.changes_over_time());
  const auto names = [](const Scene& s) {
    std::string out;
    for (const BoxObject& b : s.boxes) out += b.name + " ";
    return out;
  };
  EXPECT_EQ(names(scene.at_time(0.0)), "always gone ");
  EXPECT_EQ(names(scene.at_time(1.0)), "always gone step ");
  EXPECT_EQ(names(scene.at_time(1.5)), "always gone ");
  EXPECT_EQ(names(scene.at_time(2.0)), "always ");
  EXPECT_FALSE(scene.at_time(2.0).changes_over_time());
  std::string bad = text;
  bad.replace(bad.find("present_from_s: 1.0"), 19, "present_from_s: 1.6");
  EXPECT_NE(error_of(bad).find("test.yaml:7: boxes[2].present_until_s: expected a time after present_from_s "
                              "(1.600000 s), got 1.500000 s"),
            std::string::npos)
      << error_of(bad);
}

TEST(SceneYaml, WrongTypesAndMissingFields) {
  EXPECT_EQ(error_of(with_line(8, "    length_m: abc")), "test.yaml:8: boxes[0].length_m: expected a number, got \"abc\"");
  EXPECT_EQ(error_of(with_line(8, "    length_m: \"0.2\"")),
            "test.yaml:8: boxes[0].length_m: expected a number, got the quoted text \"0.2\"");
  EXPECT_EQ(error_of(with_line(8, "    length_m: [1, 2]")), "test.yaml:8: boxes[0].length_m: expected a number, got a list");
  EXPECT_EQ(error_of(with_line(8, "    length_m:")), "test.yaml:8: boxes[0].length_m: expected a number, got nothing");
  EXPECT_EQ(error_of(with_line(8, "")), "test.yaml:5: boxes[0].length_m: required field is missing");
  EXPECT_EQ(error_of(with_line(5, "  - center_z_m: 1")),
            "test.yaml:5: boxes[0].center_z_m: unknown field (expected one of: name, center_x_m, center_y_m, "
            "base_elevation_m, length_m, width_m, height_m, yaw_rad, reflectance, present_from_s, present_until_s)");
  EXPECT_EQ(error_of(with_line(12, "  - base_elevation_m: 0.0")), "test.yaml:12: cylinders[0].name: required field is missing");
  EXPECT_EQ(error_of(with_line(5, "  - name: [x]")), "test.yaml:5: boxes[0].name: expected a text, got a list");
  EXPECT_EQ(error_of("terrain: {kind: flat}\nboxes: 3\n"), "test.yaml:2: boxes: expected a list, got \"3\"");
  EXPECT_EQ(error_of("terrain: {kind: flat}\ncart_rail: [1]\n"),
            "test.yaml:2: cart_rail: expected a map of fields, got a list");
  EXPECT_EQ(error_of("terrain: {kind: flat}\ncylinders: [7]\n"),
            "test.yaml:2: cylinders[0]: expected a map of fields, got \"7\"");
  EXPECT_EQ(error_of("boxes: []\n"), "test.yaml:1: terrain: required section is missing");
  EXPECT_EQ(error_of(""), "test.yaml:1: expected a scene (a map with terrain, boxes, cylinders, cart_rail, walk_path), got nothing");
  EXPECT_EQ(error_of("- 1\n- 2\n"), "test.yaml:1: expected a scene (a map with terrain, boxes, cylinders, cart_rail, walk_path), got a list");
}

TEST(SceneYaml, TyposAndRepeatsAreErrors) {
  EXPECT_EQ(error_of(with_line(8, "    lenght_m: 0.2")).substr(0, 47), "test.yaml:8: boxes[0].lenght_m: unknown field (");
  EXPECT_EQ(error_of(with_line(1, "terain:")),
            "test.yaml:1: terain: unknown field (expected one of: terrain, boxes, cylinders, cart_rail, walk_path)");
  EXPECT_EQ(error_of(with_line(9, "    width_m: 0.1\n    width_m: 0.2")),
            "test.yaml:10: boxes[0].width_m: appears twice (first on line 9)");
  EXPECT_EQ(error_of(with_line(2, "  kind: hilly")), "test.yaml:2: terrain.kind: expected flat or procedural, got \"hilly\"");
  EXPECT_EQ(error_of(with_line(2, "  kind: flat\n  seed: 3")), "test.yaml:3: terrain.seed: only allowed with kind: procedural");
  EXPECT_EQ(error_of(with_line(2, "")), "test.yaml:2: terrain.kind: required field is missing (flat or procedural)");
  EXPECT_EQ(error_of("terrain: {kind: flat}\n---\nterrain: {kind: flat}\n"),
            "test.yaml:3: expected one YAML document, found 2");
  const std::string broken = error_of("terrain: {kind: flat\nboxes: []\n");
  EXPECT_EQ(broken.rfind("test.yaml:", 0), 0u) << broken;
  EXPECT_NE(broken.find("not valid YAML"), std::string::npos) << broken;
}

const char* procedural_scene =
    "terrain:\n"
    "  kind: procedural\n"
    "  extent: {min_x_m: 0, min_y_m: -0.5, max_x_m: 1, max_y_m: 0.5}\n"
    "  seed: 12\n"
    "  amplitude_m: 0.03\n"
    "  wavelength_m: 0.25\n"
    "  resolution_m: 0.01\n";

std::string procedural_with(const std::string& from, const std::string& to) {
  std::string text = procedural_scene;
  const auto at = text.find(from);
  EXPECT_NE(at, std::string::npos) << from;
  return text.replace(at, from.size(), to);
}

TEST(SceneYaml, ProceduralTerrain) {
  const Scene a = parse_scene_yaml(procedural_scene, "p.yaml");
  const Scene b = parse_scene_yaml(procedural_scene, "p.yaml");
  const Scene c = parse_scene_yaml(procedural_with("seed: 12", "seed: 13"), "p.yaml");
  EXPECT_FALSE(a.terrain.is_flat());
  EXPECT_EQ(a.terrain.nx, 101);
  EXPECT_EQ(a.terrain.ny, 101);
  EXPECT_EQ(a.terrain.samples, b.terrain.samples);
  EXPECT_NE(a.terrain.samples, c.terrain.samples);
  EXPECT_NO_THROW(a.validate());

  EXPECT_EQ(error_of(procedural_with("  seed: 12\n", "")), "test.yaml:2: terrain.seed: required field is missing");
  EXPECT_EQ(error_of(procedural_with("seed: 12", "seed: -3")),
            "test.yaml:4: terrain.seed: expected a whole number >= 0, got \"-3\"");
  EXPECT_EQ(error_of(procedural_with("seed: 12", "seed: 1.5")),
            "test.yaml:4: terrain.seed: expected a whole number >= 0, got \"1.5\"");
  EXPECT_EQ(error_of(procedural_with("  seed: 12\n", "  seed: 12\n  octaves: 9\n")),
            "test.yaml:5: terrain.octaves: expected a whole number from 1 to 8, got 9");
  EXPECT_EQ(error_of(procedural_with("amplitude_m: 0.03", "amplitude_m: -0.03")),
            "test.yaml:5: terrain.amplitude_m: expected a number >= 0, got -0.03");
  EXPECT_EQ(error_of(procedural_with("max_x_m: 1", "max_x_m: -1")),
            "test.yaml:3: terrain.extent.max_x_m: expected a number greater than min_x_m = 0, got -1");
  EXPECT_EQ(error_of(procedural_with("extent: {min_x_m: 0, ", "extent: {")),
            "test.yaml:3: terrain.extent.min_x_m: required field is missing");
  const std::string too_fine = error_of(procedural_with("resolution_m: 0.01", "resolution_m: 0.00001"));
  EXPECT_EQ(too_fine.rfind("test.yaml:7: terrain.resolution_m: gives", 0), 0u) << too_fine;
}

TEST(SceneYaml, UnreadableFile) {
  try {
    load_scene_yaml("/nonexistent/scene.yaml");
    FAIL() << "expected InputError";
  } catch (const InputError& error) {
    EXPECT_STREQ(error.what(), "/nonexistent/scene.yaml: cannot read scene file: No such file or directory");
  }
}

TEST(ShippedScene, CartRailBoxesMatchesThePaperSetUp) {
  const Scene scene = load_scene_yaml(std::string(STRIDEMAP_SOURCE_DIR) + "/scenes/cart_rail_boxes.yaml");
  EXPECT_TRUE(scene.terrain.is_flat());
  ASSERT_EQ(scene.boxes.size(), 2u);
  ASSERT_EQ(scene.cylinders.size(), 1u);
  ASSERT_TRUE(scene.cart_rail);
  EXPECT_EQ(scene.cart_rail->start_x_m, 0.0);
  EXPECT_EQ(scene.cart_rail->step_m, 0.01);
  for (const BoxObject& box : scene.boxes) {
    EXPECT_GE(box.center_x_m - box.length_m / 2, 0.6) << box.name;
    EXPECT_LE(box.center_x_m + box.length_m / 2, 1.5) << box.name;
    EXPECT_LE(std::abs(box.center_y_m) + box.width_m / 2, 0.25) << box.name;
    EXPECT_GE(box.reflectance, 0.3);
    EXPECT_LE(box.reflectance, 0.8);
  }
  const CylinderObject& can = scene.cylinders[0];
  EXPECT_GE(can.center_x_m - can.radius_m, 0.6);
  EXPECT_LE(can.center_x_m + can.radius_m, 1.5);

  // From the paper's mount, every object's top is seen along the rail.
  const SceneRayCaster caster(scene);
  const UrgParameters params;
  const SensorMount mount;  // 0.26 m, 35 deg
  std::vector<int> top_hits(scene.boxes.size() + scene.cylinders.size(), 0);
  for (const TrunkPose& pose : cart_rail_poses(*scene.cart_rail)) {
    const Eigen::Matrix3d rotation = sensor_to_map_rotation(pose, mount);
    const Eigen::Vector3d origin = sensor_origin_in_map(pose, mount);
    for (int step = params.first_step; step <= params.last_step; ++step) {
      const double t = params.step_angle_rad(step);
      const auto hit = caster.cast(origin, std::cos(t) * rotation.col(0) + std::sin(t) * rotation.col(1), 4.0);
      if (hit && hit->object_index >= 0 && hit->normal.z() > 0.99) ++top_hits[hit->object_index];
    }
  }
  for (std::size_t k = 0; k < top_hits.size(); ++k) EXPECT_GT(top_hits[k], 100) << "object " << k;
}

}  // namespace
}  // namespace scene_yaml_test
}  // namespace stridemap
