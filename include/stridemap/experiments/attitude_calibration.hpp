#pragma once
// The IMU's pitch and roll biases, measured before a walk: the robot stands
// on a flat floor and scans it from a few stances (trunk raised and
// lowered, pitched nose up and down with its legs), averaging its IMU over
// each stance. A roll bias tilts every scan line across; a pitch bias lifts
// the floor in proportion to how far ahead the line falls, and the stances
// move the line from about 0.25 to 0.55 m ahead, so a least-squares fit of
// (pitch bias, roll bias, sensor height offset) that flattens the floor
// separates them. The biases are then taken off the IMU's readings for the
// walk (WalkOptions::imu_pitch_correction_rad): the bias stays in the pose
// error model, the robot learns it, as a real one would on the lab floor.
//
// Results are from the simulator, not from a real robot.
#include <cstddef>
#include <cstdint>
#include <functional>
#include <memory>
#include <vector>

#include "stridemap/experiments/walk.hpp"
#include "stridemap/experiments/walk_sensor.hpp"

namespace stridemap {

struct AttitudeCalibrationOptions {
  /// The stances: trunk height change from the nominal [m] and trunk pitch
  /// [rad, positive nose down], paired by index. Defaults: +-4 cm and
  /// +-6 deg, all four combinations, within what Messor's legs reach. The
  /// pitch shows as the floor's height changing with its distance ahead
  /// across the stances; so does each stance's leg-height error (the
  /// encoders' noise averaged over its readings), which is what limits the
  /// pitch found (wide_stances() for a sensor that sees the floor at one
  /// distance only).
  std::vector<double> height_changes_m{-0.04, -0.04, 0.04, 0.04};
  std::vector<double> pitches_rad{0.105, -0.105, 0.105, -0.105};
  /// Scans per stance.
  int scans_per_stance = 20;
  /// IMU and leg-height readings averaged per stance: 400, a 100 Hz IMU
  /// over the 4 s the robot stands. Each is a draw of the pose-error model
  /// (white noise about the bias), so the average leaves 0.2 deg / 20 =
  /// 0.01 deg of noise beside the bias; with one reading per scan (20) the
  /// noise, 0.045 deg per stance, would be most of what is left.
  int imu_readings_per_stance = 400;
  /// Only points this close to the sensor count (the URG's favourable
  /// interval ends at 0.9 m, section 4.2) [m].
  double max_range_m = 0.9;

  /// Throws InputError naming the field.
  void validate() const;

  /// Nine stances, -4, -2 and 0 cm by -10, 0 and +10 deg, 16 s each (1600
  /// readings), 10 scans each: for structured light, whose stripe lies at
  /// one distance per stance and leaves the image when the trunk rises by
  /// 4 cm (two of the default stances then see nothing). Over seeds with
  /// an unbiased IMU the pitch found scatters 0.03 deg against the
  /// defaults' 0.2 deg. Not the URG's: its range error tilts the floor by
  /// an amount that depends on the stances' ranges, and this set finds a
  /// tilt that maps the walk higher (docs/walking.md).
  static AttitudeCalibrationOptions wide_stances();
};

struct AttitudeCalibration {
  double pitch_bias_rad = 0.0;  ///< estimate of the IMU's pitch bias
  double roll_bias_rad = 0.0;
  double height_offset_m = 0.0;  ///< the floor's mean height left after the fit
  std::size_t points = 0;
  double residual_rms_m = 0.0;   ///< of the flattened floor
};

/// Scans a flat floor with `sensor` (a fresh one, on a flat scene the caller
/// made), the pose estimate drawn from `errors` (h_ref from the truth: the
/// robot stands on the floor that defines zero), and fits the biases.
/// Deterministic for the seed. Throws InputError when the stances leave
/// too few points (under 100) to fit.
AttitudeCalibration calibrate_attitude_on_flat_floor(WalkSensor& sensor, const PoseErrorOptions& errors,
                                                     const GaitOptions& gait, const MapperOptions& mapper,
                                                     std::uint64_t seed,
                                                     const AttitudeCalibrationOptions& options = {});

/// A flat floor 4 x 4 m around the origin, of the given reflectance: the
/// calibration's scene.
Scene flat_calibration_floor(double reflectance);

}  // namespace stridemap
