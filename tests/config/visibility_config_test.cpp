// The `visibility:` section of the mapper configuration: every field read,
// defaults kept, bad values named with file, line and field.
#include <string>

#include <gtest/gtest.h>

#include "stridemap/config/mapper_config.hpp"
#include "stridemap/core/error.hpp"

namespace stridemap {
namespace visibility_config_test {
namespace {

std::string error_of(const std::string& text) {
  try {
    parse_mapper_config(text, "robot.yaml");
  } catch (const InputError& e) {
    return e.what();
  }
  return "no error";
}

TEST(VisibilityConfig, FieldsAreReadAndDefaultsKept) {
  const MapperConfig none = parse_mapper_config("map: {cells_per_side: 100}\n", "robot.yaml");
  EXPECT_EQ(none.visibility.enabled, VisibilityOptions{}.enabled);
  const MapperConfig c = parse_mapper_config(
      "visibility:\n  enabled: true\n  uncertainty_factor: 2\n  relief_factor: 0.5\n  certainty_decrement: 10\n"
      "  beam_spacing_cells: 0\n",
      "robot.yaml");
  EXPECT_TRUE(c.visibility.enabled);
  EXPECT_EQ(c.visibility.uncertainty_factor, 2.0);
  EXPECT_EQ(c.visibility.relief_factor, 0.5);
  EXPECT_EQ(c.visibility.certainty_decrement, 10.0);
  EXPECT_EQ(c.visibility.beam_spacing_cells, 0.0);
}

TEST(VisibilityConfig, BadValuesAreNamed) {
  EXPECT_NE(error_of("visibility:\n  relief_factor: -1\n").find("robot.yaml:2: visibility.relief_factor"),
            std::string::npos)
      << error_of("visibility:\n  relief_factor: -1\n");
  EXPECT_NE(error_of("visibility:\n  certainty_decrement: 0\n").find("visibility.certainty_decrement"),
            std::string::npos);
  EXPECT_NE(error_of("visibility:\n  uncertainty_factor: .nan\n").find("visibility.uncertainty_factor"),
            std::string::npos);
  EXPECT_NE(error_of("visibility:\n  beam_spacing_cells: 5000\n").find("visibility.beam_spacing_cells"),
            std::string::npos);
  EXPECT_NE(error_of("visibility:\n  enabled: maybe\n").find("visibility.enabled"), std::string::npos);
  EXPECT_NE(error_of("visibility:\n  margin_m: 0.01\n").find("visibility.margin_m: unknown field"), std::string::npos)
      << error_of("visibility:\n  margin_m: 0.01\n");
}

}  // namespace
}  // namespace visibility_config_test
}  // namespace stridemap
