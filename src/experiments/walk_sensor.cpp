#include "stridemap/experiments/walk_sensor.hpp"

#include <cmath>
#include <numbers>
#include <string>

#include "stridemap/core/error.hpp"

namespace stridemap {

void check_mount_sees_ground(const WalkSensor& sensor, double max_range_m, const std::string& mount_name) {
  const SensorMount& m = sensor.mount();
  const std::string what = "sensor mount " + mount_name + ": ";
  if (!std::isfinite(m.height_m) || !std::isfinite(m.pitch_rad)) throw InputError(what + "height and pitch must be finite");
  if (m.height_m <= 0.0) {
    throw InputError(what + "height " + std::to_string(m.height_m) +
                     " m puts the sensor at or below the terrain it stands on; it must be above 0");
  }
  if (std::abs(m.pitch_rad) >= std::numbers::pi / 2) {
    throw InputError(what + "pitch " + std::to_string(m.pitch_rad * 180.0 / std::numbers::pi) +
                     " deg is past vertical; it must lie strictly between -90 and 90 deg");
  }
  std::vector<Eigen::Vector2d> trace;
  sensor.floor_trace(TrunkPose{}, 0.0, max_range_m, trace);
  // Ahead of the sensor: a wide scanner pitched up still meets the floor
  // behind the robot, which maps nothing the feet are going to.
  const double sensor_x = m.forward_offset_m;
  for (const Eigen::Vector2d& p : trace) {
    if (p.allFinite() && p.x() > sensor_x) return;
  }
  throw InputError(what + "no ray meets the ground ahead within " + std::to_string(max_range_m) + " m (height " +
                   std::to_string(m.height_m) + " m, pitch " + std::to_string(m.pitch_rad * 180.0 / std::numbers::pi) +
                   " deg): it cannot see the ground");
}

}  // namespace stridemap
