#include "stridemap/live/map_run_info.hpp"

#include <cmath>
#include <cstdlib>

#include "stridemap/core/error.hpp"
#include "stridemap/mapfile/map_file.hpp"

namespace stridemap {

std::optional<std::pair<double, double>> parse_elevation_range(const std::string& text) {
  if (text.empty()) return std::nullopt;
  const std::size_t colon = text.find(':');
  char* end = nullptr;
  const auto number = [&](const std::string& part) {
    const double value = std::strtod(part.c_str(), &end);
    if (part.empty() || *end != '\0' || !std::isfinite(value)) {
      throw InputError("--range: '" + text + "' is not MIN:MAX in metres (e.g. -0.05:0.12)");
    }
    return value;
  };
  if (colon == std::string::npos) number("");
  const double low = number(text.substr(0, colon)), high = number(text.substr(colon + 1));
  if (!(low < high)) throw InputError("--range: MIN must be below MAX, got '" + text + "'");
  return std::make_pair(low, high);
}

MapRunInfo map_run_info(const std::string& command, const std::string& scans_from, const MapRunSettings& settings) {
  MapRunInfo info;
  info.command = command;
  info.scans_from = scans_from;
  info.poses_from = settings.poses_path;
  info.clock = settings.clock;
  try {
    info.map_filter = parse_map_filter(settings.map_filter);
  } catch (const InputError& e) {
    throw InputError(std::string("--map-filter: ") + e.what());
  }
  info.resumed_from = settings.resume_path;
  info.elevation_range_m = parse_elevation_range(settings.range);
  info.other_files = settings.overwrite ? io::OtherFiles::keep : io::OtherFiles::refuse;
  return info;
}

MapRunChoices map_run_choices(const MapRunSettings& settings, const ScanMapperOptions& options,
                              bool window_fit_possible) {
  MapRunChoices choices;
  choices.config_path = settings.config_path;
  choices.window = settings.window;
  choices.resume_path = settings.resume_path;
  if (options.resume) choices.resumed_last_scan_time_s = options.resume->metadata.last_scan_time_s;
  choices.window_fit_possible = window_fit_possible;
  return choices;
}

}  // namespace stridemap
