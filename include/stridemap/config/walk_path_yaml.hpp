#pragma once
// A walking robot's path from YAML: a file holding one `walk_path:` section,
// the same text a scene file may carry (schema: docs/walking.md). Strict,
// as the scene reader: unknown or repeated keys, wrong types, missing
// fields and unusable values are InputError "<file>:<line>: <field>: ...".
#include <string>

#include "stridemap/sim/height_field.hpp"
#include "stridemap/sim/walk_path.hpp"

namespace stridemap {

/// With `terrain`, a path that leaves its extent is an error too, reported
/// at the line of the segment that leaves it.
WalkPath load_walk_path_yaml(const std::string& path, const HeightField* terrain = nullptr);
WalkPath parse_walk_path_yaml(const std::string& text, const std::string& source_name,
                              const HeightField* terrain = nullptr);

}  // namespace stridemap
