#pragma once
// Structured-light sensor configurations from YAML (schema and examples:
// docs/structured_light.md, configs/ragno_structured_light.yaml). Strict:
// unknown or repeated keys, missing fields, wrong types and unusable values
// are errors, so that a typo never passes silently. Angles are written in
// degrees (`_deg`) and converted to radians.
#include <string>

#include "stridemap/sensors/structured_light.hpp"

namespace stridemap {

struct StructuredLightConfig {
  StructuredLightParameters parameters;
  /// The file has a `mount` section. Without one, parameters.mount keeps
  /// its default and only the camera-frame analyses make sense.
  bool has_mount = false;
};

/// Reads and parses a configuration file. Throws InputError
/// "<file>:<line>: <field path>: <what is wrong>", e.g.
/// "configs/a.yaml:4: structured_light.sheet_angle_deg: must lie strictly
/// between 0 and 90 deg, got 95 deg", or "<file>: cannot read structured-light
/// config: <reason>".
StructuredLightConfig load_structured_light_config(const std::string& path);

/// Parses configuration text; source_name stands for the file in messages.
StructuredLightConfig parse_structured_light_config(const std::string& text, const std::string& source_name);

}  // namespace stridemap
