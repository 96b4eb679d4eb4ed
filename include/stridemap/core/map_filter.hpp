#pragma once
// What runs on a map before it is shown, saved or scored: one enum and one
// name <-> value pair, for the experiments, live mapping and the CLI.
#include <cstdint>
#include <optional>
#include <string_view>

namespace stridemap {

enum class MapFilter : std::uint8_t {
  none,  ///< the map as the update rule left it
  fill,  ///< weighted-median fill-in (eq. 11), the paper's choice for the URG
  cas,   ///< the CAS filter, then the fill (the paper's choice for structured light)
};

constexpr std::string_view map_filter_name(MapFilter filter) {
  switch (filter) {
    case MapFilter::none: return "none";
    case MapFilter::fill: return "fill";
    case MapFilter::cas: return "cas";
  }
  return "?";
}

/// Empty for a name that is no map filter.
constexpr std::optional<MapFilter> map_filter_from_name(std::string_view name) {
  for (const MapFilter f : {MapFilter::none, MapFilter::fill, MapFilter::cas}) {
    if (map_filter_name(f) == name) return f;
  }
  return std::nullopt;
}

}  // namespace stridemap
