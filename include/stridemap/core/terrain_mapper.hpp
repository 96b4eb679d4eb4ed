#pragma once
// Integrates 2D scans (or points from any sensor) into an ElevationMap with
// the update rule of section 5.2. This is the per-scan hot path: it
// allocates nothing, and it rejects bad samples and poses one by one,
// counting them, so that nothing non-finite ever reaches a map layer.
#include <cstddef>
#include <cstdint>
#include <optional>
#include <span>
#include <utility>
#include <vector>

#include "stridemap/core/cell_box.hpp"
#include "stridemap/core/changed_rows.hpp"
#include "stridemap/core/grid_map.hpp"
#include "stridemap/core/map_update.hpp"
#include "stridemap/core/max_elevation_change.hpp"
#include "stridemap/core/planar_beams.hpp"
#include "stridemap/core/planar_scan.hpp"
#include "stridemap/core/planar_scan_points.hpp"
#include "stridemap/core/pose.hpp"
#include "stridemap/core/sensor_point.hpp"
#include "stridemap/core/sensor_transform.hpp"
#include "stridemap/core/window_move_listener.hpp"

namespace stridemap {

struct MapperOptions {
  GridOptions grid;
  UpdateOptions update;
  /// Re-centre the window on the robot (by whole cells) before each scan.
  /// Off for a fixed test bed such as the cart on the rail.
  bool follow_robot = true;
  /// Where the window centre sits relative to the trunk, along the heading
  /// [m]. 0 keeps the map robot-centred as in the paper; a positive value
  /// keeps more of the terrain ahead, where a tilted sensor looks.
  double window_ahead_m = 0.0;
  /// Reject a scan whose time_s is not finite or not later than that of the
  /// last accepted scan (out of order, or the same scan delivered twice):
  /// the travel term of Delta z_max assumes time runs forward, and a
  /// duplicate would raise the certainty twice for one measurement. Off for
  /// sources without timestamps (every time_s 0).
  bool reject_stale_scans = true;
};

/// What happened to one scan's beams.
struct ScanStats {
  std::size_t beams = 0;
  std::size_t integrated = 0;        ///< written into a cell (first, plausible or implausible)
  std::size_t first = 0;             ///< hit a cell that was unknown
  std::size_t plausible = 0;         ///< raised the certainty of a known cell
  std::size_t implausible = 0;       ///< disagreed with the cell beyond Delta z_max
  std::size_t replaced = 0;          ///< gated rule: replaced a cell after repeated contradictions
  std::size_t invalid_range = 0;     ///< NaN, infinite or non-positive range (incl. sensor error codes)
  std::size_t invalid_beam = 0;      ///< non-finite angle or range error, negative range error
  std::size_t outside_map = 0;       ///< valid, but outside the window
  bool pose_rejected = false;        ///< the pose had a non-finite field: nothing was used
  /// MapperOptions::reject_stale_scans: the time was not finite or not
  /// later than the last accepted scan's; nothing was used.
  bool time_rejected = false;
  std::size_t cells_reset_by_move = 0;

  /// Counts add up; a flag is set when either side has it.
  ScanStats& operator+=(const ScanStats& other);
};

/// Running totals since construction (or reset_totals()).
struct MapperTotals {
  std::size_t scans = 0;
  std::size_t scans_rejected_for_pose = 0;
  std::size_t scans_rejected_for_time = 0;  ///< non-finite, out-of-order or duplicate time_s
  std::size_t beams = 0;
  std::size_t integrated = 0;
  std::size_t invalid_range = 0;
  std::size_t invalid_beam = 0;
  std::size_t outside_map = 0;
  std::size_t implausible = 0;

  MapperTotals& operator+=(const MapperTotals& other);
};

/// A measured point already in the map frame, for sensors whose model is not
/// a range along a beam (structured light, eq. 8).
struct MapPoint {
  double x_m = 0.0;
  double y_m = 0.0;
  double elevation_m = 0.0;              ///< h_m of eq. (9)
  double max_elevation_change_m = 0.0;   ///< Delta z_max of eq. (8) for this point
};

/// For a reader that keeps its own state up to date from changed_rows()
/// (the visibility clean-up's row and column maxima): whether the rows hold
/// every change to the map since it last looked, or something happened they
/// do not show and it must look at the whole map.
struct MapChanges {
  /// Which mapper: a new number for every mapper made, copied or assigned.
  std::uint64_t mapper = 0;
  /// Changes changed_rows() does not show: bumped by every call of the
  /// non-const map() (the caller may write through it) and by every window
  /// move made with a listener (it may write tiles into the window).
  std::uint64_t unrecorded = 0;
  /// Scans accepted so far; each one's cells are in changed_rows() until it
  /// is cleared.
  std::uint64_t scans = 0;
  /// `scans` when changed_rows() was last cleared: the rows hold the cells
  /// of every later scan.
  std::uint64_t record_from_scan = 0;
};

namespace detail {
// A number no other mapper has: a copy or an assignment draws a new one.
class MapperIdentity {
 public:
  // noexcept, so that a mapper still moves without copying its layers
  // where a container asks for a move that cannot throw.
  MapperIdentity() noexcept : value_(next()) {}
  MapperIdentity(const MapperIdentity&) noexcept : value_(next()) {}
  MapperIdentity& operator=(const MapperIdentity&) noexcept {
    value_ = next();
    return *this;
  }
  std::uint64_t value() const { return value_; }

 private:
  static std::uint64_t next() noexcept;
  std::uint64_t value_;
};
}  // namespace detail

class TerrainMapper {
 public:
  /// Throws InputError for non-finite or negative options or mount.
  TerrainMapper(const MapperOptions& options, const SensorMount& mount);

  /// Integrates one scan taken at `pose` (the estimate, not ground truth).
  /// A non-finite pose, or (reject_stale_scans) a scan.time_s that is not
  /// later than the last accepted one, rejects the whole scan, counted.
  /// Packs the scan's valid beams and takes the packed path below.
  ScanStats integrate(const PlanarScan& scan, const TrunkPose& pose);
  /// The same for beams a sensor model packed itself (core/planar_beams.hpp):
  /// the per-point hot path. The maps are those integrate(PlanarScan) and
  /// integrate_scan(PlanarScanPoints) make, bit for bit.
  ScanStats integrate(const PlanarBeams& beams, const TrunkPose& pose);
  /// The same, handing each point that passed the checks to
  /// `sink(index, map_point, sensor_point)` before it is applied.
  template <class Sink>
  ScanStats integrate(const PlanarScan& scan, const TrunkPose& pose, Sink&& sink);
  /// Integrates a scan of any sensor model (core/sensor_point.hpp): the
  /// source gives each point's offset from the sensor origin and its height
  /// error; Delta z_max is formed here (core/max_elevation_change.hpp) for
  /// every sensor alike. With a time, the same order check as integrate().
  template <class Source, class Sink = NoPointSink>
  ScanStats integrate_scan(const Source& source, const TrunkPose& pose, std::optional<double> time_s,
                           Sink&& sink = {});
  /// Integrates points with their own Delta z_max; `pose` moves the window.
  /// With a time, the same order check as integrate() applies.
  ScanStats integrate_points(std::span<const MapPoint> points, const TrunkPose& pose,
                             std::optional<double> time_s = std::nullopt);

  /// The valid beams of the last scan as integrate(PlanarBeams) formed them
  /// in its vector pass (eq. 5 and 6): what the visibility clean-up would
  /// form again, the same doubles. Null when the last scan (accepted or
  /// not) took another route or they were not kept (keep_beam_hits()). The
  /// pointers are good until the next scan; range_error_m and range_m
  /// point into the beams integrated.
  struct BeamHits {
    std::size_t beams = 0, count = 0;  ///< as PlanarBeams
    double time_s = 0.0;
    double yaw_rad = 0.0, pitch_rad = 0.0, roll_rad = 0.0;  ///< of the pose
    Eigen::Vector3d origin_m = Eigen::Vector3d::Zero();     ///< the sensor's, map frame
    const double* x_m = nullptr;  ///< hit, map frame
    const double* y_m = nullptr;
    const double* z_m = nullptr;
    const double* height_error_m = nullptr;  ///< the sensor's bound, without the motion terms
    const double* range_error_m = nullptr;
    const double* range_m = nullptr;
  };
  const BeamHits* last_beam_hits() const { return hits_valid_ ? &hits_ : nullptr; }
  /// Whether integrate(PlanarBeams) keeps them: off by default, since the
  /// four stores a beam cost the update some 2.5 % of its instructions.
  void keep_beam_hits(bool keep) { keep_hits_ = keep; }

  /// Time of the last accepted scan that carried one.
  std::optional<double> last_scan_time_s() const { return previous_time_s_; }
  /// Pose of the last accepted scan.
  std::optional<TrunkPose> last_pose() const { return previous_pose_; }

  /// Motion since the previous accepted scan (zero before the first one).
  ScanMotion motion_to(const TrunkPose& pose) const;

  const ElevationMap& map() const { return map_; }
  /// Counted in changes().unrecorded at every call: write through the
  /// reference it returns before the next scan, or call it again.
  ElevationMap& map() {
    ++unrecorded_changes_;
    return map_;
  }
  /// The map for writes that raise no cell's elevation and make no unknown
  /// cell known: layers derived from it (the foothold layers), the
  /// visibility clean-up's lowering and clearing. Not counted in changes().
  ElevationMap& map_without_raising() { return map_; }
  /// What a reader of changed_rows() needs to know whether they hold every
  /// change since it last looked.
  MapChanges changes() const { return {identity_.value(), unrecorded_changes_, scans_, record_from_scan_}; }
  const MapperOptions& options() const { return options_; }
  const SensorMount& mount() const { return mount_; }
  const MapperTotals& totals() const { return totals_; }

  /// Bounding box of the cells that readings were applied to since the
  /// last take_changed_cells() (global indices; a window move may have
  /// reset some since). What derived layers (core/foothold.hpp) redo.
  const CellBox& changed_cells() const { return changed_; }
  /// Adds cells changed other than by readings (the visibility clean-up,
  /// core/visibility_clearing.hpp), so that derived layers redo them too.
  void note_changed_cells(const CellBox& box) {
    changed_.add(box);
    changed_rows_.add(box);
  }
  /// The same cells row by row (core/changed_rows.hpp): per row of cells
  /// the smallest and largest column written, finer than the box for a
  /// diagonal scan line. Cleared with the box.
  const ChangedRows& changed_rows() const { return changed_rows_; }
  /// Forgets the changed cells (box and rows); allocates nothing.
  void clear_changed_cells() {
    changed_.clear();
    changed_rows_.clear();
    record_from_scan_ = scans_;
  }
  CellBox take_changed_cells() {
    const CellBox box = changed_;
    clear_changed_cells();
    return box;
  }

  /// Told of every move of the window that follow_robot makes (a map larger
  /// than the window: mapfile/tile_store.hpp); nullptr for none. Not owned: it
  /// must outlive the mapper or be unset first.
  void set_window_listener(WindowMoveListener* listener) { window_listener_ = listener; }
  WindowMoveListener* window_listener() const { return window_listener_; }

 private:
  // locate_beams()'s turning terms: none, finite (the turn term is never
  // NaN), or unbounded (a NaN turn term, inf * 0, becomes infinite).
  enum class Turning { none, finite, unbounded };
  bool accept(const TrunkPose& pose, std::optional<double> time_s, ScanStats& stats);
  void follow(const TrunkPose& pose, ScanStats& stats) {
    follow(pose, std::cos(pose.yaw_rad), std::sin(pose.yaw_rad), stats);
  }
  // The same with cos and sin of pose.yaw_rad already made.
  void follow(const TrunkPose& pose, double cos_yaw, double sin_yaw, ScanStats& stats);
  // motion_to with the sensor origin of `pose` already made; the previous
  // scan's is kept when integrate(PlanarBeams) made it.
  ScanMotion motion_to(const TrunkPose& pose, const Eigen::Vector3d& origin) const;
  void apply(double x_m, double y_m, double h_m, double dz_max, ScanStats& stats);
  void finish(const TrunkPose& pose, std::optional<double> time_s, const ScanStats& stats);
  void refresh_beam_directions(const std::vector<double>& angles);
  void pack(const PlanarScan& scan);
  template <Turning kTurning, bool kCheckXY, bool kKeepHits>
  void locate_beams(const PlanarBeams& beams, const PlanarBeamGeometry& geometry, const MaxElevationChange& bound,
                    const Eigen::Vector3d& origin);
  template <bool kKeepHits>
  void locate_beams_for(Turning turning, bool check_xy, const PlanarBeams& beams, const PlanarBeamGeometry& geometry,
                        const MaxElevationChange& bound, const Eigen::Vector3d& origin);
  void update_located(std::size_t count, ScanStats& stats);
  void integrate_far(const PlanarBeams& beams, const PlanarBeamGeometry& geometry, const MaxElevationChange& bound,
                     const Eigen::Vector3d& origin, ScanStats& stats);
  static void check_scan_lengths(const PlanarScan& scan);

  MapperOptions options_;
  SensorMount mount_;
  ElevationMap map_;
  MapperTotals totals_;
  CellBox changed_;
  ChangedRows changed_rows_;
  // update_located()'s changed columns per window-local row, int32 so the
  // per-reading update stays two loads and two stores (reset after use).
  std::vector<std::int32_t> row_lo_, row_hi_;
  WindowMoveListener* window_listener_ = nullptr;
  // changes(): what changed_rows() may not show.
  detail::MapperIdentity identity_;
  std::uint64_t unrecorded_changes_ = 0, scans_ = 0, record_from_scan_ = 0;
  std::optional<TrunkPose> previous_pose_;
  // The sensor origin of previous_pose_, when known (per-scan work kept).
  Eigen::Vector3d previous_origin_ = Eigen::Vector3d::Zero();
  bool previous_origin_known_ = false;
  // mount_rotation(mount_): the mount never changes, so neither does M.
  Eigen::Matrix3d mount_rotation_;
  std::optional<double> previous_time_s_;
  std::vector<double> cached_angles_, cos_angle_, sin_angle_;
  PlanarBeams packed_;  // integrate(PlanarScan)'s beams
  // Per valid beam of the scan being integrated: its cell's row and column
  // from the window's corner (a row beyond the window's when outside it)
  // and h_m, Delta z_max as the map stores them; update_located() packs
  // each inside beam's slot and index side by side in located_slot_beam_
  // (one pointer for the cell loop, which is short of registers).
  std::vector<std::int32_t> located_row_, located_column_, located_slot_beam_;
  std::vector<float> located_h_m_, located_dz_max_m_;
  // The same beams' hits and error bounds in doubles, for last_beam_hits().
  std::vector<double> hit_x_m_, hit_y_m_, hit_z_m_, hit_error_m_;
  BeamHits hits_;
  bool hits_valid_ = false, keep_hits_ = false;
  // update_located()'s slot of a window-local row (times n) and column, for
  // the window's corner slot tables_corner_slot_.
  std::vector<std::uint32_t> row_slot_, column_slot_;
  std::size_t tables_corner_slot_ = 0;
};

/// True when every field of the pose is finite.
bool pose_is_finite(const TrunkPose& pose);

template <class Source, class Sink>
ScanStats TerrainMapper::integrate_scan(const Source& source, const TrunkPose& pose, std::optional<double> time_s,
                                        Sink&& sink) {
  ScanStats stats;
  stats.beams = source.size();
  if (!accept(pose, time_s, stats)) return stats;
  follow(pose, stats);
  const MaxElevationChange bound(motion_to(pose), source.inclination_rad(), mount_, options_.update, pose.yaw_rad);
  const Eigen::Vector3d origin = sensor_origin_in_map(pose, mount_);
  SensorPoint p;
  for (std::size_t i = 0; i < stats.beams; ++i) {
    switch (source.point(i, p)) {
      case PointStatus::ok: break;
      case PointStatus::invalid_range: ++stats.invalid_range; continue;
      case PointStatus::invalid_beam: ++stats.invalid_beam; continue;
    }
    const double dz_max = bound.at(p.height_error_m, p.offset_m);
    const double x_m = origin.x() + p.offset_m.x(), y_m = origin.y() + p.offset_m.y(),
                 h_m = origin.z() + p.offset_m.z();
    sink(i, Eigen::Vector3d(x_m, y_m, h_m), p);
    apply(x_m, y_m, h_m, dz_max, stats);
  }
  finish(pose, time_s, stats);
  return stats;
}

template <class Sink>
ScanStats TerrainMapper::integrate(const PlanarScan& scan, const TrunkPose& pose, Sink&& sink) {
  check_scan_lengths(scan);
  refresh_beam_directions(scan.angle_rad);
  const PlanarScanPoints source(scan, cos_angle_.data(), sin_angle_.data(), pose, mount_, options_.update);
  return integrate_scan(source, pose, scan.time_s, std::forward<Sink>(sink));
}

}  // namespace stridemap
