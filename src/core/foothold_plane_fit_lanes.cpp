// fit_footprint() for kLanes cells at once: their sums are independent,
// so each lane runs one cell's fit (one load per footprint cell where the
// lanes' cells are neighbours in a row, one per lane where not). Per lane the operations
// and their order are fit_footprint()'s; an unknown footprint cell,
// which that skips, adds +0.0 here: every sum starts at +0.0 and so is
// never -0.0, and x + 0.0 == x bit for bit for any other x. The step's
// min and max keep a lane's value on a skipped cell as std::min/std::max
// do on a tie. Built with -ffp-contract=off (src/CMakeLists.txt), as
// foothold_plane_fit.cpp, so that no CPU fuses a multiply and an add in one
// path and not the other.
#include <algorithm>
#include <bit>
#include <cmath>
#include <cstdint>
#include <cstring>

#include <Eigen/Dense>

#include "foothold_cells.hpp"
#include "foothold_plane_fit.hpp"

namespace stridemap::foothold {
namespace {

using Doubles = double __attribute__((vector_size(kLanes * sizeof(double))));
using Floats = float __attribute__((vector_size(kLanes * sizeof(float))));
using Masks = std::int64_t __attribute__((vector_size(kLanes * sizeof(std::int64_t))));

static_assert(kLanes == 4);

// Lane l's entry at `offset` from its centre.
template <bool kNeighbours>
[[gnu::always_inline]] inline Floats load_lanes(const float* const* centres, std::ptrdiff_t offset) {
  Floats v;
  if constexpr (kNeighbours) {
    std::memcpy(&v, centres[0] + offset, sizeof v);
  } else {
    v = Floats{centres[0][offset], centres[1][offset], centres[2][offset], centres[3][offset]};
  }
  return v;
}

template <bool kNeighbours>
[[gnu::always_inline]] inline void fit_lanes(const FootholdStencil& stencil, PartialInverses& inverses,
                                             const float* const* centres, std::ptrdiff_t stride, unsigned wanted,
                                             LaneFits& out) {
  const double cell_size_m = stencil.cell_size_m;
  const std::size_t m = stencil.footprint.size();
  const Doubles zero = {0.0, 0.0, 0.0, 0.0};
  const Doubles z0 = __builtin_convertvector(load_lanes<kNeighbours>(centres, 0), Doubles);
  Doubles b0 = zero, b1 = zero, b2 = zero, z2 = zero, lo = zero, hi = zero;
  Masks count = {0, 0, 0, 0}, bits = {0, 0, 0, 0}, bit = {1, 1, 1, 1};
  for (std::size_t k = 0; k < m; ++k) {
    const CellIndex& o = stencil.footprint[k];
    const Doubles e = __builtin_convertvector(load_lanes<kNeighbours>(centres, o.x * stride + o.y), Doubles);
    const Masks known = e == e;
    const Doubles z = known ? e - z0 : zero;
    b0 += z;
    b1 += stencil.foot_x_m[k] * z;
    b2 += stencil.foot_y_m[k] * z;
    z2 += z * z;
    lo = z < lo ? z : lo;
    hi = hi < z ? z : hi;
    count -= known;
    bits |= known & bit;
    bit += bit;  // bit k (k < kKept <= 64)
  }
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
        // The known cells in footprint order, as fit_footprint() adds them.
        for (auto known = static_cast<std::uint64_t>(bits[l]); known != 0; known &= known - 1) {
          const auto k = static_cast<std::size_t>(std::countr_zero(known));
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
      // Used at once: a later lane may take the slot for another set.
      inverse = &cached.inverse;
    }
    const Eigen::Vector3d b(b0[l], b1[l], b2[l]);
    const Eigen::Vector3d plane = plane_of(*inverse, b);
    out.slope_deg[l] = slope_deg(plane);
    out.roughness_m[l] = roughness_m(z2[l], plane, b, known_cells);
  }
}

}  // namespace

STRIDEMAP_FOOTHOLD_CLONES void fit_footprint_lanes(const FootholdStencil& stencil, PartialInverses& inverses,
                                                   const float* centre_entry, std::ptrdiff_t stride, unsigned wanted,
                                                   LaneFits& out) {
  const float* centres[kLanes] = {centre_entry, centre_entry + 1, centre_entry + 2, centre_entry + 3};
  fit_lanes<true>(stencil, inverses, centres, stride, wanted, out);
}

STRIDEMAP_FOOTHOLD_CLONES void fit_footprint_cells(const FootholdStencil& stencil, PartialInverses& inverses,
                                                   const LaneCentres& centres, std::ptrdiff_t stride, unsigned wanted,
                                                   LaneFits& out) {
  fit_lanes<false>(stencil, inverses, centres.entry, stride, wanted, out);
}

}  // namespace stridemap::foothold
