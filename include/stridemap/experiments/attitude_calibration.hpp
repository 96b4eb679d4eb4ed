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
  /// +-6 deg, all four combinations, within what Messor's legs reach.
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
