#include "stridemap/experiments/rocky_walk.hpp"

#include <cmath>
#include <cstdio>

#include "stridemap/core/error.hpp"

namespace stridemap {

void RockyWalkOptions::validate() const {
  for (std::size_t k = 0; k < pose_error_scales.size(); ++k) {
    const double s = pose_error_scales[k];
    if (!(std::isfinite(s) && s >= 0.0)) {
      throw InputError("rocky walk: pose error scale [" + std::to_string(k) + "] must be a number >= 0, got " +
                       std::to_string(s));
    }
  }
  walk.pose_errors.validate();
  walk.gait.validate();
  walk.height_fusion.validate();
  if (calibrate_attitude) calibration.validate();
}

RockyWalkResult run_rocky_walk(const Scene& scene, const WalkPath& path, const WalkSensorFactory& make_sensor,
                               const RockyWalkOptions& options) {
  options.validate();
  RockyWalkResult result;
  // Every walk follows the same path, so all have the main walk's scans.
  std::size_t walks = 1;
  for (std::size_t r = 0; r < options.sweep_references.size(); ++r) {
    for (const double scale : options.pose_error_scales) {
      walks += !(scale == 1.0 && options.sweep_references[r] == options.walk.pose_errors.reference);
    }
  }
  std::size_t walks_done = 0;
  const auto walk_reporting = [&](WalkSensor& sensor, const WalkOptions& walk) {
    WalkRun run(scene, path, sensor, walk);
    const std::size_t per_walk = run.total_scans(), before = walks_done * per_walk;
    while (!run.done()) {
      run.step();
      if (options.progress) options.progress(before + run.scans_done(), walks * per_walk);
    }
    ++walks_done;
    return run.finish();
  };
  // The sweep's walks follow the main walk's true trajectory with the same
  // seed, and the pose estimate enters only after the simulation, so they
  // replay the main walk's measurements instead of simulating them again
  // (the simulator is nearly all of the run's time).
  std::shared_ptr<const WalkRecording> recording;
  // The calibration's own sensor sees a floor of the scene's reflectance.
  const auto calibrated = [&](WalkOptions walk) {
    if (!options.calibrate_attitude) return walk;
    std::unique_ptr<WalkSensor> sensor =
        make_sensor(flat_calibration_floor(scene.terrain.reflectance), walk.mapper.update);
    const AttitudeCalibration c = calibrate_attitude_on_flat_floor(
        *sensor, walk.pose_errors, walk.gait, walk.mapper, walk.seed ^ 0xCA11B4A7EULL, options.calibration);
    walk.imu_pitch_correction_rad = c.pitch_bias_rad;
    walk.imu_roll_correction_rad = c.roll_bias_rad;
    if (!result.calibration) result.calibration = c;
    return walk;
  };
  const auto walk_with = [&](const PoseErrorOptions& errors) {
    WalkOptions walk = options.walk;
    walk.pose_errors = errors;
    walk = calibrated(walk);
    std::unique_ptr<WalkSensor> sensor = make_sensor(scene, walk.mapper.update);
    if (recording) sensor->replay(recording);
    return walk_reporting(*sensor, walk);
  };
  // The main walk first: it also checks the scene, path and mount before
  // the sweep spends any time.
  {
    std::unique_ptr<WalkSensor> sensor = make_sensor(scene, options.walk.mapper.update);
    result.sensor = sensor->name();
    const bool sweep_follows = walks > 1;
    if (sweep_follows) sensor->start_recording();
    result.main = walk_reporting(*sensor, calibrated(options.walk));
    if (sweep_follows) recording = sensor->recording();
  }
  const auto row_of = [](std::string label, double scale, ReferenceElevationSource source, const WalkResult& w) {
    return PoseSweepRow{std::move(label), scale, source, w.pose_errors, w.mosaic_score, w.unknown_swept_cells};
  };
  for (const ReferenceElevationSource reference : options.sweep_references) {
    for (const double scale : options.pose_error_scales) {
      char label[32];
      std::snprintf(label, sizeof label, "x%g", scale);
      PoseErrorOptions errors = options.walk.pose_errors.scaled(scale);
      errors.reference = reference;
      if (scale == 1.0 && reference == options.walk.pose_errors.reference) {
        result.sweep.push_back(row_of(label, scale, reference, result.main));
      } else {
        result.sweep.push_back(row_of(label, scale, reference, walk_with(errors)));
      }
    }
  }
  return result;
}

}  // namespace stridemap
