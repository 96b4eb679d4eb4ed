#pragma once
// Solid primitives standing on the terrain: boxes turned about the vertical
// axis and vertical cylinders. Exact ray intersection, point tests and the
// overlap tests the ground truth of a map cell needs.
#include <optional>
#include <cmath>
#include <limits>
#include <string>

#include <Eigen/Core>

#include "stridemap/sim/height_field.hpp"

namespace stridemap {

struct BoxObject {
  std::string name;
  double center_x_m = 0, center_y_m = 0;  ///< centre of the footprint [m]
  double base_elevation_m = 0;            ///< elevation of the bottom face [m]
  double length_m = 0;  ///< extent along X before yaw [m]
  double width_m = 0;   ///< extent along Y before yaw [m]
  double height_m = 0;  ///< bottom to top [m]
  double yaw_rad = 0;   ///< rotation about +Z, counter-clockwise [rad]
  double reflectance = 0.5;  ///< diffuse reflectance at 785 nm, (0, 1]
  /// When the box stands in the scene: from present_from_s (inclusive) to
  /// present_until_s (exclusive), on the simulation's clock [s]. Always by
  /// default; Scene::at_time() keeps the boxes present at a time (objects
  /// taken away, or a foot passing through as a series of short stays).
  double present_from_s = -std::numeric_limits<double>::infinity();
  double present_until_s = std::numeric_limits<double>::infinity();

  double top_m() const { return base_elevation_m + height_m; }
  bool present_at(double time_s) const { return time_s >= present_from_s && time_s < present_until_s; }
  bool always_present() const { return std::isinf(present_from_s) && present_from_s < 0 && std::isinf(present_until_s); }
};

struct CylinderObject {
  std::string name;
  double center_x_m = 0, center_y_m = 0;  ///< axis position [m]
  double base_elevation_m = 0;            ///< elevation of the bottom cap [m]
  double radius_m = 0;
  double height_m = 0;
  double reflectance = 0.5;  ///< diffuse reflectance at 785 nm, (0, 1]

  double top_m() const { return base_elevation_m + height_m; }
};

/// Axis-aligned rectangle in the map's X-Y plane.
struct Rect2 {
  double min_x_m = 0, min_y_m = 0, max_x_m = 0, max_y_m = 0;
};

/// Entry point of the ray into the box (slab test in the box frame) within
/// max_range_m; object_index is left at -1 for the caller to set. An origin
/// inside the box hits at range 0 with the normal facing the ray.
std::optional<RayHit> intersect_box(const BoxObject& box, const Eigen::Vector3d& origin,
                                    const Eigen::Vector3d& unit_dir, double max_range_m);
/// Side, top cap or bottom cap, whichever the ray meets first.
std::optional<RayHit> intersect_cylinder(const CylinderObject& cylinder, const Eigen::Vector3d& origin,
                                         const Eigen::Vector3d& unit_dir, double max_range_m);

/// Whether (x, y) lies in the footprint (closed).
bool footprint_contains(const BoxObject& box, double x_m, double y_m);
bool footprint_contains(const CylinderObject& cylinder, double x_m, double y_m);

/// Whether the footprint and the rectangle share an area (separating axis
/// test for the box, nearest point for the circle). Touching along an edge
/// or at a point does not count, so that a box whose face lies on a cell
/// boundary does not leak into the neighbouring cell; a tolerance of 1 nm
/// absorbs rounding of coordinates such as 0.8 - 0.1. A rectangle of zero
/// width or height counts as overlapped when it touches the footprint.
bool footprint_overlaps(const BoxObject& box, const Rect2& rect);
bool footprint_overlaps(const CylinderObject& cylinder, const Rect2& rect);

}  // namespace stridemap
