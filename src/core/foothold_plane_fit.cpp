#include "foothold_plane_fit.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <numbers>
#include <span>

#include <Eigen/Dense>

#include "foothold_cells.hpp"

namespace stridemap::foothold {

// Cell spacing squared sets the scale of the determinant: collinear cells
// give one that vanishes relative to it.
bool invert_normal_matrix(std::size_t count, double sx, double sy, double sxx, double sxy, double syy,
                          double cell_size_m, Eigen::Matrix3d& inverse) {
  Eigen::Matrix3d a;
  a << static_cast<double>(count), sx, sy, sx, sxx, sxy, sy, sxy, syy;
  bool invertible = false;
  const double scale = cell_size_m * cell_size_m;
  a.computeInverseWithCheck(inverse, invertible, 1e-9 * scale * scale);
  return invertible;
}

void fit_footprint(const FootholdStencil& stencil, const WindowSlots& slots, const float* elevation,
                   const std::uint8_t* state, CellIndex cell, const GeometryLayers& out) {
  const double cell_size_m = stencil.cell_size_m;
  const std::size_t s = slots.of(cell);
  float* slope = out.slope_deg;
  float* roughness = out.roughness_m;
  float* step = out.step_height_m;
  slope[s] = roughness[s] = step[s] = kNaN;
  if (!known(elevation, state, s)) return;
  // Elevations relative to the centre cell's keep the sums small, so the
  // residuals (millimetres) survive next to heights of metres.
  const double z0 = elevation[s];
  double sx = 0.0, sy = 0.0, sxx = 0.0, sxy = 0.0, syy = 0.0;
  Eigen::Vector3d b = Eigen::Vector3d::Zero();
  double lo = 0.0, hi = 0.0;
  std::size_t count = 0;
  // The known cells' relative elevations and offsets, kept for the
  // residuals so that the second pass does not look them up again (the
  // same values in the same order: the same bits).
  std::array<std::array<double, 3>, kKept> kept;
  const bool keep = stencil.footprint.size() <= kKept;
  for (const CellIndex& o : stencil.footprint) {
    const CellIndex q{cell.x + o.x, cell.y + o.y};
    if (!slots.inside(q)) continue;
    const std::size_t t = slots.of(q);
    if (!known(elevation, state, t)) continue;
    const double z = elevation[t] - z0;
    if (keep) kept[count] = {z, static_cast<double>(o.x), static_cast<double>(o.y)};
    const double x = static_cast<double>(o.x) * cell_size_m, y = static_cast<double>(o.y) * cell_size_m;
    sx += x;
    sy += y;
    sxx += x * x;
    sxy += x * y;
    syy += y * y;
    b += Eigen::Vector3d(z, x * z, y * z);
    lo = std::min(lo, z);
    hi = std::max(hi, z);
    ++count;
  }
  if (count < stencil.min_known) return;
  step[s] = static_cast<float>(hi - lo);
  Eigen::Matrix3d inverse = stencil.full_inverse;
  if (count != stencil.footprint.size() && !invert_normal_matrix(count, sx, sy, sxx, sxy, syy, cell_size_m, inverse)) {
    return;
  }
  const Eigen::Vector3d plane = inverse * b;
  double residual2 = 0.0;
  if (keep) {
    for (std::size_t k = 0; k < count; ++k) {
      const double fit = plane[0] + plane[1] * kept[k][1] * cell_size_m + plane[2] * kept[k][2] * cell_size_m;
      const double r = kept[k][0] - fit;
      residual2 += r * r;
    }
  }
  for (const CellIndex& o : keep ? std::span<const CellIndex>() : std::span<const CellIndex>(stencil.footprint)) {
    const CellIndex q{cell.x + o.x, cell.y + o.y};
    if (!slots.inside(q)) continue;
    const std::size_t t = slots.of(q);
    if (!known(elevation, state, t)) continue;
    const double fit = plane[0] + plane[1] * static_cast<double>(o.x) * cell_size_m +
                       plane[2] * static_cast<double>(o.y) * cell_size_m;
    const double r = (elevation[t] - z0) - fit;
    residual2 += r * r;
  }
  slope[s] = static_cast<float>(std::atan(std::hypot(plane[1], plane[2])) * 180.0 / std::numbers::pi);
  roughness[s] = static_cast<float>(std::sqrt(residual2 / static_cast<double>(count)));
}

}  // namespace stridemap::foothold
