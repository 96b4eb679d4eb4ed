#pragma once
// Scenes for the simulator from YAML files (schema and example:
// docs/scenes.md). Strict: unknown or repeated keys, missing fields, wrong
// types and unusable values are errors, so that a typo never passes
// silently.
#include <string>

#include "stridemap/sim/scene.hpp"

namespace stridemap {

/// Reads and parses a scene file. Throws InputError
/// "<file>:<line>: <field path>: <what is wrong>", e.g.
/// "scenes/a.yaml:12: boxes[1].length_m: expected a positive number, got -0.1",
/// or "<file>: cannot read scene file: <reason>".
Scene load_scene_yaml(const std::string& path);

/// Parses scene YAML text; source_name stands for the file in messages.
Scene parse_scene_yaml(const std::string& text, const std::string& source_name);

}  // namespace stridemap
