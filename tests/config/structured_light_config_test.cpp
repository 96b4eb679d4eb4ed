// Structured-light configurations: the shipped presets, and every kind of
// bad input with the exact place and reason in the message.
#include <gtest/gtest.h>

#include <cmath>
#include <numbers>
#include <string>

#include "stridemap/config/structured_light_config.hpp"
#include "stridemap/core/error.hpp"
#include "test_paths.hpp"

namespace stridemap {
namespace structured_light_config_test {
namespace {

constexpr double kDeg = std::numbers::pi / 180.0;

const std::string kValid =
    "structured_light:\n"            // 1
    "  baseline_m: 0.120\n"          // 2
    "  sheet_angle_deg: 45\n"        // 3
    "  image_width_px: 640\n"        // 4
    "  image_height_px: 480\n"       // 5
    "  half_fov_vertical_deg: 28.14\n"    // 6
    "  half_fov_horizontal_deg: 38.8\n";  // 7

std::string error_of(const std::string& text) {
  try {
    parse_structured_light_config(text, "sl.yaml");
  } catch (const InputError& e) {
    return e.what();
  }
  return "(accepted)";
}

std::string replaced(std::string text, const std::string& from, const std::string& to) {
  const auto at = text.find(from);
  EXPECT_NE(at, std::string::npos) << from;
  return text.replace(at, from.size(), to);
}

TEST(StructuredLightConfig, RagnoPreset) {
  const StructuredLightConfig config =
      load_structured_light_config(std::string(STRIDEMAP_SOURCE_DIR) + "/configs/ragno_structured_light.yaml");
  const StructuredLightParameters& p = config.parameters;
  EXPECT_TRUE(config.has_mount);
  EXPECT_DOUBLE_EQ(p.baseline_m, 0.120);
  EXPECT_NEAR(p.sheet_angle_rad, 45.0 * kDeg, 1e-15);
  EXPECT_NEAR(p.half_fov_vertical_rad, 28.14 * kDeg, 1e-15);
  EXPECT_NEAR(p.half_fov_horizontal_rad, 38.8 * kDeg, 1e-15);
  EXPECT_EQ(p.image_width_px, 640);
  EXPECT_EQ(p.image_height_px, 480);
  EXPECT_NEAR(p.mount.pitch_rad, 10.0 * kDeg, 1e-15);
  EXPECT_DOUBLE_EQ(p.mount.height_m, 0.174);
  EXPECT_DOUBLE_EQ(p.row_error_px, 0.5);
  EXPECT_NEAR(p.sheet_angle_error_rad, 0.25 * kDeg, 1e-15);
}

TEST(StructuredLightConfig, Fig3PresetHasNoMount) {
  const StructuredLightConfig config =
      load_structured_light_config(std::string(STRIDEMAP_SOURCE_DIR) + "/configs/fig3_structured_light.yaml");
  EXPECT_FALSE(config.has_mount);
  EXPECT_DOUBLE_EQ(config.parameters.baseline_m, 0.100);
  EXPECT_NEAR(config.parameters.sheet_angle_rad, 70.0 * kDeg, 1e-15);
  EXPECT_NEAR(config.parameters.half_fov_vertical_rad, 19.1 * kDeg, 1e-15);
}

TEST(StructuredLightConfig, FocalLengthInsteadOfAngles) {
  const std::string text =
      "structured_light: {baseline_m: 0.1, sheet_angle_deg: 70, image_width_px: 640, image_height_px: 480,"
      " focal_length_px: 693}\n";
  const StructuredLightConfig config = parse_structured_light_config(text, "f.yaml");
  EXPECT_NEAR(config.parameters.half_fov_vertical_rad, std::atan(480.0 / (2.0 * 693.0)), 1e-15);
  EXPECT_NEAR(config.parameters.half_fov_horizontal_rad, std::atan(640.0 / (2.0 * 693.0)), 1e-15);
  EXPECT_EQ(error_of(replaced(text, "693", "-5")),
            "sl.yaml:1: structured_light.focal_length_px: must be a positive number of pixels, got \"-5\"");
  EXPECT_EQ(error_of(kValid + "  focal_length_px: 693\n"),
            "sl.yaml:2: structured_light.focal_length_px: give either focal_length_px or half_fov_vertical_deg and "
            "half_fov_horizontal_deg, not both");
}

TEST(StructuredLightConfig, MountAndErrorsSections) {
  const StructuredLightConfig config = parse_structured_light_config(
      kValid + "mount:\n  pitch_deg: 12\n  height_m: 0.2\n  forward_offset_m: 0.05\nerrors:\n  row_px: 0.25\n",
      "m.yaml");
  EXPECT_TRUE(config.has_mount);
  EXPECT_NEAR(config.parameters.mount.pitch_rad, 12.0 * kDeg, 1e-15);
  EXPECT_DOUBLE_EQ(config.parameters.mount.forward_offset_m, 0.05);
  EXPECT_DOUBLE_EQ(config.parameters.mount.lateral_offset_m, 0.0);
  EXPECT_EQ(config.parameters.mount.roll_rad, 0.0);
  EXPECT_EQ(config.parameters.mount.yaw_rad, 0.0);
  EXPECT_DOUBLE_EQ(config.parameters.row_error_px, 0.25);
  const StructuredLightConfig turned = parse_structured_light_config(
      kValid + "mount: {pitch_deg: 12, height_m: 0.2, roll_deg: 5, yaw_deg: -10}\n", "m.yaml");
  EXPECT_NEAR(turned.parameters.mount.roll_rad, 5.0 * kDeg, 1e-15);
  EXPECT_NEAR(turned.parameters.mount.yaw_rad, -10.0 * kDeg, 1e-15);
  EXPECT_NE(error_of(kValid + "mount: {pitch_deg: 12, height_m: 0.2, yaw_deg: .inf}\n").find("sl.yaml:8: mount.yaw_deg"),
            std::string::npos);
  EXPECT_DOUBLE_EQ(config.parameters.baseline_error_m, StructuredLightParameters{}.baseline_error_m);
}

TEST(StructuredLightConfig, MissingFields) {
  EXPECT_EQ(error_of(replaced(kValid, "  baseline_m: 0.120\n", "")),
            "sl.yaml:2: structured_light.baseline_m: required field is missing");
  EXPECT_EQ(error_of("mount: {pitch_deg: 1, height_m: 0.1}\n"),
            "sl.yaml:1: structured_light: required section is missing");
  EXPECT_EQ(error_of(kValid + "mount:\n  pitch_deg: 10\n"), "sl.yaml:9: mount.height_m: required field is missing");
  EXPECT_EQ(error_of(replaced(kValid, "  half_fov_horizontal_deg: 38.8\n", "")),
            "sl.yaml:2: structured_light.half_fov_horizontal_deg: required field is missing");
  EXPECT_EQ(error_of(""), "sl.yaml:1: expected a structured-light configuration (a map with structured_light, mount, "
                          "errors), got nothing");
}

TEST(StructuredLightConfig, WrongTypes) {
  EXPECT_EQ(error_of(replaced(kValid, "0.120", "twelve")),
            "sl.yaml:2: structured_light.baseline_m: expected a number, got \"twelve\"");
  EXPECT_EQ(error_of(replaced(kValid, "0.120", "[0.1, 0.2]")),
            "sl.yaml:2: structured_light.baseline_m: expected a number, got a list");
  EXPECT_EQ(error_of(replaced(kValid, "0.120", "\"0.12\"")),
            "sl.yaml:2: structured_light.baseline_m: expected a number, got the quoted text \"0.12\"");
  EXPECT_EQ(error_of(replaced(kValid, "640", "640.5")),
            "sl.yaml:4: structured_light.image_width_px: expected a whole number of pixels, got \"640.5\"");
  EXPECT_EQ(error_of(replaced(kValid, "  baseline_m: 0.120\n", "  baseline_m:\n")),
            "sl.yaml:2: structured_light.baseline_m: expected a number, got nothing");
  EXPECT_EQ(error_of("structured_light: 3\n"), "sl.yaml:1: structured_light: expected a map of fields, got \"3\"");
}

TEST(StructuredLightConfig, UnusableValues) {
  EXPECT_EQ(error_of(replaced(kValid, "0.120", "-0.12")),
            "sl.yaml:2: structured_light.baseline_m: must be a positive number of metres up to 10 (is it in "
            "millimetres?), got -0.12");
  EXPECT_EQ(error_of(replaced(kValid, "0.120", "1e308")),
            "sl.yaml:2: structured_light.baseline_m: must be a positive number of metres up to 10 (is it in "
            "millimetres?), got 1e+308");
  EXPECT_EQ(error_of(replaced(kValid, "sheet_angle_deg: 45", "sheet_angle_deg: 95")),
            "sl.yaml:3: structured_light.sheet_angle_deg: must lie strictly between 0 and 90 deg, got 95 deg");
  EXPECT_EQ(error_of(replaced(kValid, "sheet_angle_deg: 45", "sheet_angle_deg: 0")),
            "sl.yaml:3: structured_light.sheet_angle_deg: must lie strictly between 0 and 90 deg, got 0 deg");
  EXPECT_EQ(error_of(replaced(kValid, "28.14", ".nan")),
            "sl.yaml:6: structured_light.half_fov_vertical_deg: must lie strictly between 0 and 90 deg, got nan deg");
  EXPECT_EQ(error_of(replaced(kValid, "480", "0")),
            "sl.yaml:5: structured_light.image_height_px: must be a whole number of pixels from 1 to 1000000, got 0");
  EXPECT_EQ(error_of(kValid + "mount: {pitch_deg: 90, height_m: 0.1}\n"),
            "sl.yaml:8: mount.pitch_deg: must lie strictly between -90 and 90 deg, got 90 deg");
  EXPECT_EQ(error_of(kValid + "errors:\n  row_px: -1\n"), "sl.yaml:9: errors.row_px: must be a number >= 0, got -1 px");
  EXPECT_EQ(error_of(kValid + "errors:\n  sheet_angle_deg: -0.5\n"),
            "sl.yaml:9: errors.sheet_angle_deg: must be a number >= 0, got -0.5 deg");
}

TEST(StructuredLightConfig, UnknownAndRepeatedKeys) {
  EXPECT_EQ(error_of(replaced(kValid, "  baseline_m:", "  baseline:")),
            "sl.yaml:2: structured_light.baseline: unknown field (expected one of: baseline_m, sheet_angle_deg, "
            "image_width_px, image_height_px, half_fov_vertical_deg, half_fov_horizontal_deg, focal_length_px)");
  EXPECT_EQ(error_of(kValid + "camera: {}\n"),
            "sl.yaml:8: camera: unknown field (expected one of: structured_light, mount, errors)");
  EXPECT_EQ(error_of(kValid + "  baseline_m: 0.1\n"),
            "sl.yaml:8: structured_light.baseline_m: appears twice (first on line 2)");
  EXPECT_EQ(error_of(kValid + "mount: {pitch: 10, height_m: 0.1}\n"),
            "sl.yaml:8: mount.pitch: unknown field (expected one of: pitch_deg, height_m, forward_offset_m, "
            "lateral_offset_m, roll_deg, yaw_deg)");
}

TEST(StructuredLightConfig, UnreadableFiles) {
  EXPECT_EQ(error_of("structured_light: [1, 2\n").rfind("sl.yaml:", 0), 0u);
  EXPECT_NE(error_of("structured_light: [1, 2\n").find("not valid YAML"), std::string::npos);
  try {
    load_structured_light_config("/nonexistent/sl.yaml");
    FAIL() << "read a missing file";
  } catch (const InputError& e) {
    EXPECT_EQ(std::string(e.what()),
              "/nonexistent/sl.yaml: cannot read structured-light config: No such file or directory");
  }
}

}  // namespace
}  // namespace structured_light_config_test
}  // namespace stridemap
