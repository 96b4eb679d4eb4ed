#pragma once
// Option values shared by the experiment sub-commands: each parser names
// the option and lists what it accepts.
#include <string>
#include <vector>

#include "stridemap/core/error.hpp"
#include "stridemap/core/map_filter.hpp"
#include "stridemap/core/map_update.hpp"
#include "stridemap/experiments/cart_rail.hpp"

namespace stridemap::cli {

inline bool parse_on_off(const std::string& option, const std::string& value) {
  if (value == "on") return true;
  if (value == "off") return false;
  throw InputError(option + ": expected on or off, got '" + value + "'");
}

inline MapFilter parse_map_filter(const std::string& name) {
  try {
    return stridemap::parse_map_filter(name);
  } catch (const InputError& e) {
    throw InputError(std::string("--map-filter: ") + e.what());
  }
}

inline ElevationRule parse_elevation_rule(const std::string& name) {
  if (name == "paper") return ElevationRule::paper_highest;
  if (name == "gated") return ElevationRule::gated_highest;
  throw InputError("--elevation-rule: '" + name + "' is not a rule; use paper (eq. 10) or gated");
}

}  // namespace stridemap::cli
