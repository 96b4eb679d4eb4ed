#pragma once
// The range sensor on a walking robot, as the walk experiments see it: it
// measures the scene from the TRUE pose, hands its data to the mapper with
// the ESTIMATED pose, and tells where it would meet a flat floor (for the
// area it sweeps). The URG-04LX implements it here
// (urg_walk_sensor.hpp); the structured-light sensor plugs in the same way.
#include <cstddef>
#include <memory>
#include <string>
#include <vector>

#include <Eigen/Core>

#include "stridemap/core/pose.hpp"
#include "stridemap/core/terrain_mapper.hpp"
#include "stridemap/pipeline/scan_integrator.hpp"

namespace stridemap {

/// One measured point as the mapper placed it (estimated pose), for the
/// mount analysis: the pipeline hands them back (ScanIntegrator::last_points).
using ObservedPoint = IntegratedPoint;

/// What a sensor simulated during one walk, kept so that another walk
/// along the same true trajectory, with a sensor made with the same seed,
/// replays it instead of simulating again: the simulation depends on the
/// true pose, the time and the seed only, the pose estimate enters after it
/// (the rocky walk's pose-error sweep). Each sensor keeps its own kind.
class WalkRecording {
 public:
  virtual ~WalkRecording() = default;
};

class WalkSensor {
 public:
  virtual ~WalkSensor() = default;

  /// "urg", "structured-light".
  virtual std::string name() const = 0;
  virtual const SensorMount& mount() const = 0;
  /// Time between measurements [s] (URG: 0.1).
  virtual double frame_period_s() const = 0;

  /// Simulates one measurement from `truth` at `time_s` and integrates what
  /// the sensor delivers with `estimate`. A sensor whose pre-processing
  /// holds one measurement back integrates the previous one with its own
  /// estimate. Returns the mapper's statistics of what it integrated.
  virtual ScanStats measure(const TrunkPose& truth, const TrunkPose& estimate, double time_s,
                            TerrainMapper& mapper) = 0;
  /// From now on keep what measure() simulates; false when this sensor
  /// cannot (the walk then simply simulates again).
  virtual bool start_recording() { return false; }
  /// What was kept since start_recording() (nullptr when not recording).
  virtual std::shared_ptr<const WalkRecording> recording() const { return nullptr; }
  /// Makes measure() take its measurements from `recording` (made by a
  /// sensor of this kind and seed) instead of simulating them. measure()
  /// then throws std::logic_error when asked for a true pose or time other
  /// than the recording's next: a replay never silently differs from a
  /// simulation. False when this sensor cannot replay it.
  virtual bool replay(std::shared_ptr<const WalkRecording> recording) {
    (void)recording;
    return false;
  }

  /// Integrates whatever is still held back at the end of a walk.
  virtual ScanStats flush(TerrainMapper& mapper) = 0;

  /// Whether measure() fills last_points() (off by default: it costs time).
  virtual void set_collect_points(bool collect) = 0;
  /// The points integrated by the last measure() / flush() when collecting.
  virtual const std::vector<ObservedPoint>& last_points() const = 0;

  /// The visibility clean-up of the last measure() (nullptr when the
  /// sensor has none or it is off): what it cleared, for scoring.
  virtual const VisibilityClearing* visibility() const { return nullptr; }

  /// Where the sensor's rays or stripe meet the plane z = floor_elevation_m
  /// seen from `pose`, within max_range_m: one entry per ray (or stripe
  /// column), always the same count, NaN where a ray misses. Consecutive
  /// calls pair entries by index to sweep the area between them.
  virtual void floor_trace(const TrunkPose& pose, double floor_elevation_m, double max_range_m,
                           std::vector<Eigen::Vector2d>& out) const = 0;
};

/// Throws InputError "sensor mount <name>: ..." when the mount cannot see
/// the ground: the sensor at or below the terrain it stands on (height <= 0),
/// pitched past vertical (|alpha| >= 90 deg), or with no ray meeting a flat
/// floor ahead of the sensor within max_range_m from the nominal pose. Run
/// before any work.
void check_mount_sees_ground(const WalkSensor& sensor, double max_range_m, const std::string& mount_name);

}  // namespace stridemap
