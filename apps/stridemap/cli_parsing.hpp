#pragma once
// Option values shared by the experiment sub-commands: each parser names
// the option and lists what it accepts.
#include <charconv>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <limits>
#include <numbers>
#include <string>
#include <vector>

#include <CLI/CLI.hpp>

#include "stridemap/core/error.hpp"
#include "stridemap/core/grid_map.hpp"
#include "stridemap/core/map_filter.hpp"
#include "stridemap/core/map_update.hpp"
#include "stridemap/experiments/cart_rail.hpp"

namespace stridemap::cli {

// Degrees for what the tool prints; one definition for every command file,
// which the single-translation-unit build of the tool needs (apps/CMakeLists.txt).
inline constexpr double kDegPerRad = 180.0 / std::numbers::pi;

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

// Checks of numeric option values, run on the text before CLI11 converts it.
// CLI11 alone lets through what a user never meant: NaN passes its Range (no
// comparison with NaN fails), "-1" becomes 2^64-1 for an unsigned option and
// "010" is read as octal 8. Each message says what the option accepts and
// quotes what it got; CLI11 puts the option's name in front.

inline std::string number_text(double value) {
  char text[32];
  std::snprintf(text, sizeof text, "%g", value);
  return text;
}

/// A finite decimal number from `lo` to `hi` (inclusive); `unit` is printed
/// after the bounds ("m", "s").
inline CLI::Validator number_from_to(double lo, double hi, const std::string& unit = "") {
  const std::string accepted = "a number from " + number_text(lo) + " to " + number_text(hi) +
                               (unit.empty() ? std::string() : " " + unit);
  return CLI::Validator(
      [lo, hi, accepted](std::string& text) -> std::string {
        char* end = nullptr;
        const double value = text.empty() ? 0.0 : std::strtod(text.c_str(), &end);
        const bool parsed = !text.empty() && end == text.c_str() + text.size();
        if (parsed && std::isfinite(value) && value >= lo && value <= hi) return {};
        return "expected " + accepted + ", got '" + text + "'";
      },
      "NUMBER " + number_text(lo) + ".." + number_text(hi));
}

/// A whole decimal number from `lo` to `hi` (inclusive), no sign for
/// unsigned bounds, no octal or hex.
inline CLI::Validator whole_from_to(std::int64_t lo, std::uint64_t hi) {
  const std::string accepted = "a whole number from " + std::to_string(lo) + " to " + std::to_string(hi);
  return CLI::Validator(
      [lo, hi, accepted](std::string& text) -> std::string {
        const bool negative = !text.empty() && text.front() == '-';
        const char* first = text.data() + (negative ? 1 : 0);
        const char* last = text.data() + text.size();
        std::uint64_t magnitude = 0;
        const auto [end, error] = std::from_chars(first, last, magnitude);
        bool ok = first != last && error == std::errc() && end == last;
        if (ok && negative) {
          ok = lo < 0 && magnitude <= static_cast<std::uint64_t>(-(lo + 1)) + 1;
        } else if (ok) {
          ok = magnitude <= hi && (lo <= 0 || magnitude >= static_cast<std::uint64_t>(lo));
        }
        if (ok) return {};
        return "expected " + accepted + ", got '" + text + "'";
      },
      "INT " + std::to_string(lo) + ".." + std::to_string(hi));
}

/// Cells per map side: `lo` (0 where 0 means "fit") up to the library's
/// limit; beyond it the message says how much memory the grid would take.
inline CLI::Validator grid_cells_option(int lo) {
  const CLI::Validator whole = whole_from_to(lo, kMaxGridCellsPerSide);
  return CLI::Validator(
      [whole](std::string& text) -> std::string {
        std::string problem = whole(text);
        if (problem.empty()) return {};
        int cells = 0;
        const auto [end, error] = std::from_chars(text.data(), text.data() + text.size(), cells);
        if (error == std::errc() && end == text.data() + text.size() && cells > kMaxGridCellsPerSide) {
          try {
            validate_grid_options(GridOptions{cells, 0.01});
          } catch (const GridSizeError& e) {
            problem = e.what();
          }
        }
        return problem;
      },
      "INT " + std::to_string(lo) + ".." + std::to_string(kMaxGridCellsPerSide));
}

/// Runs `run`, turning a grid the library refuses into an error that names
/// the setting which chose the cell size (`--cell-size-m 0.0001`).
template <class Run>
auto naming_grid_setting(const std::string& setting, Run&& run) {
  try {
    return run();
  } catch (const GridSizeError& e) {
    throw InputError(setting + ": " + e.what());
  }
}

/// Every seed: a whole number from 0 to 2^64 - 1 (docs/experiments.md).
inline CLI::Validator seed_value() { return whole_from_to(0, std::numeric_limits<std::uint64_t>::max()); }

}  // namespace stridemap::cli
