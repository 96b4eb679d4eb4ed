#pragma once
// Before mapping goes on from a saved map (core/map_resume.hpp): the map
// must have been made with the settings of the run that continues it. A
// different cell size, mount or update rule would put the new scans into
// cells that mean something else, silently; so every difference is named.
#include <string>
#include <vector>

#include "stridemap/config/mapper_config.hpp"
#include "stridemap/mapfile/map_file.hpp"

namespace stridemap::io {

/// The settings in which the saved map differs from `config`, one line
/// each, as "map.cell_size_m: the map has 0.01, this run 0.02". Compares the
/// map's own geometry, its recorded mount, and (when the map carries it as
/// JSON, as stridemap writes it) every setting of its configuration.
std::vector<std::string> map_config_differences(const MapFile& saved, const MapperConfig& config);

/// What the map file lacks of the settings a resume is checked against:
/// "the sensor mount", "the mapper configuration"; empty when it has both.
std::vector<std::string> missing_resume_settings(const MapFile& saved);

/// Throws InputError "<source>: cannot resume mapping from this map: ..."
/// naming what the file lacks (missing_resume_settings), or else listing
/// every difference (map_config_differences).
void check_map_resumable(const MapFile& saved, const MapperConfig& config, const std::string& source);

}  // namespace stridemap::io
