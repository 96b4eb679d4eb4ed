#include "stridemap/core/map_update.hpp"

#include <cmath>
#include <limits>

namespace stridemap {

double turning_travel_m(double point_distance_m, double sensor_turn_offset_m, double yaw_change_rad) {
  // Beyond a quarter turn between two scans tan() explodes; such a jump is a
  // pose glitch, and the bound then only needs to be "anything goes".
  const double theta = std::abs(yaw_change_rad);
  if (theta >= std::numbers::pi / 2) return std::numeric_limits<double>::infinity();
  const double delta_x = std::abs(point_distance_m + sensor_turn_offset_m) * std::tan(theta / 2.0);
  return delta_x * std::tan(theta);
}

double laser_max_elevation_change(const ElevationPartials& partials, double range_error_m,
                                  double travel_m, double gamma_rad, const UpdateOptions& options) {
  return std::abs(travel_m * std::tan(gamma_rad)) + elevation_error_bound_m(partials, range_error_m, options);
}

}  // namespace stridemap
