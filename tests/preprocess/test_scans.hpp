#pragma once
// Hand-made scans for the preprocess tests: beams at the URG-04LX step,
// ranges placed on lines of the sensor frame (a tilted scanner sees flat
// ground and box faces as lines x = const), plus small helpers.
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <functional>
#include <limits>
#include <random>
#include <string>
#include <vector>

#include "stridemap/core/error.hpp"
#include "stridemap/core/planar_scan.hpp"

namespace stridemap::test {

inline constexpr double pi = 3.14159265358979323846;
inline constexpr double urg_step_rad = 2.0 * pi / 1024.0;
inline constexpr double nan = std::numeric_limits<double>::quiet_NaN();

inline double deg(double degrees) { return degrees * pi / 180.0; }

/// `beams` beams centred on the forward direction, URG step, all ranges
/// invalid, Delta r = 10 mm (the URG-04LX spec below 1 m).
inline PlanarScan centred_scan(std::size_t beams, double step_rad = urg_step_rad) {
  PlanarScan scan;
  scan.resize(beams);
  const double first = -0.5 * static_cast<double>(beams - 1) * step_rad;
  for (std::size_t i = 0; i < beams; ++i) {
    scan.angle_rad[i] = first + static_cast<double>(i) * step_rad;
    scan.range_m[i] = nan;
    scan.range_error_m[i] = 0.010;
  }
  return scan;
}

/// Puts beams [first, last] on the line x = x_m of the sensor frame.
inline void put_on_line_x(PlanarScan& scan, std::size_t first, std::size_t last, double x_m) {
  for (std::size_t i = first; i <= last; ++i) scan.range_m[i] = x_m / std::cos(scan.angle_rad[i]);
}

/// A tilted scanner in front of a box: every beam on the ground line x =
/// ground_x_m, except those whose hit on the line x = box_x_m lies within
/// |y| <= box_half_width_m, which see the box there.
inline void put_box_scene(PlanarScan& scan, double ground_x_m, double box_x_m, double box_half_width_m) {
  for (std::size_t i = 0; i < scan.size(); ++i) {
    const double t = scan.angle_rad[i];
    const bool on_box = std::abs(box_x_m * std::tan(t)) <= box_half_width_m;
    scan.range_m[i] = (on_box ? box_x_m : ground_x_m) / std::cos(t);
  }
}

/// First and last beam of put_box_scene's box for a given box_x_m.
inline void box_beams(const PlanarScan& scan, double box_x_m, double box_half_width_m, std::size_t& first,
                      std::size_t& last) {
  first = scan.size();
  last = 0;
  for (std::size_t i = 0; i < scan.size(); ++i) {
    if (std::abs(box_x_m * std::tan(scan.angle_rad[i])) <= box_half_width_m) {
      if (first == scan.size()) first = i;
      last = i;
    }
  }
}

/// A coherent group of mixed points on beams [first, last]: x wanders
/// smoothly between x_min_m and x_max_m, slowly enough from beam to beam that
/// range clustering sees one surface (the second kind of mixed points of the
/// paper's section 5.3, too large for clustering).
inline void put_wavy_veil(PlanarScan& scan, std::size_t first, std::size_t last, double x_min_m,
                          double x_max_m, double phase_rad) {
  for (std::size_t i = first; i <= last; ++i) {
    const double wave = 0.5 * (1.0 + std::sin(0.25 * static_cast<double>(i - first) + phase_rad));
    scan.range_m[i] = (x_min_m + (x_max_m - x_min_m) * wave) / std::cos(scan.angle_rad[i]);
  }
}

/// Adds N(0, sigma_m) to every valid range (deterministic for a seed).
inline void add_noise(PlanarScan& scan, double sigma_m, std::uint64_t seed) {
  std::mt19937_64 engine(seed);
  std::normal_distribution<double> noise(0.0, sigma_m);
  for (double& r : scan.range_m) {
    if (!std::isnan(r)) r += noise(engine);
  }
}

inline std::size_t count_marked(const std::vector<std::uint8_t>& mask) {
  std::size_t count = 0;
  for (const std::uint8_t value : mask) count += value != 0 ? 1 : 0;
  return count;
}

inline std::size_t count_valid(const PlanarScan& scan) {
  std::size_t count = 0;
  for (const double r : scan.range_m) count += std::isnan(r) ? 0 : 1;
  return count;
}

/// The message of the InputError that `action` throws, or a marker if none.
inline std::string input_error_message(const std::function<void()>& action) {
  try {
    action();
  } catch (const InputError& error) {
    return error.what();
  }
  return "(no InputError thrown)";
}

}  // namespace stridemap::test
