#pragma once
// What a sensor model hands the mapper for each point of a scan: where the
// point lies relative to the sensor origin (map axes) and how uncertain its
// height is. The mapper adds the motion terms (core/max_elevation_change.hpp)
// and the pose; the sensor knows nothing of the map.
//
// A source of points is any type with
//   std::size_t size() const;
//   double inclination_rad() const;            // gamma of eq. (7) for this scan
//   PointStatus point(std::size_t i, SensorPoint& out) const;
// TerrainMapper::integrate_scan takes it as a template argument, so a
// built-in sensor's per-point code is inlined into the update loop.
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <vector>

#include <Eigen/Core>

namespace stridemap {

enum class PointStatus : std::uint8_t {
  ok,
  invalid_range,  ///< no usable measurement (NaN, infinite or non-positive range, a point not finite)
  invalid_beam,   ///< the measurement is there but its geometry or error is not (non-finite angle or error)
};

struct SensorPoint {
  Eigen::Vector3d offset_m = Eigen::Vector3d::Zero();  ///< from the sensor origin, map axes [m]
  double height_error_m = 0.0;  ///< the sensor's error part of Delta z_max (eq. 6 / eq. 8 / sigma) [m]
  double range_m = 0.0;         ///< distance from the sensor origin, as the sensor measured it [m]
};

/// A scan's points computed up front: the source for sensors whose points
/// are not cheaper to compute inside the update loop (structured light,
/// point clouds, sensors added outside the library).
struct PointBatch {
  double gamma_rad = 0.0;
  std::vector<SensorPoint> points;

  void clear() { points.clear(); }
  std::size_t size() const { return points.size(); }
  double inclination_rad() const { return gamma_rad; }
  PointStatus point(std::size_t i, SensorPoint& out) const {
    out = points[i];
    if (!out.offset_m.allFinite()) return PointStatus::invalid_range;
    // An infinite error is meaningful ("anything is plausible"); NaN or a
    // negative bound is not.
    if (std::isnan(out.height_error_m) || out.height_error_m < 0.0) return PointStatus::invalid_beam;
    return PointStatus::ok;
  }
};

/// The default of TerrainMapper::integrate_scan: the points are not kept.
struct NoPointSink {
  void operator()(std::size_t, const Eigen::Vector3d&, const SensorPoint&) const {}
};

}  // namespace stridemap
