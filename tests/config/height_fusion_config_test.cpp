// The `height_fusion:` section of the mapper configuration: every field
// read, defaults kept, bad values named with file, line and field.
#include <string>

#include <gtest/gtest.h>

#include "stridemap/config/mapper_config.hpp"
#include "stridemap/core/error.hpp"

namespace stridemap {
namespace height_fusion_config_test {
namespace {

std::string error_of(const std::string& text) {
  try {
    parse_mapper_config(text, "robot.yaml");
  } catch (const InputError& e) {
    return e.what();
  }
  return "no error";
}

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
}  // namespace height_fusion_config_test
}  // namespace stridemap
