#pragma once
// What runs on a finished (or published) map before it is used: nothing,
// the weighted-median fill-in (eq. 11), or the CAS filter followed by its
// fill. One enum, one name/parse pair, one function that applies it, for
// the experiments, the CLI and the mapping pipeline alike.
#include <cstddef>
#include <cstdint>
#include <string_view>

#include "stridemap/core/cas_filter.hpp"
#include "stridemap/core/grid_map.hpp"
#include "stridemap/core/weighted_median_fill.hpp"

namespace stridemap {

enum class MapFilter : std::uint8_t {
  none,  ///< the map as the update rule left it
  fill,  ///< weighted-median fill-in (eq. 11), the paper's choice for the URG
  cas,   ///< the CAS filter, then the fill (the paper's choice for structured light)
};

/// "none", "fill", "cas".
std::string_view map_filter_name(MapFilter filter);
/// One of map_filter_name()'s names; throws InputError "'<name>' is not a
/// map filter; use fill (eq. 11), cas or none".
MapFilter parse_map_filter(std::string_view name);

struct MapFilterOptions {
  MapFilter filter = MapFilter::fill;
  FillOptions fill{};  ///< MapFilter::fill (CAS uses cas.fill)
  CasOptions cas{};
};

struct MapFilterResult {
  std::size_t filled = 0;       ///< cells in state filled afterwards
  std::size_t cas_removed = 0;  ///< measured cells CAS reset to unknown
};

/// Throws InputError for invalid fill or CAS options (also those of the
/// filter not selected are not checked: only the one that runs).
MapFilterResult apply_map_filter(const MapFilterOptions& options, ElevationMap& map);

}  // namespace stridemap
