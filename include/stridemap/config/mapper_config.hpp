#pragma once
// The mapper's settings from a YAML file: sensor mount, map, update rule,
// fill-in, range calibration, foothold layers, the visibility clean-up and global map (schema and defaults: docs/config.md).
// Angles are in degrees in the file (`_deg` fields) and radians inside.
#include <string>

#include "stridemap/config/global_map_options.hpp"
#include "stridemap/core/foothold.hpp"
#include "stridemap/core/height_fusion.hpp"
#include "stridemap/core/pose.hpp"
#include "stridemap/core/terrain_mapper.hpp"
#include "stridemap/core/visibility_clearing.hpp"
#include "stridemap/core/weighted_median_fill.hpp"
#include "stridemap/sensors/range_calibration.hpp"

namespace stridemap {

struct MapperConfig {
  SensorMount mount{};
  MapperOptions mapper{};
  FillOptions fill{};
  RangeCalibration calibration{};
  FootholdOptions foothold{};
  /// Where cells leaving the window go (mapfile/tile_store.hpp); none by default.
  /// Not a setting of the map itself: not in the map file's config, and a
  /// resumed map may use another folder.
  GlobalMapOptions global_map{};
  VisibilityOptions visibility{};
  /// The fused height layers (off by default): `height_fusion.enabled`.
  HeightFusionOptions height_fusion{};
};

/// Every section and field is optional (the structs' defaults apply);
/// unknown or repeated keys, wrong types and values out of range are
/// InputError "<file>:<line>: <field path>: <what is wrong>".
MapperConfig load_mapper_config(const std::string& path);
MapperConfig parse_mapper_config(const std::string& text, const std::string& source_name);

}  // namespace stridemap
