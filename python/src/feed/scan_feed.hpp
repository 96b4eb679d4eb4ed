#pragma once
// The per-scan work behind stridemap.Pipeline's add_* calls, without
// pybind11: the binding checks shapes and dtypes and hands over C-contiguous
// float64 data; ScanFeed checks the values, fills buffers grown once and
// feeds the pipeline. Apart from the binding so that a C++ test counts what
// it allocates (tests/python/scan_feed_allocation_test.cpp): nothing per
// scan once warmed up. Argument names are put together only for a message.
#include <cstddef>
#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "stridemap/core/pose.hpp"
#include "stridemap/pipeline/mapping_pipeline.hpp"
#include "stridemap/sensors/urg04lx.hpp"

namespace stridemap::python {

/// An argument as the caller wrote it: "ranges", or row 3 of a batch
/// ("ranges[3]"). `argument` must outlive the name.
struct ArgumentName {
  const char* argument;
  long long row = -1;
  std::string text() const;
  /// "ranges[7]", or "ranges[3][7]" for a row.
  std::string element(long long index) const;
};

/// A finite number, InputError naming `name` otherwise.
double finite_value(double value, const ArgumentName& name);

/// 5 values (x_m, y_m, roll_rad, pitch_rad, yaw_rad) or 6 (x_m, y_m, z_m,
/// roll_rad, pitch_rad, yaw_rad), every one finite; InputError naming the field.
TrunkPose pose_of_values(const double* values, std::size_t count, double reference_elevation_m,
                         double height_change_m, const ArgumentName& name);

/// How add_urg_scan's ranges are given: the sensor's raw millimetres, or metres.
enum class RangeUnits : std::uint8_t { mm, m };

/// "mm" or "m"; InputError otherwise.
RangeUnits range_units(const std::string& units);

/// add_urg_scans' arrays, shapes checked by the binding: row i of `ranges`
/// (values_per_scan values) is the scan at times_s[i] seen from poses' row i
/// (pose_values: 5 or 6). Per-scan elevations are finite, or null for 0.
struct UrgBatch {
  std::size_t scans = 0;
  const double* ranges = nullptr;
  std::size_t values_per_scan = 0;
  const double* times_s = nullptr;
  const double* poses = nullptr;
  std::size_t pose_values = 5;
  const double* reference_elevation_m = nullptr;
  const double* height_change_m = nullptr;
  RangeUnits units = RangeUnits::mm;
};

/// How a batch's scans fared, from the pipeline's and the mapper's counts.
struct UrgBatchCounts {
  std::size_t mapped = 0;
  std::size_t stale = 0;     ///< a time not after the last mapped scan's
  std::size_t bad_pose = 0;  ///< the mapper refused the pose
  std::size_t unfit = 0;     ///< not the sensor's shape
  std::optional<std::size_t> first_stale;  ///< the row of the first stale scan
};

class ScanFeed {
 public:
  /// `pipeline` must outlive the feed.
  explicit ScanFeed(MappingPipeline& pipeline);

  /// One URG scan, `count` values from first_step (default the sensor's).
  /// InputError naming the value ("ranges[7]") or the sensor's words for a
  /// scan that does not fit it; nothing reaches the pipeline then.
  ScanOutcome add_urg(const double* values, std::size_t count, RangeUnits units, double time_s,
                      std::optional<int> first_step, int cluster, const TrunkPose& pose);
  /// The batch's scans in order; an error names the row ("poses[3]") and
  /// leaves the rows before it mapped.
  UrgBatchCounts add_urg_batch(const UrgBatch& batch);
  /// `count` points (x, y, z rows) with one sigma each, or sigma_m[0] for all.
  ScanOutcome add_points(const double* xyz, std::size_t count, const double* sigma_m, bool one_sigma, double time_s,
                         const TrunkPose& pose);
  /// `count` stripe pixels (u_px, v_px rows).
  ScanOutcome add_stripe(const double* uv, std::size_t count, std::optional<double> time_s, const TrunkPose& pose);

 private:
  void fill_raw(const double* values, std::size_t count, RangeUnits units, double time_s, int first_step, int cluster,
                const ArgumentName& ranges);

  MappingPipeline& pipeline_;
  UrgModel urg_;  // the pipeline's sensor, to refuse what it would only count
  UrgRawScan raw_;
  PointFrame points_;
  std::vector<StripePixel> stripe_;
};

}  // namespace stridemap::python
