#pragma once
// What every scan filter does before it looks at a scan: check that the scan
// is well formed, turn every unusable range into the one invalid encoding
// (NaN), and prepare the caller's removal mask. Shared so that all filters
// treat bad input the same way and report it with the same words.
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <string_view>
#include <vector>

#include "stridemap/core/planar_scan.hpp"

namespace stridemap {

/// What one filter did to one scan.
struct ScanFilterStats {
  std::size_t beams = 0;          ///< beams in the scan
  std::size_t invalid_input = 0;  ///< ranges that were unusable on input (NaN, inf, <= 0); set to NaN
  std::size_t removed = 0;        ///< valid beams this filter invalidated (marked in the removal mask)
};

/// Throws InputError unless angle_rad, range_m and range_error_m have the same
/// length and every angle is finite. `filter_name` starts the message; a
/// `scan_index` other than npos (a position in a stream) is named too.
void check_scan_shape(const PlanarScan& scan, std::string_view filter_name,
                      std::size_t scan_index = static_cast<std::size_t>(-1));

/// A range the filters can use: finite and positive. Everything else (NaN,
/// +-inf, zero, negative) is "no return" for the filters.
inline bool is_usable_range(double range_m) { return std::isfinite(range_m) && range_m > 0.0; }

/// check_scan_shape, then rewrites unusable ranges to NaN and resizes `removed`
/// to the scan length filled with 0. Allocates only when `removed` must grow.
ScanFilterStats prepare_scan_for_filter(PlanarScan& scan, std::vector<std::uint8_t>& removed,
                                        std::string_view filter_name,
                                        std::size_t scan_index = static_cast<std::size_t>(-1));

/// Sets range_m to NaN wherever `removed` is nonzero and returns how many
/// beams that were valid it invalidated.
std::size_t apply_removal_mask(PlanarScan& scan, const std::vector<std::uint8_t>& removed);

}  // namespace stridemap
