#include "stridemap/preprocess/scan_checks.hpp"

#include <algorithm>
#include <bit>
#include <cmath>
#include <cstdint>
#include <limits>
#include <sstream>
#include <string>

#include "stridemap/core/error.hpp"
#include "vector_clones.hpp"

namespace stridemap {
namespace {

constexpr std::size_t no_index = static_cast<std::size_t>(-1);

// The passes over every beam compare and select: an AVX2 copy gives the same bits.

// 1 when the exponent bits of a double's bits are all ones (inf or NaN), else 0.
constexpr std::uint64_t exponent_all_ones(std::uint64_t bits) { return (((bits >> 52) & 0x7FF) + 1) >> 11; }

// Nonzero when some angle is not finite: on the bits, so that it vectorises
// (a double is not finite when its exponent bits are all ones).
STRIDEMAP_PREPROCESS_CLONES std::uint64_t any_angle_not_finite(const double* angle, std::size_t n) {
  std::uint64_t not_finite = 0;
  for (std::size_t i = 0; i < n; ++i) not_finite |= exponent_all_ones(std::bit_cast<std::uint64_t>(angle[i]));
  return not_finite;
}

// is_usable_range without branches (dropouts come scattered among valid
// beams): unusable ranges become NaN; returns how many.
STRIDEMAP_PREPROCESS_CLONES std::size_t normalize_ranges(double* range, std::size_t n) {
  constexpr double kMax = std::numeric_limits<double>::max(), kNaN = std::numeric_limits<double>::quiet_NaN();
  std::size_t invalid = 0;
  for (std::size_t i = 0; i < n; ++i) {
    const bool usable = (range[i] > 0.0) & (range[i] <= kMax);
    range[i] = usable ? range[i] : kNaN;
    invalid += static_cast<std::size_t>(!usable);
  }
  return invalid;
}

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
  // One branch-free pass over all the angles; the loop that names the bad
  // beam runs only when there is one.
  const std::uint64_t not_finite = any_angle_not_finite(scan.angle_rad.data(), angles);
  for (std::size_t i = 0; not_finite != 0 && i < angles; ++i) {
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
  // Counted even when already NaN: "invalid on input" is what the caller
  // needs to tell filter removals from sensor dropouts.
  stats.invalid_input = normalize_ranges(scan.range_m.data(), stats.beams);
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
