#include "foothold_plane_fit.hpp"

#include <algorithm>
#include <cmath>

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
  double sum_z2 = 0.0, lo = 0.0, hi = 0.0;
  std::size_t count = 0;
  for (const CellIndex& o : stencil.footprint) {
    const CellIndex q{cell.x + o.x, cell.y + o.y};
    if (!slots.inside(q)) continue;
    const std::size_t t = slots.of(q);
    if (!known(elevation, state, t)) continue;
    const double z = elevation[t] - z0;
    const double x = static_cast<double>(o.x) * cell_size_m, y = static_cast<double>(o.y) * cell_size_m;
    sx += x;
    sy += y;
    sxx += x * x;
    sxy += x * y;
    syy += y * y;
    b += Eigen::Vector3d(z, x * z, y * z);
    sum_z2 += z * z;
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
  const Eigen::Vector3d plane = plane_of(inverse, b);
  slope[s] = slope_deg(plane);
  roughness[s] = roughness_m(sum_z2, plane, b, count);
}

}  // namespace stridemap::foothold
