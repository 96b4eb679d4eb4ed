#include "stridemap/mapfile/map_resume_check.hpp"

#include <nlohmann/json.hpp>

#include "stridemap/core/error.hpp"
#include "stridemap/mapfile/detail/settings_json.hpp"

namespace stridemap::io {
namespace {

using nlohmann::json;

std::string value_text(const json& value) { return value.is_null() ? "nothing" : value.dump(); }

// Leaf by leaf, so that the message names the one setting that differs
// rather than the whole section.
void compare(const json& saved, const json& given, const std::string& path, std::vector<std::string>& out) {
  if (saved.is_object() && given.is_object()) {
    for (const auto& [key, value] : given.items()) {
      const auto it = saved.find(key);
      compare(it == saved.end() ? json(nullptr) : *it, value, path.empty() ? key : path + "." + key, out);
    }
    for (const auto& [key, value] : saved.items()) {
      if (!given.contains(key)) compare(value, json(nullptr), path.empty() ? key : path + "." + key, out);
    }
    return;
  }
  if (saved != given) out.push_back(path + ": the map has " + value_text(saved) + ", this run " + value_text(given));
}

}  // namespace

std::vector<std::string> map_config_differences(const MapFile& saved, const MapperConfig& config) {
  std::vector<std::string> differences;
  const ElevationMap& map = saved.map;
  const GridOptions& grid = config.mapper.grid;
  if (map.cells_per_side() != grid.cells_per_side) {
    differences.push_back("map.cells_per_side: the map has " + std::to_string(map.cells_per_side()) + ", this run " +
                          std::to_string(grid.cells_per_side));
  }
  if (map.cell_size_m() != grid.cell_size_m) {
    differences.push_back("map.cell_size_m: the map has " + json(map.cell_size_m()).dump() + ", this run " +
                          json(grid.cell_size_m).dump());
  }
  // Parsed from the text a map file records, so that the comparison sees
  // this run's settings exactly as its own map would keep them.
  json given = json::parse(mapper_config_json(config));
  json recorded = json::parse(saved.metadata.config_text, nullptr, false);
  if (recorded.is_object()) {
    // The fused layers may start on a map without them (they start
    // unknown) and go on with other gate or variance settings; but a run
    // that stops keeping them would carry the map's along unchanged, stale
    // under a robot that reads them.
    const auto kept = recorded.find("height_fusion");
    const bool map_kept_them = kept != recorded.end() && kept->is_object() && kept->contains("enabled") &&
                               (*kept)["enabled"] == json(true);
    if (map_kept_them && !config.height_fusion.enabled) {
      differences.emplace_back("height_fusion.enabled: the map has true (its fused layers), this run false");
    }
    recorded.erase("height_fusion");
    given.erase("height_fusion");
    std::vector<std::string> settings;
    compare(recorded, given, "", settings);
    for (std::string& line : settings) {
      // The grid is compared above against the map itself.
      if (line.rfind("map.cells_per_side:", 0) == 0 || line.rfind("map.cell_size_m:", 0) == 0) continue;
      // Foothold layers are derived and recomputed on resume: their
      // settings may change (and maps from before them lack the section).
      if (line.rfind("foothold.", 0) == 0) continue;
      differences.push_back(std::move(line));
    }
  } else if (saved.metadata.mount) {
    // A configuration stored as other text: the mount is still recorded.
    const json mount = given["mount"];
    compare(detail::mount_json(*saved.metadata.mount), mount, "mount", differences);
  }
  return differences;
}

std::vector<std::string> missing_resume_settings(const MapFile& saved) {
  std::vector<std::string> missing;
  if (!saved.metadata.mount) missing.emplace_back("the sensor mount");
  if (saved.metadata.config_text.empty()) missing.emplace_back("the mapper configuration");
  return missing;
}

void check_map_resumable(const MapFile& saved, const MapperConfig& config, const std::string& source) {
  // Without them there is nothing to compare this run's settings with: the
  // scans would go into the map whatever the mount or update rule was.
  const std::vector<std::string> missing = missing_resume_settings(saved);
  if (!missing.empty()) {
    std::string what;
    for (std::size_t i = 0; i < missing.size(); ++i) what += (i ? " or " : "") + missing[i];
    throw InputError(source + ": cannot resume mapping from this map: the file does not record " + what +
                     " it was made with, so this run's settings cannot be checked against it; resume from a map "
                     "file written by `stridemap map` or `live` or saved from a Python Pipeline (they record "
                     "both), or map its scans again");
  }
  const std::vector<std::string> differences = map_config_differences(saved, config);
  if (differences.empty()) return;
  std::string message = source + ": cannot resume mapping from this map: it was made with other settings (";
  for (std::size_t i = 0; i < differences.size(); ++i) message += (i ? "; " : "") + differences[i];
  throw InputError(message + "); give the --config it was made with");
}

}  // namespace stridemap::io
