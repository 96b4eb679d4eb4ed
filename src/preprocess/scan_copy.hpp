#pragma once
// Copying one scan into another that keeps its buffers (internal): the
// filter chain and the scan-sequence filter reuse their work scans so that
// a steady stream of same-sized scans allocates nothing.
#include "stridemap/core/planar_scan.hpp"

namespace stridemap::detail {

/// Copies `from` into `to` reusing to's capacity; a no-op when they are the same scan.
inline void copy_scan(const PlanarScan& from, PlanarScan& to) {
  if (&from == &to) return;
  to.time_s = from.time_s;
  to.angle_rad.assign(from.angle_rad.begin(), from.angle_rad.end());
  to.range_m.assign(from.range_m.begin(), from.range_m.end());
  to.range_error_m.assign(from.range_error_m.begin(), from.range_error_m.end());
}

}  // namespace stridemap::detail
