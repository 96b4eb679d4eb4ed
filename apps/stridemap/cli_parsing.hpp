#pragma once
// Option values shared by the experiment sub-commands: each parser names
// the option and lists what it accepts.
#include <string>
#include <vector>

#include "stridemap/core/error.hpp"
#include "stridemap/core/map_update.hpp"
#include "stridemap/experiments/cart_rail.hpp"

namespace stridemap::cli {

inline bool parse_on_off(const std::string& option, const std::string& value) {
  if (value == "on") return true;
  if (value == "off") return false;
  throw InputError(option + ": expected on or off, got '" + value + "'");
}

inline MapFilter parse_map_filter(const std::string& name) {
  if (name == "fill") return MapFilter::fill;
  if (name == "cas") return MapFilter::cas;
  if (name == "none") return MapFilter::none;
  throw InputError("--map-filter: '" + name + "' is not a map filter; use fill (eq. 11), cas or none");
}

/// An option's word as its enum (the enum's own name table), the option
/// named in front of the error.
template <typename Enum>
Enum parse_option(const std::string& option, const std::string& word) {
  try {
    return parse_enum_name<Enum>(word);
  } catch (const InputError& e) {
    throw InputError(option + ": " + e.what());
  }
}

inline ElevationRule parse_elevation_rule(const std::string& name) {
  return parse_option<ElevationRule>("--elevation-rule", name);
}

}  // namespace stridemap::cli
