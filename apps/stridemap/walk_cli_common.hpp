#pragma once
// Shared by the walking-robot sub-commands (walk_experiments.cpp,
// mount_analysis_command.cpp).
#include <cmath>
#include <cstdint>
#include <sstream>
#include <string>
#include <vector>

#include <CLI/CLI.hpp>

#include "stridemap/core/error.hpp"
#include "stridemap/experiments/mount_analysis.hpp"
#include "stridemap/experiments/rocky_walk.hpp"
#include "cli_parsing.hpp"

namespace stridemap::cli {


inline double checked_non_negative(const std::string& option, double value) {
  if (!(std::isfinite(value) && value >= 0.0)) {
    throw InputError(option + ": expected a number >= 0, got " + std::to_string(value));
  }
  return value;
}

/// "0,0.5,1" -> {0, 0.5, 1}; "none" -> {}. Every entry a number >= 0.
inline std::vector<double> parse_number_list(const std::string& option, const std::string& text) {
  std::vector<double> values;
  if (text == "none") return values;
  std::stringstream in(text);
  std::string item;
  while (std::getline(in, item, ',')) {
    std::size_t used = 0;
    double value = 0.0;
    try {
      value = std::stod(item, &used);
    } catch (const std::exception&) {
      used = 0;
    }
    while (used < item.size() && item[used] == ' ') ++used;
    if (item.empty() || used != item.size()) throw InputError(option + ": '" + item + "' is not a number");
    values.push_back(checked_non_negative(option, value));
  }
  if (values.empty()) throw InputError(option + ": expected a comma-separated list of numbers, or none");
  return values;
}

/// The structured-light sensor for the walk experiments.
WalkSensorFactory structured_light_walk_sensor_factory(std::uint64_t seed, StripePipeline pipeline);
MountSensorFactory structured_light_mount_sensor_factory(std::uint64_t seed);

void register_mount_analysis(CLI::App* experiment);

}  // namespace stridemap::cli
