#include "stridemap/config/mapper_config.hpp"

#include <cmath>
#include <string>

#include <gtest/gtest.h>

#include "stridemap/core/error.hpp"
#include "test_paths.hpp"

namespace stridemap {
namespace mapper_config_test {
namespace {

std::string error_of(const std::string& text) {
  try {
    parse_mapper_config(text, "robot.yaml");
  } catch (const InputError& e) {
    return e.what();
  }
  return "no error";
}

TEST(MapperConfig, ShippedMessorConfigIsTheDefaults) {
  const MapperConfig c = load_mapper_config(std::string(STRIDEMAP_SOURCE_DIR) + "/configs/urg_messor.yaml");
  const MapperConfig d;
  EXPECT_DOUBLE_EQ(c.mount.height_m, d.mount.height_m);
  EXPECT_NEAR(c.mount.pitch_rad, d.mount.pitch_rad, 1e-12);
  EXPECT_EQ(c.mount.roll_rad, 0.0);
  EXPECT_EQ(c.mount.yaw_rad, 0.0);
  EXPECT_EQ(c.mapper.grid.cells_per_side, 100);
  EXPECT_DOUBLE_EQ(c.mapper.grid.cell_size_m, 0.01);
  EXPECT_EQ(c.mapper.reject_stale_scans, d.mapper.reject_stale_scans);
  EXPECT_NEAR(c.mapper.update.max_pitch_error_rad, d.mapper.update.max_pitch_error_rad, 1e-12);
  EXPECT_EQ(c.mapper.update.elevation_rule, ElevationRule::paper_highest);
  EXPECT_EQ(c.fill.min_known_neighbours, 8);
  EXPECT_EQ(c.calibration.coefficients[3], 0.0);
  EXPECT_EQ(c.height_fusion.enabled, d.height_fusion.enabled);
  EXPECT_EQ(c.height_fusion.mahalanobis_gate, d.height_fusion.mahalanobis_gate);
  EXPECT_EQ(c.height_fusion.outlier_variance_m2, d.height_fusion.outlier_variance_m2);
  EXPECT_EQ(c.height_fusion.min_variance_m2, d.height_fusion.min_variance_m2);
  EXPECT_EQ(c.height_fusion.sigma_per_uncertainty, d.height_fusion.sigma_per_uncertainty);
}

TEST(MapperConfig, FieldsOverrideDefaultsAndDegreesBecomeRadians) {
  const MapperConfig c = parse_mapper_config(
      "mount: {pitch_deg: 20, height_m: 0.16}\nupdate: {elevation_rule: gated}\n"
      "range_calibration: {coefficients: [0.001, -0.01, 0.002, 0]}\n",
      "x.yaml");
  EXPECT_NEAR(c.mount.pitch_rad, 20.0 * std::acos(-1.0) / 180.0, 1e-12);
  EXPECT_DOUBLE_EQ(c.mount.height_m, 0.16);
  EXPECT_EQ(c.mapper.update.elevation_rule, ElevationRule::gated_highest);
  EXPECT_DOUBLE_EQ(c.calibration.coefficients[1], -0.01);
  EXPECT_EQ(parse_mapper_config("", "empty.yaml").mapper.grid.cells_per_side, 100);
  EXPECT_FALSE(parse_mapper_config("map: {reject_stale_scans: false}\n", "x.yaml").mapper.reject_stale_scans);
  EXPECT_FALSE(parse_mapper_config("", "empty.yaml").foothold.update_every_scan);
  EXPECT_TRUE(parse_mapper_config("foothold: {update_every_scan: true}\n", "x.yaml").foothold.update_every_scan);
}

TEST(MapperConfig, ErrorsNameFileLineAndField) {
  EXPECT_EQ(error_of("map:\n  cell_size_m: -0.01\n"), "robot.yaml:2: map.cell_size_m: expected a cell size from 0.0001 to 10 m, got -0.010000");
  EXPECT_EQ(error_of("map:\n  cells_per_side: many\n"),
            "robot.yaml:2: map.cells_per_side: expected a whole number >= 0, got \"many\"");
  EXPECT_NE(error_of("mount:\n  heigth_m: 0.2\n").find("robot.yaml:2: mount.heigth_m: unknown field"), std::string::npos);
  EXPECT_NE(error_of("mount:\n  pitch_deg: 95\n").find("robot.yaml:2: mount.pitch_deg: expected a pitch strictly"),
            std::string::npos);
  EXPECT_NE(error_of("update:\n  elevation_rule: newest\n").find("robot.yaml:2: update.elevation_rule: 'newest' is not an elevation rule; expected one of: paper, gated"),
            std::string::npos);
  EXPECT_NE(error_of("range_calibration: {}\n").find("range_calibration.coefficients: required field is missing"),
            std::string::npos);
  EXPECT_NE(error_of("range_calibration:\n  coefficients: [1, 2, x, 4]\n").find("coefficients[2]: expected a number"),
            std::string::npos);
  EXPECT_NE(error_of("fill:\n  min_quadrants: 5\n").find("robot.yaml:2: fill.min_quadrants"), std::string::npos);
  EXPECT_NE(error_of("update:\n  certainty_max: 1\n").find("update.certainty_max: expected a number >= certainty_increment"),
            std::string::npos);
  EXPECT_NE(error_of("update: [1, 2]\n").find("robot.yaml:1: update: expected a map of fields"), std::string::npos);
  EXPECT_NE(error_of("map: {follow_robot: yes please}\n").find("map.follow_robot: expected true or false"),
            std::string::npos);
  EXPECT_NE(error_of("map: {cell_size_m: .nan}\n").find("map.cell_size_m"), std::string::npos);
  EXPECT_NE(error_of("a: [\n").find("robot.yaml:"), std::string::npos);
}

TEST(MapperConfig, MountTakesTheRigidTransformKeys) {
  const MapperConfig c = parse_mapper_config(
      "mount: {x_m: 0.12, y_m: -0.03, z_m: -0.05, roll_deg: 5, pitch_deg: 30, yaw_deg: -10}\n", "x.yaml");
  const double deg = std::acos(-1.0) / 180.0;
  EXPECT_DOUBLE_EQ(c.mount.forward_offset_m, 0.12);
  EXPECT_DOUBLE_EQ(c.mount.lateral_offset_m, -0.03);
  EXPECT_DOUBLE_EQ(c.mount.height_m, -0.05);  // below the trunk reference point: allowed as z_m
  EXPECT_NEAR(c.mount.roll_rad, 5 * deg, 1e-15);
  EXPECT_NEAR(c.mount.pitch_rad, 30 * deg, 1e-15);
  EXPECT_NEAR(c.mount.yaw_rad, -10 * deg, 1e-15);
  // The old keys mean the same quantities.
  const MapperConfig old = parse_mapper_config(
      "mount: {forward_offset_m: 0.12, lateral_offset_m: -0.03, height_m: 0.2}\n", "x.yaml");
  EXPECT_DOUBLE_EQ(old.mount.forward_offset_m, 0.12);
  EXPECT_DOUBLE_EQ(old.mount.lateral_offset_m, -0.03);
  EXPECT_DOUBLE_EQ(old.mount.height_m, 0.2);
  EXPECT_EQ(old.mount.roll_rad, 0.0);
  EXPECT_EQ(old.mount.yaw_rad, 0.0);
}

TEST(MapperConfig, AQuantityGivenBothWaysIsRefusedWithBothLines) {
  EXPECT_EQ(error_of("mount:\n  height_m: 0.26\n  z_m: 0.3\n"),
            "robot.yaml:3: mount.z_m: gives the same quantity as height_m on line 2; keep one of them");
  EXPECT_EQ(error_of("mount:\n  x_m: 0.1\n  pitch_deg: 20\n  forward_offset_m: 0.1\n"),
            "robot.yaml:2: mount.x_m: gives the same quantity as forward_offset_m on line 4; keep one of them");
  EXPECT_NE(error_of("mount: {y_m: 0, lateral_offset_m: 0}\n").find("robot.yaml:1: mount.y_m: gives the same quantity"),
            std::string::npos);
  EXPECT_NE(error_of("mount:\n  roll_deg: 200\n").find("robot.yaml:2: mount.roll_deg: expected a roll from -180 to 180"),
            std::string::npos);
  EXPECT_NE(error_of("mount:\n  yaw_deg: .inf\n").find("robot.yaml:2: mount.yaw_deg"), std::string::npos);
  EXPECT_NE(error_of("mount:\n  z_m: abc\n").find("robot.yaml:2: mount.z_m: expected a number"), std::string::npos);
  EXPECT_NE(error_of("mount:\n  height_m: -0.1\n").find("robot.yaml:2: mount.height_m: expected a height above"),
            std::string::npos);
}

TEST(MapperConfig, MissingFileIsNamed) {
  try {
    load_mapper_config("/nonexistent/robot.yaml");
    FAIL();
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("/nonexistent/robot.yaml"), std::string::npos);
  }
}

// The `height_fusion:` section: every field read, bad values named.
TEST(HeightFusionConfig, FieldsAreReadAndDefaultsKept) {
  const MapperConfig none = parse_mapper_config("map: {cells_per_side: 100}\n", "robot.yaml");
  EXPECT_FALSE(none.height_fusion.enabled);
  EXPECT_EQ(none.height_fusion.mahalanobis_gate, HeightFusionOptions{}.mahalanobis_gate);
  const MapperConfig c = parse_mapper_config(
      "height_fusion:\n  enabled: true\n  mahalanobis_gate: 3\n  outlier_variance_m2: 2.5e-5\n"
      "  min_variance_m2: 1.0e-6\n  sigma_per_uncertainty: 0.5\n",
      "robot.yaml");
  EXPECT_TRUE(c.height_fusion.enabled);
  EXPECT_EQ(c.height_fusion.mahalanobis_gate, 3.0);
  EXPECT_EQ(c.height_fusion.outlier_variance_m2, 2.5e-5);
  EXPECT_EQ(c.height_fusion.min_variance_m2, 1.0e-6);
  EXPECT_EQ(c.height_fusion.sigma_per_uncertainty, 0.5);
  EXPECT_NO_THROW(c.height_fusion.validate());
}

TEST(HeightFusionConfig, BadValuesAreNamed) {
  const std::string negative = error_of("height_fusion:\n  mahalanobis_gate: -1\n");
  EXPECT_NE(negative.find("robot.yaml:2: height_fusion.mahalanobis_gate"), std::string::npos) << negative;
  EXPECT_NE(error_of("height_fusion:\n  outlier_variance_m2: 0\n").find("height_fusion.outlier_variance_m2"),
            std::string::npos);
  EXPECT_NE(error_of("height_fusion:\n  min_variance_m2: .nan\n").find("height_fusion.min_variance_m2"),
            std::string::npos);
  EXPECT_NE(error_of("height_fusion:\n  sigma_per_uncertainty: .inf\n").find("height_fusion.sigma_per_uncertainty"),
            std::string::npos);
  EXPECT_NE(error_of("height_fusion:\n  enabled: sometimes\n").find("height_fusion.enabled"), std::string::npos);
  const std::string unknown = error_of("height_fusion:\n  gate: 2\n");
  EXPECT_NE(unknown.find("height_fusion.gate: unknown field"), std::string::npos) << unknown;
}

}  // namespace
}  // namespace mapper_config_test
}  // namespace stridemap
