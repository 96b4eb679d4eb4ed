#pragma once
// One scan's way from the sensor's data into a TerrainMapper: the sensor
// model (URG-04LX, structured light, generic points, or a SensorModel of the
// caller's) with its error model, the scan filters with the scan's pose and
// tags carried through their delay (TaggedScanFilter), then the map update
// with Delta z_max formed in one place, and the visibility clean-up
// (core/visibility_clearing.hpp) with the same beams. Without scan filters
// a URG scan goes straight into the mapper's packed beams
// (UrgModel::to_beams): the map is the planar route's bit for bit, and no
// PlanarScan is made unless last_scan() asks for one. The mapper is the caller's, so that
// a walk simulation can keep reading the map it builds; MappingPipeline
// owns one and adds the pose stream and the map filter.
#include <cstddef>
#include <cstdint>
#include <optional>
#include <span>
#include <vector>

#include <Eigen/Core>

#include "stridemap/core/planar_beams.hpp"
#include "stridemap/core/terrain_mapper.hpp"
#include "stridemap/core/visibility_clearing.hpp"
#include "stridemap/pipeline/pipeline_options.hpp"
#include "stridemap/pipeline/point_cloud_sensor.hpp"
#include "stridemap/pipeline/structured_light_sensor.hpp"
#include "stridemap/pipeline/tagged_scan_filter.hpp"

namespace stridemap {

/// One point as the mapper placed it, handed back on request.
struct IntegratedPoint {
  Eigen::Vector3d map_m = Eigen::Vector3d::Zero();  ///< map frame
  double range_m = 0.0;  ///< from the sensor's origin (URG: the beam's range) [m]
  /// The sensor's error part of Delta z_max (eq. 6 without d tan(gamma),
  /// eq. 8, or the point source's bound): the predicted height uncertainty [m].
  double height_uncertainty_m = 0.0;
};

/// What the pipeline did with its scans so far.
struct PipelineStats {
  std::size_t scans = 0;               ///< offered (MappingPipeline; the integrator counts pushes)
  std::size_t integrated = 0;          ///< reached the mapper
  std::size_t before_first_pose = 0;   ///< skipped: earlier than every pose
  std::size_t after_last_pose = 0;     ///< skipped: later than every pose, and no more poses came
  std::size_t pose_gap = 0;            ///< skipped: the poses around it are too far apart
  std::size_t rejected = 0;            ///< skipped: the data do not fit the sensor's parameters
  UrgConversionStats beams;            ///< URG raw values
  StripeConversionStats stripe;        ///< structured-light pixels
  PointConversionStats points;         ///< generic points
  std::size_t cells_contradicted = 0;  ///< visibility clean-up: a scan's beams passed below (once per scan)
  std::size_t cells_cleared = 0;       ///< visibility clean-up: cleared to unknown

  PipelineStats& operator+=(const PipelineStats& other);
};

/// What one push or flush did.
struct ScanOutcome {
  bool integrated = false;  ///< a scan reached the mapper (it may still have been rejected there)
  ScanStats stats;          ///< the mapper's account of it
};

/// One integrated scan, as observers see it.
struct ScanReport {
  const ScanPayload& payload;                 ///< its pose, tags and number
  std::optional<double> time_s;               ///< as given to the mapper
  const ScanStats& stats;
  std::span<const std::uint8_t> removed;      ///< 1 where a scan filter removed the beam (planar scans only)
};

/// A consumer of per-scan results (statistics, logs, scoring): called once
/// per scan that reached the mapper, after it was integrated.
class PipelineObserver {
 public:
  virtual ~PipelineObserver() = default;
  virtual void on_scan(const ScanReport& report) = 0;
};

class ScanIntegrator {
 public:
  /// Uses options' sensor, filters and drop_beams_tagged (the mapper, its
  /// mount and update rule come with each call). Throws InputError for
  /// invalid options, e.g. scan filters with a sensor that has no planar scans.
  explicit ScanIntegrator(const PipelineOptions& options);

  /// URG-04LX: converts, filters and integrates at `pose`; with
  /// scan-sequence, what is integrated is the previous scan at ITS pose.
  /// `beam_tags` (optional, one per raw value) travel with the scan.
  ScanOutcome push(const UrgRawScan& raw, const TrunkPose& pose, TerrainMapper& mapper,
                   std::span<const std::uint8_t> beam_tags = {});
  /// Structured light: one frame's stripe. Without a time the mapper's
  /// order check does not apply.
  ScanOutcome push(std::span<const StripePixel> pixels, std::optional<double> time_s, const TrunkPose& pose,
                   TerrainMapper& mapper);
  /// Generic points: sensor frame, one sigma each.
  ScanOutcome push(std::span<const Eigen::Vector3d> points_m, std::span<const double> height_sigma_m,
                   std::optional<double> time_s, const TrunkPose& pose, TerrainMapper& mapper);
  /// Any sensor model holding its next scan (the extension point).
  ScanOutcome push(SensorModel& model, std::optional<double> time_s, const TrunkPose& pose, TerrainMapper& mapper);
  /// A scan already in its scan plane (MappingPipeline::add_planar): the
  /// mapper's planar path, no scan filters; the clean-up, the collected
  /// points and the observers as for every other scan.
  ScanOutcome push_planar(const PlanarScan& scan, const TrunkPose& pose, TerrainMapper& mapper);
  /// Ends the stream: the scan the filters hold, if any, at its own pose.
  ScanOutcome flush(TerrainMapper& mapper);

  /// The visibility clean-up on a planar scan integrated at `pose` (every
  /// push does it itself; for a caller integrating into the mapper on its
  /// own). Does nothing when options().visibility.enabled is off.
  void clear_visible(const PlanarScan& scan, const TrunkPose& pose, TerrainMapper& mapper);
  /// The last scan's clean-up (nullptr before the first or when off).
  const VisibilityClearing* visibility() const { return visibility_ ? &*visibility_ : nullptr; }

  /// Hand back the points of each integrated scan in last_points() (off by
  /// default: it costs a copy per point). A URG scan without filters keeps
  /// the packed route: the points are the mapper's hits of its one pass.
  void set_collect_points(bool collect) { collect_ = collect; }
  /// The points integrated by the last push / flush, when collecting.
  const std::vector<IntegratedPoint>& last_points() const { return points_; }
  /// Observers are called in the order added; they must outlive the integrator.
  void add_observer(PipelineObserver& observer) { observers_.push_back(&observer); }

  const PipelineStats& stats() const { return stats_; }
  const TaggedScanFilter& filters() const { return filters_; }
  /// The planar scan integrated last (URG), as the filters left it. Made
  /// here from the raw scan when the packed route took it (no filters), so
  /// not for a reader on another thread while push() runs.
  const PlanarScan& last_scan() const;
  std::size_t delay_scans() const { return filters_.delay_scans(); }
  SensorKind sensor() const { return options_.sensor; }
  const UrgModel& urg_model() const { return urg_; }
  const StructuredLightSensor* structured_light() const { return structured_light_ ? &*structured_light_ : nullptr; }

 private:
  ScanOutcome integrate_planar(TerrainMapper& mapper);
  bool packed_route(std::span<const std::uint8_t> beam_tags) const;
  ScanOutcome push_packed(const UrgRawScan& raw, const TrunkPose& pose, TerrainMapper& mapper,
                          std::span<const std::uint8_t> beam_tags);
  bool collect_hits(const TerrainMapper& mapper);
  void collect_beams(const TrunkPose& pose, const TerrainMapper& mapper);
  void collect_scan(const PlanarScan& scan, const TrunkPose& pose, const TerrainMapper& mapper);
  ScanStats integrate_collecting(const PlanarScan& scan, const TrunkPose& pose, TerrainMapper& mapper);
  void clear_visible(const PlanarBeams& beams, const TrunkPose& pose, TerrainMapper& mapper);
  bool clear_formed(double time_s, std::size_t beams, const TrunkPose& pose, TerrainMapper& mapper);
  ScanOutcome integrate_batch(std::optional<double> time_s, const TrunkPose& pose, TerrainMapper& mapper);
  void require(SensorKind kind) const;
  VisibilityClearing& visibility_for(TerrainMapper& mapper);
  void clear_visible_batch(const TrunkPose& pose, TerrainMapper& mapper);
  void finish_visibility(TerrainMapper& mapper);
  void report(const ScanPayload& payload, std::optional<double> time_s, const ScanStats& stats,
              std::span<const std::uint8_t> removed);

  PipelineOptions options_;
  UrgModel urg_;
  std::optional<StructuredLightSensor> structured_light_;
  PointCloudSensor points_sensor_;
  TaggedScanFilter filters_;
  PlanarScan scan_, filtered_;
  // The packed route: the beams, the removal flags observers see (none), and
  // the raw values from which last_scan() makes the planar scan on demand.
  PlanarBeams beams_;
  std::vector<std::uint8_t> no_removals_;
  UrgRawScan last_raw_;
  bool last_packed_ = false;
  mutable bool last_raw_converted_ = false;
  mutable PlanarScan unfiltered_;
  mutable std::vector<std::uint8_t> normalize_mask_;
  PointBatch batch_;
  ScanPayload batch_payload_;
  std::size_t pushed_ = 0;
  bool collect_ = false;
  std::vector<IntegratedPoint> points_;
  std::vector<double> scan_cos_, scan_sin_;  // a planar scan's directions, where its points are formed here
  std::vector<PipelineObserver*> observers_;
  std::optional<VisibilityClearing> visibility_;  // made at the first scan, for its mapper's window
  std::vector<double> visibility_angles_, visibility_cos_, visibility_sin_;  // the scan's beam directions
  PipelineStats stats_;
};

}  // namespace stridemap
