#include "stridemap/sim/primitives.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>

namespace stridemap {
namespace {

// Coordinates below this are rounding, not geometry (see footprint_overlaps).
constexpr double overlap_tolerance_m = 1e-9;

RayHit make_hit(double t, const Eigen::Vector3d& origin, const Eigen::Vector3d& dir, const Eigen::Vector3d& normal,
                double reflectance) {
  RayHit hit;
  hit.range_m = t;
  hit.point_m = origin + t * dir;
  hit.normal = normal;
  hit.reflectance = reflectance;
  hit.object_index = -1;
  return hit;
}

// Box-frame coordinates of a map-frame vector (rotation by -yaw about Z).
Eigen::Vector2d to_box_frame(const BoxObject& box, double x, double y) {
  const double c = std::cos(box.yaw_rad), s = std::sin(box.yaw_rad);
  return {c * x + s * y, -s * x + c * y};
}

bool has_area(const Rect2& rect) { return rect.max_x_m > rect.min_x_m && rect.max_y_m > rect.min_y_m; }

}  // namespace

std::optional<RayHit> intersect_box(const BoxObject& box, const Eigen::Vector3d& origin, const Eigen::Vector3d& dir,
                                    double max_range_m) {
  const Eigen::Vector2d o_xy = to_box_frame(box, origin.x() - box.center_x_m, origin.y() - box.center_y_m);
  const Eigen::Vector2d d_xy = to_box_frame(box, dir.x(), dir.y());
  const double half_height = 0.5 * box.height_m;
  const std::array<double, 3> o{o_xy.x(), o_xy.y(), origin.z() - (box.base_elevation_m + half_height)};
  const std::array<double, 3> d{d_xy.x(), d_xy.y(), dir.z()};
  const std::array<double, 3> half{0.5 * box.length_m, 0.5 * box.width_m, half_height};

  double t_near = -std::numeric_limits<double>::infinity();
  double t_far = std::numeric_limits<double>::infinity();
  int near_axis = 0;
  for (int axis = 0; axis < 3; ++axis) {
    if (d[axis] == 0.0) {
      if (std::abs(o[axis]) > half[axis]) return std::nullopt;
      continue;
    }
    double t1 = (-half[axis] - o[axis]) / d[axis];
    double t2 = (half[axis] - o[axis]) / d[axis];
    if (t1 > t2) std::swap(t1, t2);
    if (t1 > t_near) t_near = t1, near_axis = axis;
    t_far = std::min(t_far, t2);
  }
  if (t_near > t_far || t_far < 0.0) return std::nullopt;
  if (t_near < 0.0) return make_hit(0.0, origin, dir, -dir, box.reflectance);  // origin inside
  if (t_near > max_range_m) return std::nullopt;

  Eigen::Vector3d normal = Eigen::Vector3d::Zero();
  const double outward = d[near_axis] > 0.0 ? -1.0 : 1.0;
  if (near_axis == 2) {
    normal.z() = outward;
  } else {
    // Face normal in the box frame, turned back by +yaw.
    const double c = std::cos(box.yaw_rad), s = std::sin(box.yaw_rad);
    const double lx = near_axis == 0 ? outward : 0.0, ly = near_axis == 1 ? outward : 0.0;
    normal.x() = c * lx - s * ly;
    normal.y() = s * lx + c * ly;
  }
  return make_hit(t_near, origin, dir, normal, box.reflectance);
}

std::optional<RayHit> intersect_cylinder(const CylinderObject& cylinder, const Eigen::Vector3d& origin,
                                         const Eigen::Vector3d& dir, double max_range_m) {
  const double ox = origin.x() - cylinder.center_x_m, oy = origin.y() - cylinder.center_y_m;
  const double r2 = cylinder.radius_m * cylinder.radius_m;
  const double bottom = cylinder.base_elevation_m, top = cylinder.top_m();
  if (ox * ox + oy * oy <= r2 && origin.z() >= bottom && origin.z() <= top) {
    return make_hit(0.0, origin, dir, -dir, cylinder.reflectance);
  }

  double best_t = std::numeric_limits<double>::infinity();
  Eigen::Vector3d best_normal = Eigen::Vector3d::UnitZ();
  const double a = dir.x() * dir.x() + dir.y() * dir.y();
  if (a > 0.0) {
    const double half_b = ox * dir.x() + oy * dir.y();
    const double c = ox * ox + oy * oy - r2;
    const double discriminant = half_b * half_b - a * c;
    if (discriminant >= 0.0) {
      // The smaller root is where the ray enters the infinite cylinder; a
      // negative one means the origin is already within the radius, where
      // only a cap can be the entry.
      const double t = (-half_b - std::sqrt(discriminant)) / a;
      const double z = origin.z() + t * dir.z();
      if (t >= 0.0 && z >= bottom && z <= top) {
        best_t = t;
        best_normal = Eigen::Vector3d(ox + t * dir.x(), oy + t * dir.y(), 0.0) / cylinder.radius_m;
        best_normal.normalize();
      }
    }
  }
  if (dir.z() != 0.0) {
    const bool from_above = dir.z() < 0.0;
    const double cap_z = from_above ? top : bottom;
    const double t = (cap_z - origin.z()) / dir.z();
    const double x = ox + t * dir.x(), y = oy + t * dir.y();
    if (t >= 0.0 && t < best_t && x * x + y * y <= r2) {
      best_t = t;
      best_normal = Eigen::Vector3d(0.0, 0.0, from_above ? 1.0 : -1.0);
    }
  }
  if (best_t > max_range_m) return std::nullopt;
  return make_hit(best_t, origin, dir, best_normal, cylinder.reflectance);
}

bool footprint_contains(const BoxObject& box, double x_m, double y_m) {
  const Eigen::Vector2d local = to_box_frame(box, x_m - box.center_x_m, y_m - box.center_y_m);
  return std::abs(local.x()) <= 0.5 * box.length_m + overlap_tolerance_m &&
         std::abs(local.y()) <= 0.5 * box.width_m + overlap_tolerance_m;
}

bool footprint_contains(const CylinderObject& cylinder, double x_m, double y_m) {
  const double dx = x_m - cylinder.center_x_m, dy = y_m - cylinder.center_y_m;
  return std::hypot(dx, dy) <= cylinder.radius_m + overlap_tolerance_m;
}

bool footprint_overlaps(const BoxObject& box, const Rect2& rect) {
  const double required = has_area(rect) ? overlap_tolerance_m : -overlap_tolerance_m;
  const double c = std::cos(box.yaw_rad), s = std::sin(box.yaw_rad);
  const Eigen::Vector2d center(box.center_x_m, box.center_y_m);
  const Eigen::Vector2d along(c, s), across(-s, c);
  const double hl = 0.5 * box.length_m, hw = 0.5 * box.width_m;
  const std::array<Eigen::Vector2d, 4> box_corners{
      center + hl * along + hw * across, center + hl * along - hw * across,
      center - hl * along + hw * across, center - hl * along - hw * across};
  const std::array<Eigen::Vector2d, 4> rect_corners{
      Eigen::Vector2d(rect.min_x_m, rect.min_y_m), Eigen::Vector2d(rect.max_x_m, rect.min_y_m),
      Eigen::Vector2d(rect.min_x_m, rect.max_y_m), Eigen::Vector2d(rect.max_x_m, rect.max_y_m)};
  // Two convex polygons overlap unless their projections onto one of their
  // edge normals are disjoint; both are rectangles, so four axes suffice.
  const std::array<Eigen::Vector2d, 4> axes{Eigen::Vector2d::UnitX(), Eigen::Vector2d::UnitY(), along, across};
  for (const Eigen::Vector2d& axis : axes) {
    double box_lo = std::numeric_limits<double>::infinity(), box_hi = -box_lo;
    double rect_lo = box_lo, rect_hi = -box_lo;
    for (const auto& p : box_corners) box_lo = std::min(box_lo, axis.dot(p)), box_hi = std::max(box_hi, axis.dot(p));
    for (const auto& p : rect_corners) rect_lo = std::min(rect_lo, axis.dot(p)), rect_hi = std::max(rect_hi, axis.dot(p));
    if (std::min(box_hi, rect_hi) - std::max(box_lo, rect_lo) <= required) return false;
  }
  return true;
}

bool footprint_overlaps(const CylinderObject& cylinder, const Rect2& rect) {
  const double nearest_x = std::clamp(cylinder.center_x_m, rect.min_x_m, rect.max_x_m);
  const double nearest_y = std::clamp(cylinder.center_y_m, rect.min_y_m, rect.max_y_m);
  const double distance = std::hypot(nearest_x - cylinder.center_x_m, nearest_y - cylinder.center_y_m);
  if (has_area(rect)) return distance < cylinder.radius_m - overlap_tolerance_m;
  return distance <= cylinder.radius_m + overlap_tolerance_m;
}

}  // namespace stridemap
