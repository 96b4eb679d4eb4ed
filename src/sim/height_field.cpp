#include "stridemap/sim/height_field.hpp"

#include <algorithm>
#include <cmath>
#include <cstddef>

namespace stridemap {
namespace {

struct CellPosition {
  int i = 0, j = 0;     ///< cell (lower-left sample) index
  double u = 0, v = 0;  ///< position inside the cell, 0..1 (slightly beyond after rounding)
};

CellPosition locate(const HeightField& field, double x_m, double y_m) {
  const double gx = (x_m - field.min_x_m) / field.resolution_m;
  const double gy = (y_m - field.min_y_m) / field.resolution_m;
  CellPosition cell;
  cell.i = std::clamp(static_cast<int>(std::floor(gx)), 0, field.nx - 2);
  cell.j = std::clamp(static_cast<int>(std::floor(gy)), 0, field.ny - 2);
  cell.u = gx - cell.i;
  cell.v = gy - cell.j;
  return cell;
}

// Heights of a cell's corners and the bilinear patch in the form
// h(u, v) = h00 + a u + b v + c u v.
struct Patch {
  double h00, a, b, c, top;
};

Patch patch_of(const HeightField& field, int i, int j) {
  const std::size_t row = static_cast<std::size_t>(j) * static_cast<std::size_t>(field.nx);
  const std::size_t next_row = row + static_cast<std::size_t>(field.nx);
  const double h00 = field.samples[row + i];
  const double h10 = field.samples[row + i + 1];
  const double h01 = field.samples[next_row + i];
  const double h11 = field.samples[next_row + i + 1];
  return {h00, h10 - h00, h01 - h00, h00 - h10 - h01 + h11, std::max({h00, h10, h01, h11})};
}

double patch_height(const Patch& p, double u, double v) { return p.h00 + p.a * u + p.b * v + p.c * u * v; }

Eigen::Vector3d patch_normal(const Patch& p, double u, double v, double resolution_m) {
  const double dh_dx = (p.a + p.c * v) / resolution_m;
  const double dh_dy = (p.b + p.c * u) / resolution_m;
  return Eigen::Vector3d(-dh_dx, -dh_dy, 1.0).normalized();
}

// Whether the ray, running through one cell for a length of `length` from
// the point where (ray height - surface height) = f0 > 0, meets the surface;
// returns the distance along the ray. Along the ray the bilinear surface is
// a quadratic, so f(s) = f0 + f1 s + f2 s^2 exactly. Whether a crossing
// exists is decided from f itself (end value, or the vertex of a convex f),
// which brackets the first root; the closed form then gives it, with
// bisection as the fallback should rounding put it outside the bracket.
std::optional<double> first_crossing(double f0, double f1, double f2, double length) {
  const auto f = [&](double s) { return f0 + s * (f1 + s * f2); };
  if (f0 <= 0.0) return 0.0;
  double lo = 0.0, hi = 0.0;
  if (f(length) <= 0.0) {
    hi = length;
  } else if (f2 > 0.0) {
    const double vertex = -f1 / (2.0 * f2);
    if (!(vertex > 0.0 && vertex < length && f(vertex) <= 0.0)) return std::nullopt;
    hi = vertex;
  } else {
    return std::nullopt;
  }
  // Exactly one root lies in (lo, hi]: f is positive at lo, not at hi, and a
  // quadratic that is convex there is monotone up to its vertex.
  double root = -1.0;
  if (std::abs(f2) * hi * hi <= 1e-12 * (std::abs(f1) * hi + f0)) {
    if (f1 < 0.0) root = -f0 / f1;
  } else {
    const double discriminant = std::max(0.0, f1 * f1 - 4.0 * f2 * f0);
    const double q = -0.5 * (f1 + std::copysign(std::sqrt(discriminant), f1));
    const double r1 = q / f2;
    const double r2 = q != 0.0 ? f0 / q : r1;
    const double tolerance = 1e-9 * (1.0 + hi);
    for (double r : {std::min(r1, r2), std::max(r1, r2)}) {
      if (r >= lo - tolerance && r <= hi + tolerance) {
        root = std::clamp(r, lo, hi);
        break;
      }
    }
  }
  if (root >= lo && root <= hi) return root;
  for (int iteration = 0; iteration < 200 && hi - lo > 1e-13 * (1.0 + hi); ++iteration) {
    const double mid = 0.5 * (lo + hi);
    (f(mid) > 0.0 ? lo : hi) = mid;
  }
  return hi;
}

RayHit terrain_hit(const HeightField& field, const Eigen::Vector3d& origin, const Eigen::Vector3d& dir,
                   double t, const Eigen::Vector3d& normal) {
  RayHit hit;
  hit.range_m = t;
  hit.point_m = origin + t * dir;
  hit.normal = normal;
  hit.reflectance = field.reflectance;
  hit.object_index = -1;
  return hit;
}

// Wall between the sampled extent and the flat outside, crossed along `axis`
// (0 x, 1 y): it faces against the ray's horizontal motion on that axis.
Eigen::Vector3d wall_normal(int axis, const Eigen::Vector3d& dir) {
  Eigen::Vector3d normal = Eigen::Vector3d::Zero();
  normal[axis] = dir[axis] > 0.0 ? -1.0 : 1.0;
  return normal;
}

}  // namespace

double HeightField::height_at(double x_m, double y_m) const {
  if (!std::isfinite(x_m) || !std::isfinite(y_m)) return std::numeric_limits<double>::quiet_NaN();
  if (is_flat() || !in_extent(x_m, y_m)) return base_elevation_m;
  const CellPosition cell = locate(*this, x_m, y_m);
  return patch_height(patch_of(*this, cell.i, cell.j), cell.u, cell.v);
}

Eigen::Vector3d HeightField::normal_at(double x_m, double y_m) const {
  if (is_flat() || !in_extent(x_m, y_m)) return Eigen::Vector3d::UnitZ();
  const CellPosition cell = locate(*this, x_m, y_m);
  return patch_normal(patch_of(*this, cell.i, cell.j), cell.u, cell.v, resolution_m);
}

double HeightField::max_sample_height_m() const {
  if (is_flat()) return base_elevation_m;
  return *std::max_element(samples.begin(), samples.end());
}

double HeightField::max_height_in_rect(double x0, double y0, double x1, double y1) const {
  if (!std::isfinite(x0) || !std::isfinite(y0) || !std::isfinite(x1) || !std::isfinite(y1)) {
    return std::numeric_limits<double>::quiet_NaN();
  }
  if (x0 > x1) std::swap(x0, x1);
  if (y0 > y1) std::swap(y0, y1);
  if (is_flat()) return base_elevation_m;
  const bool leaves_extent = x0 < min_x_m || x1 > max_x_m || y0 < min_y_m || y1 > max_y_m;
  const double cx0 = std::max(x0, min_x_m), cx1 = std::min(x1, max_x_m);
  const double cy0 = std::max(y0, min_y_m), cy1 = std::min(y1, max_y_m);
  if (cx0 > cx1 || cy0 > cy1) return base_elevation_m;

  // Candidate coordinates on each axis: the clipped rectangle's edges and
  // every grid line strictly between them.
  const auto candidates = [this](double lo, double hi, double origin, int count, auto&& visit) {
    visit(lo);
    const int first = std::max(0, static_cast<int>(std::floor((lo - origin) / resolution_m)) + 1);
    const int last = std::min(count - 1, static_cast<int>(std::ceil((hi - origin) / resolution_m)) - 1);
    for (int k = first; k <= last; ++k) {
      const double line = origin + k * resolution_m;
      if (line > lo && line < hi) visit(line);
    }
    visit(hi);
  };
  double best = leaves_extent ? base_elevation_m : -std::numeric_limits<double>::infinity();
  candidates(cx0, cx1, min_x_m, nx, [&](double x) {
    candidates(cy0, cy1, min_y_m, ny, [&](double y) { best = std::max(best, height_at(x, y)); });
  });
  return best;
}

std::optional<RayHit> HeightField::cast_ray(const Eigen::Vector3d& origin, const Eigen::Vector3d& dir,
                                            double max_range_m, double known_top_m) const {
  if (!origin.allFinite() || !dir.allFinite() || !(max_range_m >= 0.0)) return std::nullopt;
  const double base = base_elevation_m;
  const auto height_along = [&](double t) { return origin.z() + t * dir.z(); };
  const auto plane_crossing = [&](double t_from, double t_to) -> std::optional<double> {
    if (dir.z() >= 0.0) return std::nullopt;
    const double t = (base - origin.z()) / dir.z();
    if (t >= t_from && t <= t_to) return t;
    return std::nullopt;
  };

  if (is_flat()) {
    if (origin.z() <= base) return terrain_hit(*this, origin, dir, 0.0, Eigen::Vector3d::UnitZ());
    if (auto t = plane_crossing(0.0, max_range_m)) return terrain_hit(*this, origin, dir, *t, Eigen::Vector3d::UnitZ());
    return std::nullopt;
  }

  // Clip the ray to the extent: [t_in, t_out] inside, flat terrain outside.
  double t_in = 0.0, t_out = max_range_m;
  int entry_axis = -1, exit_axis = -1;
  const double lows[2] = {min_x_m, min_y_m}, highs[2] = {max_x_m, max_y_m};
  for (int axis = 0; axis < 2; ++axis) {
    if (dir[axis] == 0.0) {
      if (origin[axis] < lows[axis] || origin[axis] > highs[axis]) t_in = std::numeric_limits<double>::infinity();
      continue;
    }
    double t_low = (lows[axis] - origin[axis]) / dir[axis];
    double t_high = (highs[axis] - origin[axis]) / dir[axis];
    if (t_low > t_high) std::swap(t_low, t_high);
    if (t_low > t_in) t_in = t_low, entry_axis = axis;
    if (t_high < t_out) t_out = t_high, exit_axis = axis;
  }
  const bool crosses_extent = t_in <= t_out;

  if (!crosses_extent || entry_axis >= 0) {  // the origin lies outside the extent
    if (origin.z() <= base) return terrain_hit(*this, origin, dir, 0.0, Eigen::Vector3d::UnitZ());
    const double outside_end = crosses_extent ? t_in : max_range_m;
    if (auto t = plane_crossing(0.0, outside_end)) return terrain_hit(*this, origin, dir, *t, Eigen::Vector3d::UnitZ());
    if (!crosses_extent) return std::nullopt;
    const Eigen::Vector3d entry = origin + t_in * dir;
    if (entry.z() < height_at(std::clamp(entry.x(), min_x_m, max_x_m), std::clamp(entry.y(), min_y_m, max_y_m))) {
      return terrain_hit(*this, origin, dir, t_in, wall_normal(entry_axis, dir));
    }
  }

  // Only the part of the ray below the highest sample can meet the samples.
  double t_start = t_in, t_end = t_out;
  if (std::isfinite(known_top_m)) {
    if (height_along(t_start) > known_top_m) {
      t_start = dir.z() < 0.0 ? (known_top_m - origin.z()) / dir.z() : std::numeric_limits<double>::infinity();
    }
    if (dir.z() > 0.0) t_end = std::min(t_end, (known_top_m - origin.z()) / dir.z());
  }

  if (t_start <= t_end) {
    const Eigen::Vector3d start = origin + t_start * dir;
    CellPosition cell = locate(*this, start.x(), start.y());
    const int step_i = dir.x() > 0.0 ? 1 : -1, step_j = dir.y() > 0.0 ? 1 : -1;
    const double inf = std::numeric_limits<double>::infinity();
    const double dt_x = dir.x() != 0.0 ? resolution_m / std::abs(dir.x()) : inf;
    const double dt_y = dir.y() != 0.0 ? resolution_m / std::abs(dir.y()) : inf;
    double t_next_x = dir.x() != 0.0
        ? (min_x_m + (cell.i + (step_i > 0 ? 1 : 0)) * resolution_m - origin.x()) / dir.x() : inf;
    double t_next_y = dir.y() != 0.0
        ? (min_y_m + (cell.j + (step_j > 0 ? 1 : 0)) * resolution_m - origin.y()) / dir.y() : inf;
    const double du = dir.x() / resolution_m, dv = dir.y() / resolution_m;
    double t = t_start;
    for (;;) {
      const double t_exit = std::min({t_next_x, t_next_y, t_end});
      const double length = std::max(0.0, t_exit - t);
      const Patch p = patch_of(*this, cell.i, cell.j);
      const double z0 = height_along(t);
      if (std::min(z0, z0 + length * dir.z()) <= p.top) {
        const double u0 = (origin.x() + t * dir.x() - min_x_m) / resolution_m - cell.i;
        const double v0 = (origin.y() + t * dir.y() - min_y_m) / resolution_m - cell.j;
        const double f0 = z0 - patch_height(p, u0, v0);
        const double f1 = dir.z() - (p.a * du + p.b * dv + p.c * (u0 * dv + v0 * du));
        const double f2 = -p.c * du * dv;
        if (auto s = first_crossing(f0, f1, f2, length)) {
          const Eigen::Vector3d normal = patch_normal(p, u0 + du * *s, v0 + dv * *s, resolution_m);
          return terrain_hit(*this, origin, dir, t + *s, normal);
        }
      }
      if (t_exit >= t_end) break;
      if (t_next_x <= t_next_y) {
        cell.i += step_i;
        t_next_x += dt_x;
      } else {
        cell.j += step_j;
        t_next_y += dt_y;
      }
      if (cell.i < 0 || cell.i > nx - 2 || cell.j < 0 || cell.j > ny - 2) break;
      t = t_exit;
    }
  }

  if (exit_axis < 0 || !crosses_extent) return std::nullopt;  // the range ends inside the extent
  if (height_along(t_out) < base) return terrain_hit(*this, origin, dir, t_out, wall_normal(exit_axis, dir));
  if (auto t = plane_crossing(t_out, max_range_m)) return terrain_hit(*this, origin, dir, *t, Eigen::Vector3d::UnitZ());
  return std::nullopt;
}

}  // namespace stridemap
