#pragma once
// One sweep of a 2D range sensor in the sensor's own frame, already converted
// to SI units by a sensor model (sensors/). Reused between scans so that the
// per-scan path allocates nothing once the vectors have grown.
#include <cstddef>
#include <vector>

namespace stridemap {

struct PlanarScan {
  double time_s = 0.0;  ///< acquisition time of the scan [s]
  /// Beam direction in the scan plane: 0 ahead, positive to the left [rad].
  std::vector<double> angle_rad;
  /// Measured range, NaN where the sensor gave no valid return [m].
  std::vector<double> range_m;
  /// Maximum error of each range (Delta r of eq. 6) [m].
  std::vector<double> range_error_m;

  std::size_t size() const { return range_m.size(); }
  void resize(std::size_t beams) {
    angle_rad.resize(beams);
    range_m.resize(beams);
    range_error_m.resize(beams);
  }
};

}  // namespace stridemap
