#pragma once
// The mapping pipeline: one options struct (pipeline_options.hpp) in,
// timestamped scans and poses in, an elevation map out. Poses come either
// one per scan (add(scan, pose)), or as a stream (queue() the scans, then
// process() them against a PoseTrack, which interpolates each scan's pose
// at its time). A queued scan waits until the poses around its time have
// arrived; a scan that can never get a pose (before the first pose, in a
// gap, after the last pose once the poses are complete, or overdue in live
// mapping: expire()) is skipped and counted.
//
// Inside, each scan takes the way of ScanIntegrator: sensor model and error
// model, scan filters with the scan's pose carried through their delay, the
// map update with Delta z_max formed in one place, then (when on) the
// visibility clean-up (core/visibility_clearing.hpp). After each, the
// foothold layers (core/foothold.hpp) note the cells the scan changed, the
// cleared ones included, and are brought up to date around them (after
// every scan by default; foothold.update_every_scan off: at
// refresh_foothold()).
#include <cstddef>
#include <optional>
#include <span>
#include <variant>

#include "stridemap/core/foothold.hpp"
#include "stridemap/core/grid_map.hpp"
#include "stridemap/core/map_filter.hpp"
#include "stridemap/core/pose_track.hpp"
#include "stridemap/core/ring_queue.hpp"
#include "stridemap/core/terrain_mapper.hpp"
#include "stridemap/pipeline/pipeline_options.hpp"
#include "stridemap/pipeline/scan_integrator.hpp"

namespace stridemap {

class MappingPipeline {
 public:
  /// Throws InputError for invalid options (sensor, filters, map, update
  /// rule, map filter, mount), before any scan.
  explicit MappingPipeline(const PipelineOptions& options);

  // One pose per scan: integrated now (with scan-sequence, the previous
  // scan is, at its own pose).
  ScanOutcome add(const UrgRawScan& raw, const TrunkPose& pose, std::span<const std::uint8_t> beam_tags = {});
  ScanOutcome add(const StripeFrame& frame, const TrunkPose& pose);
  /// A stripe without a frame time: the mapper's order check does not apply.
  ScanOutcome add(std::span<const StripePixel> pixels, std::optional<double> time_s, const TrunkPose& pose);
  ScanOutcome add(const PointFrame& frame, const TrunkPose& pose);
  /// A sensor model of the caller's holding its next scan (SensorKind::custom).
  ScanOutcome add(SensorModel& model, double time_s, const TrunkPose& pose);
  /// A scan already in its scan plane (a ROS LaserScan from any scanner):
  /// the mapper's own planar path (eq. 6, as for the URG), no scan filters,
  /// the foothold layers kept current as for every other scan.
  ScanStats add_planar(const PlanarScan& scan, const TrunkPose& pose);

  // A pose stream: scans wait in a queue until their pose is known. The
  // scan's time must be on the poses' clock; `arrival_s` is when it arrived
  // (any clock; only expire() compares it).
  void queue(const UrgRawScan& raw, double arrival_s = 0.0);
  void queue(const StripeFrame& frame, double arrival_s = 0.0);
  void queue(const PointFrame& frame, double arrival_s = 0.0);
  /// Integrates the waiting scans, oldest first, while their pose is known;
  /// with `poses_complete` a scan after the last pose is skipped instead of
  /// waiting. Returns the scans integrated. Drops poses no longer needed.
  std::size_t process(PoseTrack& poses, bool poses_complete);
  /// Skips the waiting scans that arrived at or before `before_s`. Returns how many.
  std::size_t expire(double before_s);
  std::size_t waiting() const { return queue_.size(); }
  /// Room for `scans` URG scans of `values` values waiting at once, so that
  /// a longer wait for poses than before allocates nothing (live mapping).
  void reserve_queue(std::size_t scans, std::size_t values);

  /// Ends the stream: the scan the filters hold is integrated.
  ScanOutcome finish();

  /// Runs the map filter of the options on the map being built (and
  /// recomputes the foothold layers, which it changes everywhere).
  MapFilterResult apply_map_filter();
  /// The map with the map filter applied to a copy, foothold layers
  /// recomputed on it: the map being built is not changed.
  ElevationMap filtered_map() const;

  /// The foothold layers' keeper; nullptr when options().foothold.enabled
  /// is off. Their values are the map's layers (foothold->score() etc.).
  const FootholdLayers* foothold() const { return foothold_ ? &*foothold_ : nullptr; }
  /// Brings the foothold layers up to date with every scan so far (nothing
  /// to do after each scan with foothold.update_every_scan, the default).
  /// With update_every_scan off, call this before reading the layers from
  /// mapper().map(): until then they hold the values of the last refresh.
  void refresh_foothold();
  /// Recomputes the foothold layers everywhere: after the map was changed
  /// other than by scans (mapper().map() edited, resume_from_map()).
  void recompute_foothold();

  TerrainMapper& mapper() { return mapper_; }
  const TerrainMapper& mapper() const { return mapper_; }
  ScanIntegrator& integrator() { return integrator_; }
  const ScanIntegrator& integrator() const { return integrator_; }
  const PipelineOptions& options() const { return options_; }
  /// The integrator's counts plus the scans offered and those skipped for want of a pose.
  PipelineStats stats() const;

 private:
  using Scan = std::variant<UrgRawScan, StripeFrame, PointFrame>;
  struct Waiting {
    Scan scan;
    double arrival_s = 0.0;
  };
  ScanOutcome integrate(const Scan& scan, const TrunkPose& pose);
  ScanOutcome updated(ScanOutcome outcome);

  PipelineOptions options_;
  TerrainMapper mapper_;
  ScanIntegrator integrator_;
  std::optional<FootholdLayers> foothold_;
  // Slots are reused: a queued scan is copied into the storage of one that
  // left, so the stream allocates nothing per scan once the queue is long enough.
  RingQueue<Waiting> queue_;
  PipelineStats stream_;  // scans offered and skipped
};

}  // namespace stridemap
