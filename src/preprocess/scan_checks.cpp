#include "stridemap/preprocess/scan_checks.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <sstream>
#include <string>

#include "stridemap/core/error.hpp"

namespace stridemap {
namespace {

constexpr std::size_t no_index = static_cast<std::size_t>(-1);

std::string scan_label(std::string_view filter_name, std::size_t scan_index) {
  std::string label(filter_name);
  label += ": ";
  if (scan_index != no_index) label += "scan " + std::to_string(scan_index) + " of the stream: ";
  return label;
}

}  // namespace

void check_scan_shape(const PlanarScan& scan, std::string_view filter_name, std::size_t scan_index) {
  const std::size_t angles = scan.angle_rad.size();
  const std::size_t ranges = scan.range_m.size();
  const std::size_t errors = scan.range_error_m.size();
  if (angles != ranges || errors != ranges) {
    throw InputError(scan_label(filter_name, scan_index) + "the scan has " + std::to_string(angles) +
                     " angles, " + std::to_string(ranges) + " ranges and " + std::to_string(errors) +
                     " range errors; angle_rad, range_m and range_error_m must have the same length");
  }
  for (std::size_t i = 0; i < angles; ++i) {
    if (!std::isfinite(scan.angle_rad[i])) {
      std::ostringstream message;
      message << scan_label(filter_name, scan_index) << "beam " << i << " has angle " << scan.angle_rad[i]
              << " rad; every beam needs a finite angle";
      throw InputError(message.str());
    }
  }
}

ScanFilterStats prepare_scan_for_filter(PlanarScan& scan, std::vector<std::uint8_t>& removed,
                                        std::string_view filter_name, std::size_t scan_index) {
  check_scan_shape(scan, filter_name, scan_index);
  ScanFilterStats stats;
  stats.beams = scan.size();
  for (double& range : scan.range_m) {
    if (!is_usable_range(range)) {
      // Counted even when already NaN: "invalid on input" is what the caller
      // needs to tell filter removals from sensor dropouts.
      range = std::numeric_limits<double>::quiet_NaN();
      ++stats.invalid_input;
    }
  }
  removed.assign(scan.size(), 0);
  return stats;
}

std::size_t apply_removal_mask(PlanarScan& scan, const std::vector<std::uint8_t>& removed) {
  std::size_t count = 0;
  const std::size_t n = std::min(scan.range_m.size(), removed.size());
  for (std::size_t i = 0; i < n; ++i) {
    if (removed[i] != 0 && !std::isnan(scan.range_m[i])) {
      scan.range_m[i] = std::numeric_limits<double>::quiet_NaN();
      ++count;
    }
  }
  return count;
}

}  // namespace stridemap
