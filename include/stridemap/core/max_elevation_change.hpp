#pragma once
// The one place where a point's height uncertainty becomes Delta z_max.
//
// Every sensor model states how uncertain the height of each of its points
// is (the error part of eq. 6 for the laser, of eq. 8 for structured light,
// a per-point sigma for a generic point source). What the robot's motion
// between two scans adds is the same for all of them: d tan(gamma) for the
// measuring surface climbing a face (eq. 6, 7), plus the travel a turn
// gives a point at its horizontal distance from the sensor (Fig. 10), and
// the travel along the heading that a turn gives a point beside the turning
// centre, |y| |sin theta| (Fig. 10 leaves it out; a point 0.3 m to the side
// moves 26 mm along the heading in a 5 deg turn). These are fixed per scan;
// this class holds them, so the per-point work is two additions (and a
// square root and a product while the robot turns).
#include <cmath>
#include <limits>

#include <Eigen/Core>

#include "stridemap/core/map_update.hpp"
#include "stridemap/core/pose.hpp"

namespace stridemap {

class MaxElevationChange {
 public:
  /// `gamma_rad` is the inclination of the sensor's measuring surface about
  /// the lateral axis (scan plane, laser sheet) for this scan's pose;
  /// `trunk_yaw_rad` the heading the lateral distances are measured across.
  MaxElevationChange(const ScanMotion& motion, double gamma_rad, const SensorMount& mount,
                     const UpdateOptions& options, double trunk_yaw_rad)
      : MaxElevationChange(motion, gamma_rad, mount, options, std::cos(trunk_yaw_rad), std::sin(trunk_yaw_rad)) {}
  /// The same with cos and sin of the trunk's heading already made (a scan
  /// needs them in several places): the same terms, bit for bit.
  MaxElevationChange(const ScanMotion& motion, double gamma_rad, const SensorMount& mount,
                     const UpdateOptions& options, double cos_trunk_yaw, double sin_trunk_yaw)
      : turn_offset_m_(std::hypot(mount.forward_offset_m, mount.lateral_offset_m)),
        mount_lateral_m_(mount.lateral_offset_m),
        cos_yaw_(cos_trunk_yaw),
        sin_yaw_(sin_trunk_yaw) {
    const double tan_gamma = std::tan(gamma_rad);
    travel_term_m_ = std::abs(motion.horizontal_travel_m * tan_gamma);
    // Fig. 10's travel is (distance + d_s) times a factor of the yaw change.
    const double turn_factor = options.use_turning_term ? turning_travel_m(1.0, 0.0, motion.yaw_change_rad) : 0.0;
    turn_term_per_m_ =
        std::isfinite(turn_factor) ? std::abs(tan_gamma) * turn_factor : std::numeric_limits<double>::infinity();
    if (options.use_turning_term && std::isfinite(turn_factor)) {
      lateral_term_per_m_ = std::abs(tan_gamma * std::sin(motion.yaw_change_rad));
    }
  }

  /// Delta z_max of a point `offset_m` (map axes) from the sensor origin
  /// whose height the sensor knows to within `height_error_m`. Infinite
  /// ("any change is plausible") when a turn beyond a quarter turn makes
  /// Fig. 10's term unbounded.
  double at(double height_error_m, const Eigen::Vector3d& offset_m) const {
    double dz_max = travel_term_m_ + height_error_m;
    if (turn_term_per_m_ != 0.0) {
      // Plain sqrt: hypot's overflow care costs more than the rest of a point.
      const double turn = turn_term_per_m_ * (std::sqrt(offset_m.x() * offset_m.x() + offset_m.y() * offset_m.y()) +
                                              turn_offset_m_);
      dz_max += turn != turn ? std::numeric_limits<double>::infinity() : turn;  // inf * 0 at the sensor itself
      // A point beside the turning centre moves along the heading by
      // |y| |sin theta|, and the inclined surface meets the terrain that
      // much further on: |y| |sin theta| tan(gamma).
      const double lateral_m = -sin_yaw_ * offset_m.x() + cos_yaw_ * offset_m.y() + mount_lateral_m_;
      dz_max += lateral_term_per_m_ * (lateral_m < 0 ? -lateral_m : lateral_m);
    }
    return dz_max;
  }

  double travel_term_m() const { return travel_term_m_; }
  double turn_term_per_m() const { return turn_term_per_m_; }
  double lateral_term_per_m() const { return lateral_term_per_m_; }
  double turn_offset_m() const { return turn_offset_m_; }
  /// The lateral term's axis (across the trunk's heading) and the mount's
  /// offset along it, for code that writes `at` out per coordinate.
  double cos_yaw() const { return cos_yaw_; }
  double sin_yaw() const { return sin_yaw_; }
  double mount_lateral_m() const { return mount_lateral_m_; }

 private:
  double travel_term_m_ = 0.0;
  double turn_offset_m_;
  double mount_lateral_m_;
  double cos_yaw_, sin_yaw_;
  double turn_term_per_m_ = 0.0;
  double lateral_term_per_m_ = 0.0;
};

}  // namespace stridemap
