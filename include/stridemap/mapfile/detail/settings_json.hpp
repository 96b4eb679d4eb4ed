#pragma once
// The one writer of a run's settings as JSON: the map file's metadata, the
// resume check that compares a map's settings with a run's, and the
// summaries of the runs that make maps all take their settings from here,
// so that what a file records and what a check compares cannot drift apart.
// Shared with the layers that write files; no installed header includes it.
#include <optional>
#include <string>

#include <nlohmann/json.hpp>

#include "stridemap/config/mapper_config.hpp"
#include "stridemap/core/map_filter.hpp"

namespace stridemap::io::detail {

/// The sensor mount as a map file's metadata records it.
nlohmann::json mount_json(const SensorMount& mount);

/// Every setting of a mapper configuration (defaults included), in the
/// units of the structs (SI, radians): mapper_config_json() is its text.
nlohmann::json mapper_settings_json(const MapperConfig& config);

/// What a run did to its scans and its map, as its summary records them:
/// "filters" (the scan filter list's name, preprocess/scan_filter_chain.hpp),
/// "map_filter" and, when the run has one, the "clock" its poses were on.
nlohmann::json run_settings_json(const std::string& filters, MapFilter map_filter,
                                 const std::optional<std::string>& clock = std::nullopt);

}  // namespace stridemap::io::detail
