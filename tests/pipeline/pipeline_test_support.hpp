#pragma once
// Scans, poses and the map comparison the pipeline tests share.
#include <cmath>
#include <cstdint>
#include <cstring>
#include <numbers>

#include <gtest/gtest.h>

#include "stridemap/core/grid_map.hpp"
#include "stridemap/core/pose.hpp"
#include "stridemap/sensors/urg04lx.hpp"

namespace stridemap::test {

/// A URG-04LX raw scan of a flat floor seen from the default mount: each
/// beam that points down gets the floor's range, the others error code 0.
inline UrgRawScan floor_scan(double time_s, const UrgParameters& urg = {}, const SensorMount& mount = {}) {
  UrgRawScan raw;
  raw.time_s = time_s;
  raw.first_step = urg.first_step;
  for (int step = urg.first_step; step <= urg.last_step; ++step) {
    const double down = std::cos(urg.step_angle_rad(step)) * std::sin(mount.pitch_rad);
    const double range = down > 0.1 ? mount.height_m / down : 0.0;
    raw.values_mm.push_back(range > urg.min_range_m && range < urg.max_range_m
                                ? static_cast<std::uint32_t>(std::lround(range * 1000.0))
                                : 0u);
  }
  return raw;
}

inline TrunkPose pose_at(double x_m, double yaw_rad = 0.0) {
  TrunkPose p;
  p.x_m = x_m;
  p.yaw_rad = yaw_rad;
  return p;
}

/// Success when both maps cover the same window with the same layers,
/// byte for byte.
inline ::testing::AssertionResult same_maps(const ElevationMap& a, const ElevationMap& b) {
  if (a.layer_count() != b.layer_count() || a.cells_per_side() != b.cells_per_side() ||
      a.min_cell().x != b.min_cell().x || a.min_cell().y != b.min_cell().y) {
    return ::testing::AssertionFailure() << "the maps' windows or layer counts differ";
  }
  const std::size_t cells = static_cast<std::size_t>(a.cells_per_side()) * static_cast<std::size_t>(a.cells_per_side());
  for (std::size_t k = 0; k < a.layer_count(); ++k) {
    const std::size_t bytes = cells * layer_type_bytes(a.layer_spec(k).type);
    if (std::memcmp(a.layer_bytes(k), b.layer_bytes(k), bytes) != 0) {
      return ::testing::AssertionFailure() << "layer " << a.layer_spec(k).name << " differs";
    }
  }
  return ::testing::AssertionSuccess();
}

}  // namespace stridemap::test
