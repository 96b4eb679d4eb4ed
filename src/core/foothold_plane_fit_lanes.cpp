// fit_footprint_inside() for kLanes neighbouring cells at once: most of a
// refresh's plane fits are of cells side by side in a row, and their sums
// are independent, so each lane runs one cell's fit. Per lane the operations
// and their order are fit_footprint_inside()'s; an unknown footprint cell,
// which that skips, adds +0.0 here: every sum starts at +0.0 and so is
// never -0.0, and x + 0.0 == x bit for bit for any other x. The step's
// min and max keep a lane's value on a skipped cell as std::min/std::max
// do on a tie. Built with -ffp-contract=off (src/CMakeLists.txt), as
// foothold_plane_fit.cpp, so that no CPU fuses a multiply and an add in one
// path and not the other.
#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <numbers>

#include <Eigen/Dense>

#include "foothold_cells.hpp"
#include "foothold_plane_fit.hpp"

namespace stridemap::foothold {
namespace {

using Doubles = double __attribute__((vector_size(kLanes * sizeof(double))));
using Floats = float __attribute__((vector_size(kLanes * sizeof(float))));
using Masks = std::int64_t __attribute__((vector_size(kLanes * sizeof(std::int64_t))));

}  // namespace

STRIDEMAP_FOOTHOLD_CLONES void fit_footprint_lanes(const FootholdStencil& stencil, PartialInverses& inverses,
                                                   const float* centre_entry, std::ptrdiff_t stride, unsigned wanted,
                                                   LaneFits& out) {
  const double cell_size_m = stencil.cell_size_m;
  const std::size_t m = stencil.footprint.size();
  const Doubles zero = {0.0, 0.0, 0.0, 0.0};
  Floats centre;
  std::memcpy(&centre, centre_entry, sizeof centre);
  const Doubles z0 = __builtin_convertvector(centre, Doubles);
  Doubles b0 = zero, b1 = zero, b2 = zero, lo = zero, hi = zero;
  Masks count = {0, 0, 0, 0}, bits = {0, 0, 0, 0}, bit = {1, 1, 1, 1};
  // Per footprint cell: the lanes' relative elevations (0 where unknown)
  // and which lanes know it, for the residuals and a partial footprint.
  std::array<Doubles, kKept> z_of;
  std::array<Masks, kKept> known_of;
  for (std::size_t k = 0; k < m; ++k) {
    const CellIndex& o = stencil.footprint[k];
    Floats loaded;
    std::memcpy(&loaded, centre_entry + o.x * stride + o.y, sizeof loaded);
    const Doubles e = __builtin_convertvector(loaded, Doubles);
    const Masks known = e == e;
    const Doubles z = known ? e - z0 : zero;
    b0 += z;
    b1 += stencil.foot_x_m[k] * z;
    b2 += stencil.foot_y_m[k] * z;
    lo = z < lo ? z : lo;
    hi = hi < z ? z : hi;
    count -= known;
    bits |= known & bit;
    bit += bit;  // bit k (k < kKept <= 64)
    z_of[k] = z;
    known_of[k] = known;
  }
  Doubles p0 = zero, p1 = zero, p2 = zero;
  bool fitted[kLanes] = {false, false, false, false};
  for (int l = 0; l < kLanes; ++l) {
    out.slope_deg[l] = out.roughness_m[l] = out.step_height_m[l] = kNaN;
    const auto known_cells = static_cast<std::size_t>(count[l]);
    if (!(wanted >> l & 1u) || std::isnan(z0[l]) || known_cells < stencil.min_known) continue;
    out.step_height_m[l] = static_cast<float>(hi[l] - lo[l]);
    const Eigen::Matrix3d* inverse = &stencil.full_inverse;
    if (known_cells != m) {
      PartialInverses::Entry& cached = inverses.slot(static_cast<std::uint64_t>(bits[l]));
      if (cached.known != static_cast<std::uint64_t>(bits[l])) {
        double sx = 0.0, sy = 0.0, sxx = 0.0, sxy = 0.0, syy = 0.0;
        for (std::size_t k = 0; k < m; ++k) {
          if (!known_of[k][l]) continue;
          const double x = stencil.foot_x_m[k], y = stencil.foot_y_m[k];
          sx += x;
          sy += y;
          sxx += x * x;
          sxy += x * y;
          syy += y * y;
        }
        cached.invertible = invert_normal_matrix(known_cells, sx, sy, sxx, sxy, syy, cell_size_m, cached.inverse);
        cached.known = static_cast<std::uint64_t>(bits[l]);
      }
      if (!cached.invertible) continue;
      inverse = &cached.inverse;
    }
    const Eigen::Vector3d b(b0[l], b1[l], b2[l]);
    const Eigen::Vector3d plane = *inverse * b;
    p0[l] = plane[0];
    p1[l] = plane[1];
    p2[l] = plane[2];
    fitted[l] = true;
  }
  Doubles residual2 = zero;
  for (std::size_t k = 0; k < m; ++k) {
    // (plane * offset in cells) * cell size, as fit_footprint(): the same bits.
    const Doubles fit = p0 + p1 * stencil.foot_dx[k] * cell_size_m + p2 * stencil.foot_dy[k] * cell_size_m;
    const Doubles r = z_of[k] - fit;
    residual2 += known_of[k] ? r * r : zero;
  }
  for (int l = 0; l < kLanes; ++l) {
    if (!fitted[l]) continue;
    out.slope_deg[l] = static_cast<float>(std::atan(std::hypot(p1[l], p2[l])) * 180.0 / std::numbers::pi);
    out.roughness_m[l] = static_cast<float>(std::sqrt(residual2[l] / static_cast<double>(count[l])));
  }
}

}  // namespace stridemap::foothold
