#pragma once
// How a sensor joins the mapping pipeline. A sensor model turns the data of
// one scan (or camera frame) into points relative to the sensor origin and
// says how uncertain each point's height is (its error model); the mapper
// adds the motion terms of Delta z_max and the pose
// (core/max_elevation_change.hpp), the same for every sensor.
//
// The structured-light sensor and the generic point source are models of
// this kind; a sensor added outside the library is too (one class, handed
// to ScanIntegrator::push / MappingPipeline::add). The URG-04LX is not:
// its per-point path is inlined into the map update (core/planar_scan_points.hpp).
#include <string_view>

#include "stridemap/core/map_update.hpp"
#include "stridemap/core/pose.hpp"
#include "stridemap/core/sensor_point.hpp"

namespace stridemap {

class SensorModel {
 public:
  virtual ~SensorModel() = default;
  /// For messages and reports ("structured-light", "points", ...).
  virtual std::string_view name() const = 0;
  /// The points of the data the model holds now (each model has its own
  /// setter for it), seen from `pose` with the sensor at `mount`: offsets
  /// in map axes, the height error from the model's own error bounds and
  /// `update`'s pose error bounds, and gamma of the measuring surface in
  /// batch.gamma_rad. One call per scan; `batch` is refilled in place.
  virtual void to_points(const TrunkPose& pose, const SensorMount& mount, const UpdateOptions& update,
                         PointBatch& batch) = 0;
};

}  // namespace stridemap
