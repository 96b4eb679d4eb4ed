#include "stridemap/experiments/wall_range_calibration.hpp"

#include <cmath>
#include <string>
#include <vector>

#include "stridemap/core/error.hpp"
#include "stridemap/core/pose.hpp"
#include "stridemap/sim/scene.hpp"

namespace stridemap {
namespace {

constexpr double kWallThickness_m = 0.1;
// Level and high enough that the beams near head-on meet the wall well
// above the floor at every distance.
constexpr double kSensorHeight_m = 0.3;

Scene wall_scene(double distance_m, double reflectance) {
  Scene scene;
  scene.terrain.min_x_m = -1.0;
  scene.terrain.min_y_m = -2.0;
  scene.terrain.max_x_m = 3.0;
  scene.terrain.max_y_m = 2.0;
  BoxObject wall;
  wall.name = "wall";
  wall.center_x_m = distance_m + kWallThickness_m / 2.0;
  wall.length_m = kWallThickness_m;
  wall.width_m = 3.0;
  wall.height_m = 1.0;
  wall.reflectance = reflectance;
  scene.boxes.push_back(wall);
  return scene;
}

}  // namespace

void WallRangeCalibrationOptions::validate() const {
  if (!(std::isfinite(nearest_m) && nearest_m > 0.0 && std::isfinite(farthest_m) && farthest_m > nearest_m &&
        farthest_m <= 2.5)) {
    throw InputError("range calibration: need 0 < nearest_m < farthest_m <= 2.5 m, got " + std::to_string(nearest_m) +
                     " and " + std::to_string(farthest_m));
  }
  if (!(std::isfinite(step_m) && step_m > 0.0 && (farthest_m - nearest_m) / step_m >= 3.0 &&
        (farthest_m - nearest_m) / step_m <= 1000.0)) {
    throw InputError("range calibration: step_m must give 4 to 1001 distances, got " + std::to_string(step_m));
  }
  if (scans_per_distance < 1 || scans_per_distance > 1000) {
    throw InputError("range calibration: scans_per_distance must be 1..1000, got " + std::to_string(scans_per_distance));
  }
  if (beams_each_side < 0 || beams_each_side > 10) {
    throw InputError("range calibration: beams_each_side must be 0..10, got " + std::to_string(beams_each_side));
  }
  if (!(wall_reflectance > 0.0 && wall_reflectance <= 1.0)) {
    throw InputError("range calibration: wall_reflectance must be in (0, 1], got " + std::to_string(wall_reflectance));
  }
}

RangeCalibrationFit calibrate_range_on_wall(const UrgParameters& urg, const UrgSimOptions& sim, std::uint64_t seed,
                                            const WallRangeCalibrationOptions& options) {
  options.validate();
  SensorMount level;
  level.height_m = kSensorHeight_m;
  level.pitch_rad = 0.0;
  const int first = urg.front_step - options.beams_each_side, last = urg.front_step + options.beams_each_side;
  if (first < urg.first_step || last > urg.last_step) {
    throw InputError("range calibration: the beams around the front step " + std::to_string(urg.front_step) +
                     " are not all measured (steps " + std::to_string(urg.first_step) + ".." +
                     std::to_string(urg.last_step) + ")");
  }
  const UrgModel model(urg);
  std::vector<double> measured_m, true_m;
  UrgRawScan raw;
  const int distances = static_cast<int>(std::floor((options.farthest_m - options.nearest_m) / options.step_m + 1e-9)) + 1;
  for (int d = 0; d < distances; ++d) {
    const double distance_m = options.nearest_m + d * options.step_m;
    // One simulator per distance, each with its own seed, so a distance's
    // noise does not depend on how many came before it.
    UrgSimulator simulator(wall_scene(distance_m, options.wall_reflectance), urg, sim,
                           seed ^ (0x9E3779B97F4A7C15ULL * static_cast<std::uint64_t>(d + 1)));
    for (int s = 0; s < options.scans_per_distance; ++s) {
      simulator.scan(TrunkPose{}, level, s * urg.scan_period_s, raw);
      for (int step = first; step <= last; ++step) {
        const std::uint32_t value = raw.values_mm[static_cast<std::size_t>(step - raw.first_step)];
        if (model.classify(value) != UrgValueClass::valid) continue;
        measured_m.push_back(value * 0.001);
        true_m.push_back(distance_m / std::cos(urg.step_angle_rad(step)));
      }
    }
  }
  if (measured_m.size() < 4 * static_cast<std::size_t>(distances) / 2) {
    throw InputError("range calibration: only " + std::to_string(measured_m.size()) +
                     " valid readings of the wall came back; the sensor model drops the target");
  }
  return fit_range_calibration(measured_m, true_m);
}

}  // namespace stridemap
