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
// cleared ones included. They are brought up to date around them when the
// map is read: map() (the one accessor every reader of the map goes
// through), and before the window's cells leave it for a window listener
// (the tile store). foothold.update_every_scan: after every scan instead.
// With height_fusion.enabled the fused height layers are fed every
// integrated point (pipeline/height_fusion_observer.hpp).
#include <cstddef>
#include <memory>
#include <optional>
#include <span>
#include <variant>

#include "stridemap/core/foothold.hpp"
#include "stridemap/core/grid_map.hpp"
#include "stridemap/core/map_filter.hpp"
#include "stridemap/core/pose_track.hpp"
#include "stridemap/core/ring_queue.hpp"
#include "stridemap/core/terrain_mapper.hpp"
#include "stridemap/core/window_move_listener.hpp"
#include "stridemap/pipeline/pipeline_options.hpp"
#include "stridemap/pipeline/scan_integrator.hpp"

namespace stridemap {

class HeightFusion;
class HeightFusionObserver;

class MappingPipeline {
 public:
  /// Throws InputError for invalid options (sensor, filters, map, update
  /// rule, map filter, mount), before any scan.
  explicit MappingPipeline(const PipelineOptions& options);
  ~MappingPipeline();
  // Neither copied nor moved: the mapper may point at window_relay_, which
  // points back at its pipeline.
  MappingPipeline(const MappingPipeline&) = delete;
  MappingPipeline& operator=(const MappingPipeline&) = delete;

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

  /// The map for reading, its derived (foothold) layers brought up to date
  /// with every scan so far first: what every reader (snapshots, tile
  /// store flushes, writers, exports, bindings) takes. Bit for bit the map
  /// an eager pipeline (foothold.update_every_scan) holds after the same
  /// scans. Const because the layers are a cache of the elevation, so the
  /// refresh changes nothing a reader can tell; like every other call, not
  /// to be made from two threads at once.
  const ElevationMap& map() const;

  /// The foothold layers' keeper; nullptr when options().foothold.enabled
  /// is off. Their values are the map's layers (foothold->score() etc.).
  const FootholdLayers* foothold() const { return foothold_ ? &*foothold_ : nullptr; }
  /// Brings the foothold layers up to date with every scan so far; map()
  /// does so itself. Needed only before reading them from
  /// mapper().map(), which leaves them as of the last refresh.
  void refresh_foothold();
  /// Recomputes the foothold layers everywhere: after the map was changed
  /// other than by scans (mapper().map() edited, resume_from_map()).
  void recompute_foothold();

  /// The fused height layers' keeper (its layer handles and options);
  /// nullptr when options().height_fusion.enabled is off.
  const HeightFusion* height_fusion() const;

  /// Told of every move of the window (TerrainMapper::set_window_listener),
  /// the foothold layers brought up to date before the cells leaving it
  /// are handed over, so that a tile store keeps the values map() gives.
  /// nullptr for none. Not owned; the pipeline must not be copied or moved
  /// while one is set (the mapper points into it).
  void set_window_listener(WindowMoveListener* listener);

  /// The mapper, for its counts and for writes; reads of the map go through
  /// map(), since mapper().map() may hold the foothold layers of an earlier scan.
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
  void refresh_layers() const;

  // Between the mapper and the caller's window listener: the layers of the
  // cells leaving must be current before they are handed on.
  class LayersBeforeLeaving final : public WindowMoveListener {
   public:
    explicit LayersBeforeLeaving(const MappingPipeline& pipeline) : pipeline_(pipeline) {}
    void window_leaving(const ElevationMap& map, CellIndex new_min) override;
    void window_entered(ElevationMap& map, CellIndex old_min) override;
    WindowMoveListener* next = nullptr;

   private:
    const MappingPipeline& pipeline_;
  };

  PipelineOptions options_;
  TerrainMapper mapper_;
  ScanIntegrator integrator_;
  std::unique_ptr<HeightFusionObserver> fusion_;
  // Mutable: map() const brings the layers (a cache of the elevation) up to date.
  mutable std::optional<FootholdLayers> foothold_;
  LayersBeforeLeaving window_relay_{*this};
  // Slots are reused: a queued scan is copied into the storage of one that
  // left, so the stream allocates nothing per scan once the queue is long enough.
  RingQueue<Waiting> queue_;
  PipelineStats stream_;  // scans offered and skipped
};

}  // namespace stridemap
