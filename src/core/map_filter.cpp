#include "stridemap/core/map_filter.hpp"

#include <array>
#include <string>
#include <utility>

#include "stridemap/core/error.hpp"

namespace stridemap {
namespace {

constexpr std::array<std::pair<std::string_view, MapFilter>, 3> kNames{{
    {"none", MapFilter::none},
    {"fill", MapFilter::fill},
    {"cas", MapFilter::cas},
}};

}  // namespace

std::string_view map_filter_name(MapFilter filter) {
  for (const auto& [name, value] : kNames) {
    if (value == filter) return name;
  }
  return "unknown";
}

MapFilter parse_map_filter(std::string_view name) {
  for (const auto& [known, value] : kNames) {
    if (known == name) return value;
  }
  throw InputError("'" + std::string(name) + "' is not a map filter; use fill (eq. 11), cas or none");
}

MapFilterResult apply_map_filter(const MapFilterOptions& options, ElevationMap& map) {
  MapFilterResult result;
  switch (options.filter) {
    case MapFilter::none: break;
    case MapFilter::fill: result.filled = WeightedMedianFill(options.fill).apply(map); break;
    case MapFilter::cas: {
      const CasResult cas = CasFilter(options.cas).apply(map);
      result.filled = cas.filled;
      result.cas_removed = cas.removed;
      break;
    }
  }
  return result;
}

}  // namespace stridemap
