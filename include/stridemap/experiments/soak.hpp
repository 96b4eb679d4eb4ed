#pragma once
// The soak test (docs/reliability.md): a long simulated run through the
// whole per-scan pipeline (simulated URG-04LX -> sensor model -> scan
// filters -> mapper -> snapshot for a planner thread, with the fill-in),
// over a path far larger than the map, with bad scans injected on purpose.
// It checks what must hold however long a robot runs: every scan is
// accounted for (used, or rejected and counted), no map layer ever holds an
// invalid value, memory stays flat (nothing allocated per scan), and the
// same seed gives bit-identical maps.
//
// The motion is pluggable (SoakMotion): the circuit below exists now; a
// walking robot's gait can take its place without touching the harness.
// Results come from the simulator, not from a real sensor.
#include <cstdint>
#include <functional>
#include <string>
#include <vector>

#include "stridemap/config/global_map_options.hpp"
#include "stridemap/core/progress.hpp"
#include "stridemap/core/terrain_mapper.hpp"
#include "stridemap/core/weighted_median_fill.hpp"
#include "stridemap/preprocess/scan_filter_chain.hpp"
#include "stridemap/sensors/urg04lx.hpp"
#include "stridemap/sim/scene.hpp"
#include "stridemap/sim/urg_simulator.hpp"

namespace stridemap {

/// Where the robot is at each scan of a soak run. Must depend only on the
/// scan index (and the motion's own settings), never on earlier calls, and
/// allocate nothing.
class SoakMotion {
 public:
  virtual ~SoakMotion() = default;
  /// `truth`: the pose the simulated sensor scans from. `estimate`: what
  /// the pose estimator would hand the mapper (truth plus its errors).
  virtual void pose_at(std::uint64_t scan, TrunkPose& truth, TrunkPose& estimate) const = 0;
  /// One line for reports.
  virtual std::string describe() const = 0;
};

struct CircuitOptions {
  double centre_x_m = 0.0;
  double centre_y_m = 0.0;
  /// Radius of the circle driven round and round [m]; 3 m makes a 6 m wide
  /// path over a 1 m map.
  double radius_m = 3.0;
  /// Travel per scan [m]: 1 cm at 10 Hz is Messor's slow walk.
  double step_m = 0.01;
  /// Trunk pitch and roll swing as a gait makes them [rad], with this
  /// period in scans, and the sensor height bobbing by height_amplitude_m.
  double sway_amplitude_rad = 0.02;
  double sway_period_scans = 24.0;
  double height_amplitude_m = 0.005;
  /// Standard deviation of the pitch and roll errors of the estimate [rad],
  /// well inside the mapper's 1 deg bounds.
  double estimate_sigma_rad = 0.002;
  std::uint64_t seed = 1;
};

/// Drives a circle counter-clockwise, heading along the tangent, the sensor
/// riding at the mount height above the scene's surface under the trunk.
/// Throws InputError for a non-positive radius or step or a non-finite field.
class CircuitMotion final : public SoakMotion {
 public:
  CircuitMotion(const Scene& scene, const CircuitOptions& options);
  void pose_at(std::uint64_t scan, TrunkPose& truth, TrunkPose& estimate) const override;
  std::string describe() const override;

 private:
  const Scene& scene_;
  CircuitOptions options_;
};

/// Bad input injected into the stream on purpose; each must be rejected and
/// counted by the mapper, and nothing else lost. 0 turns one off.
struct SoakFaults {
  std::uint64_t nan_pose_every = 997;     ///< the estimate of every n-th scan has a NaN roll
  std::uint64_t duplicate_every = 1009;   ///< every n-th scan is handed to the mapper twice
  std::uint64_t out_of_order_every = 1013;  ///< every n-th scan is followed by the one before it again
};

struct SoakOptions {
  std::uint64_t scans = 2000;
  std::uint64_t seed = 1;
  /// Default: the paper's 100 x 100 map of 1 cm cells following the robot,
  /// the window centred 0.3 m ahead where the tilted sensor looks.
  MapperOptions mapper = [] {
    MapperOptions m;
    m.window_ahead_m = 0.3;
    return m;
  }();
  SensorMount mount{};
  UrgParameters urg{};
  UrgSimOptions sim{};
  /// Default: the paper's chain (range clustering + scan sequence).
  std::vector<ScanFilterKind> filters{ScanFilterKind::range_clustering, ScanFilterKind::scan_sequence};
  FillOptions fill{};
  /// A snapshot is published for the planner every n-th scan (1 Hz at the
  /// URG's 10 Hz), with the fill-in of eq. (11) run on it; the mapper's own
  /// map is never filled.
  std::uint64_t publish_every = 10;
  /// Integrity check of the mapper's map and of the snapshot every n-th scan.
  std::uint64_t check_every = 1;
  /// Map hashes and memory are sampled every n-th scan (and after the last).
  std::uint64_t checkpoint_every = 1000;
  /// A planner thread takes snapshots throughout and checks each one.
  bool reader_thread = true;
  SoakFaults faults{};
  /// With a folder: the cells leaving the window go to a tiled global map
  /// there (mapfile/tile_store.hpp), which the window reloads on every lap; the
  /// run then checks the tiles at the end (SoakGlobalMap).
  GlobalMapOptions global_map{};
  /// Told the scans simulated so far (from the mapping thread).
  ProgressCallback progress{};
};

struct SoakCheckpoint {
  std::uint64_t scan = 0;           ///< scans simulated so far
  std::uint64_t map_hash = 0;       ///< map_layers_hash of the mapper's map
  std::uint64_t snapshot_hash = 0;  ///< ... of the latest (filled) snapshot
  std::size_t measured_cells = 0;
  std::size_t heap_in_use_bytes = 0;  ///< process_memory(); 0 when unknown
  std::size_t resident_bytes = 0;
  std::size_t global_map_tiles = 0;  ///< tiles on disk so far (0 without a global map)
};

/// The global map's check after a run: every cell the mapper ever measured
/// for the first time (ScanStats::first, summed) is on disk exactly once,
/// as a measured cell of a tile that loads (checksum) and holds no invalid
/// value. A cell lost on its way out or back would be measured "first"
/// again on the next lap; a cell invented would be on disk unmeasured.
struct SoakGlobalMap {
  bool enabled = false;
  std::size_t tiles_on_disk = 0;
  std::size_t tiles_written = 0;
  std::size_t tiles_read = 0;
  std::size_t cells_restored = 0;    ///< copied back into the window from tiles
  std::uint64_t first_measured = 0;  ///< ScanStats::first over the run
  std::uint64_t measured_on_disk = 0;
  std::uint64_t invalid_on_disk = 0;
  std::uint64_t bytes_on_disk = 0;
  std::string first_invalid;
};

struct SoakResult {
  std::string motion;
  std::uint64_t scans_simulated = 0;
  std::uint64_t scans_to_mapper = 0;  ///< including the injected repeats
  MapperTotals totals{};
  std::uint64_t beams_of_rejected_scans = 0;
  std::uint64_t injected_nan_poses = 0;     ///< NaN pose estimates handed to the mapper
  std::uint64_t injected_duplicates = 0;
  std::uint64_t injected_out_of_order = 0;
  std::uint64_t integrity_checks = 0;
  std::uint64_t invalid_cells = 0;  ///< summed over all checks; must be 0
  std::string first_invalid;        ///< where and what, when invalid_cells > 0
  std::uint64_t published = 0;
  std::uint64_t publishes_skipped = 0;
  std::uint64_t reader_snapshots = 0;      ///< snapshots the planner thread checked
  std::uint64_t reader_invalid_cells = 0;  ///< must be 0
  std::vector<SoakCheckpoint> checkpoints;
  /// Hash over every checkpoint's map and snapshot hashes: equal for equal runs.
  std::uint64_t run_hash = 0;
  double path_length_m = 0.0;
  double path_extent_x_m = 0.0;  ///< max - min of the true x over the run
  double path_extent_y_m = 0.0;
  std::uint64_t cells_reset_by_moves = 0;
  SoakGlobalMap global_map{};
  double wall_time_s = 0.0;

  /// What went wrong, one sentence each; empty when the run passed: a lost
  /// or miscounted scan, an invalid cell, memory that grew after the first
  /// checkpoint.
  std::vector<std::string> failures() const;
};

/// Runs the soak. `on_checkpoint` (optional) is called at each checkpoint,
/// e.g. to count allocations between two of them. Throws InputError for
/// unusable options (zero scans, zero intervals, invalid mapper or sensor
/// settings).
SoakResult run_soak(const Scene& scene, const SoakMotion& motion, const SoakOptions& options,
                    const std::function<void(const SoakCheckpoint&)>& on_checkpoint = {});

}  // namespace stridemap
