#pragma once
// What can be wrong with a scene, stated once, so that a scene built in code
// (Scene::validate) and a scene read from a file (config/scene_yaml.hpp, which
// adds file and line) report the same rule in the same words.
#include <optional>
#include <string>

namespace stridemap {

/// The field path as a scene file spells it ("boxes[1].length_m"), the
/// object's name when the field belongs to one, and what is wrong
/// ("expected a positive number, got -0.1").
struct SceneProblem {
  std::string field_path;
  std::string object_name;
  std::string message;
};

namespace scene_rules {

/// Shortest text that reads back as the same double ("-0.1", "nan", "inf").
std::string format_number(double value);

/// Each returns the complaint, or nothing when the value obeys the rule.
std::optional<std::string> finite(double value);
std::optional<std::string> positive(double value);
std::optional<std::string> non_negative(double value);
std::optional<std::string> reflectance(double value);  ///< in (0, 1]

}  // namespace scene_rules
}  // namespace stridemap
