#pragma once
// The rocky mock-up walk (paper section 6.2, Figs. 22-24): the robot walks a
// path over the rocky terrain with its gait and an imperfect pose estimate,
// mapping with its local map; the maps are scored against the scene, and
// the walk is repeated over a sweep of pose-error levels to show how the
// map's error grows with the pose error.
//
// Results are from the simulator, not from a real robot.
#include <cstdint>
#include <functional>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "stridemap/core/progress.hpp"
#include "stridemap/experiments/attitude_calibration.hpp"
#include "stridemap/sensors/range_calibration.hpp"
#include "stridemap/experiments/walk.hpp"
#include "stridemap/experiments/walk_sensor.hpp"

namespace stridemap {

/// Makes a fresh sensor for one walk (the simulators keep per-run state).
/// Every call must make the same sensor with the same seed: the sweep's
/// walks replay what the main walk's sensor simulated when it can
/// (WalkSensor::replay), and simulate again otherwise.
using WalkSensorFactory = std::function<std::unique_ptr<WalkSensor>(const Scene& scene, const UpdateOptions& update)>;

struct RockyWalkOptions {
  /// The main walk: default gait, default pose errors (h_ref from the map),
  /// the paper's 100 x 100 local map of 10 mm cells, fill-in.
  WalkOptions walk{};
  /// Pose-error levels of the sweep, as factors on every sigma and bias of
  /// walk.pose_errors (each >= 0; the main walk's own level is reused).
  std::vector<double> pose_error_scales{0.0, 0.5, 1.0, 2.0, 4.0};
  /// Each level is walked with h_ref from each of these sources: with
  /// `truth` the rows show what the IMU, camera and leg errors alone do; with
  /// `map` they add the paper's h_ref read from the map (section 5.2); with
  /// `map_mean` the same from the cells' means.
  std::vector<ReferenceElevationSource> sweep_references{
      ReferenceElevationSource::truth, ReferenceElevationSource::map, ReferenceElevationSource::map_mean};

  /// Before each walk, measure the IMU's pitch and roll biases on a flat
  /// floor (attitude_calibration.hpp) and take them off its readings. Off
  /// by default (the paper's robot had no such step).
  bool calibrate_attitude = false;
  AttitudeCalibrationOptions calibration{};

  /// Told the scans walked so far of all the walks (main and sweep).
  ProgressCallback progress{};

  /// Throws InputError for a negative or non-finite scale.
  void validate() const;
};

struct PoseSweepRow {
  std::string label;     ///< "x0.5", ...
  double scale = 0.0;    ///< factor on walk.pose_errors
  ReferenceElevationSource reference = ReferenceElevationSource::map;
  PoseErrorStats pose;
  MapScore score;        ///< of the mosaic over the swept area
  std::size_t unknown_swept_cells = 0;
};

struct RockyWalkResult {
  std::string sensor;
  WalkResult main;
  std::vector<PoseSweepRow> sweep;
  /// The main walk's calibration, with calibrate_attitude.
  std::optional<AttitudeCalibration> calibration;
  /// The URG's range calibration on a wall before the walk
  /// (wall_range_calibration.hpp), when the caller made one; the sensor
  /// factory applies it, run_rocky_walk only reports it.
  std::optional<RangeCalibrationFit> range_calibration;
  /// Whether the URG's readings carried the receiver's range-intensity
  /// coupling (mixed pixels on and UrgSimOptions::receiver.enabled), when
  /// the caller says; like range_calibration, only reported.
  std::optional<bool> receiver_coupling;
};

/// Runs the main walk and the sweep; deterministic for options.walk.seed.
/// Everything is validated before the first scan.
RockyWalkResult run_rocky_walk(const Scene& scene, const WalkPath& path, const WalkSensorFactory& make_sensor,
                               const RockyWalkOptions& options);

}  // namespace stridemap
