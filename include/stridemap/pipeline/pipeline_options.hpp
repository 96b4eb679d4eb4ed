#pragma once
// Everything that configures a mapping pipeline, in one struct: which sensor
// and its model, the scan filters, the map and update rule, the map filter
// and the mount. Defaults: a URG-04LX on the paper's Messor mount, no scan
// filters, the paper's local map and update rule, the fill-in (eq. 11),
// the foothold layers, the visibility clean-up and the fused height layers.
#include <cstdint>
#include <optional>
#include <string_view>
#include <vector>

#include "stridemap/core/foothold.hpp"
#include "stridemap/core/height_fusion.hpp"
#include "stridemap/core/map_filter.hpp"
#include "stridemap/core/pose.hpp"
#include "stridemap/core/terrain_mapper.hpp"
#include "stridemap/core/visibility_clearing.hpp"
#include "stridemap/pipeline/point_cloud_sensor.hpp"
#include "stridemap/preprocess/scan_filter_chain.hpp"
#include "stridemap/sensors/range_calibration.hpp"
#include "stridemap/sensors/structured_light.hpp"
#include "stridemap/sensors/urg04lx.hpp"

namespace stridemap {

enum class SensorKind : std::uint8_t {
  urg,               ///< URG-04LX raw scans (UrgRawScan)
  structured_light,  ///< stripe pixels of a camera frame (StripeFrame)
  points,            ///< points in the sensor frame with a sigma each (PointFrame)
  custom,            ///< a SensorModel of the caller's (ScanIntegrator::push(SensorModel&, ...))
};

/// "urg", "structured-light", "points", "custom".
std::string_view sensor_kind_name(SensorKind kind);
/// One of sensor_kind_name()'s names; throws InputError listing them.
SensorKind parse_sensor_kind(std::string_view name);

struct PipelineOptions {
  SensorKind sensor = SensorKind::urg;
  /// SensorKind::urg: the parameters the sensor reports (PP) and the
  /// per-unit range calibration.
  UrgParameters urg{};
  RangeCalibration calibration{};
  /// SensorKind::structured_light: camera and sheet (its mount field is
  /// not used; `mount` places the sensor).
  StructuredLightParameters structured_light{};
  /// SensorKind::points.
  PointCloudSensorOptions points{};
  /// Scan filters between the URG's model and the mapper, in order (none by
  /// default; with scan-sequence the map lags one scan until finish()).
  /// Other sensors take none.
  std::vector<ScanFilterKind> filters{};
  ScanFilterChainOptions filter_options{};
  /// For reference runs only: beams carrying this tag are dropped before
  /// the filters (an ideal filter that sees the caller's ground truth).
  std::optional<std::uint8_t> drop_beams_tagged{};
  /// Map window and update rule.
  MapperOptions mapper{};
  /// What apply_map_filter() / filtered_map() run on the map.
  MapFilterOptions map_filter{};
  /// Where the sensor sits on the trunk.
  SensorMount mount{};
  /// The foothold layers (core/foothold.hpp), kept current after every
  /// scan; on by default, `enabled = false` leaves the map without them.
  FootholdOptions foothold{};
  /// The visibility clean-up (core/visibility_clearing.hpp): what a beam
  /// passes below is cleared, after each scan's readings; `enabled = false`
  /// keeps eq. (10)'s highest reading however the scene changes.
  VisibilityOptions visibility{};
  /// The fused height layers (core/height_fusion.hpp), from which a walking
  /// robot reads its own height (core/stance_height.hpp): with `enabled`
  /// the pipeline declares "fused_elevation" and "fused_variance" and feeds
  /// them every integrated point; off by default.
  HeightFusionOptions height_fusion{};
};

}  // namespace stridemap
