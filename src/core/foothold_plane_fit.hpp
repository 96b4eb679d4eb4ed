#pragma once
// The foothold layers' plane fits (core/foothold.hpp): slope, roughness and
// step height of one cell from the least-squares plane through its
// footprint. Private to the core library.
#include <algorithm>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <numbers>

#include <Eigen/Core>

#include "stridemap/core/foothold_stencil.hpp"
#include "stridemap/core/grid_map.hpp"

namespace stridemap::foothold {

/// Footprints up to this size (one bit per cell in a 64-bit mask) are
/// fitted kLanes cells at once (fit_footprint_lanes()).
inline constexpr std::size_t kKept = 64;

/// Slots of the window addressed by global index, without a modulo per
/// cell: the storage row of local row i is (corner row + i) wrapped once.
struct WindowSlots {
  explicit WindowSlots(const ElevationMap& map)
      : n(map.cells_per_side()),
        corner(map.min_cell()),
        row0(static_cast<std::int64_t>(map.slot(map.min_cell()) / static_cast<std::size_t>(n))),
        col0(static_cast<std::int64_t>(map.slot(map.min_cell()) % static_cast<std::size_t>(n))) {}
  bool inside(CellIndex c) const { return c.x >= corner.x && c.y >= corner.y && c.x < corner.x + n && c.y < corner.y + n; }
  std::size_t of(CellIndex c) const {
    std::int64_t i = c.x - corner.x + row0, j = c.y - corner.y + col0;
    if (i >= n) i -= n;
    if (j >= n) j -= n;
    return static_cast<std::size_t>(i * n + j);
  }
  std::int64_t n;
  CellIndex corner;
  std::int64_t row0, col0;
};

/// The three geometry layers' storage.
struct GeometryLayers {
  float* slope_deg;
  float* roughness_m;
  float* step_height_m;
};

// The one-cell fit and the lanes share these, so that both give the same
// bits; each sum is written out left to right, as the reference test's.

/// The least-squares plane (relative height, x and y gradients) from the
/// normal matrix's inverse and the right side b.
inline Eigen::Vector3d plane_of(const Eigen::Matrix3d& inverse, const Eigen::Vector3d& b) {
  return {inverse(0, 0) * b[0] + inverse(0, 1) * b[1] + inverse(0, 2) * b[2],
          inverse(1, 0) * b[0] + inverse(1, 1) * b[1] + inverse(1, 2) * b[2],
          inverse(2, 0) * b[0] + inverse(2, 1) * b[1] + inverse(2, 2) * b[2]};
}

/// The plane's inclination in degrees.
inline float slope_deg(const Eigen::Vector3d& plane) {
  return static_cast<float>(std::atan(std::sqrt(plane[1] * plane[1] + plane[2] * plane[2])) * 180.0 /
                            std::numbers::pi);
}

/// RMS residual of the plane through `count` cells from their relative
/// elevations' sum of squares: the residuals' sum of squares is
/// sum z^2 - plane . b by the normal equations, so the cells are not
/// visited again. Relative elevations of millimetres to centimetres leave
/// the difference some ten significant digits; rounding can take an exact
/// plane's zero just below, hence the clamp.
inline float roughness_m(double sum_z2, const Eigen::Vector3d& plane, const Eigen::Vector3d& b, std::size_t count) {
  const double residual2 = sum_z2 - (plane[0] * b[0] + plane[1] * b[1] + plane[2] * b[2]);
  return static_cast<float>(std::sqrt(std::max(0.0, residual2) / static_cast<double>(count)));
}

/// Fits the plane over `cell`'s footprint from the map's elevation and
/// state, cells outside the window counting as unknown, and writes the
/// cell's slope, roughness and step height (NaN where the footprint holds
/// too few known cells or they are collinear).
void fit_footprint(const FootholdStencil& stencil, const WindowSlots& slots, const float* elevation,
                   const std::uint8_t* state, CellIndex cell, const GeometryLayers& out);

/// Cells fit_footprint_lanes() fits at once.
inline constexpr int kLanes = kFootholdLanes;

/// One fit per lane: slope, roughness and step height.
struct LaneFits {
  float slope_deg[kLanes], roughness_m[kLanes], step_height_m[kLanes];
};

/// fit_footprint_inside() of kLanes consecutive cells of a row at once, one
/// per vector lane: the same operations in the same order per cell, so the
/// same bits. Known-ness and elevation from `centre` (the first cell's
/// entry of PaddedElevations::values (core/foothold_stencil.hpp), NaN: unknown), rows `stride` apart.
/// Lanes not in `wanted` (bit l: lane l) are left NaN: the plane and the
/// atan of a cell whose fit will not be stored are skipped.
void fit_footprint_lanes(const FootholdStencil& stencil, PartialInverses& inverses, const float* centre,
                         std::ptrdiff_t stride, unsigned wanted, LaneFits& out);

/// Where each lane's cell is in PaddedElevations::values: any kLanes cells,
/// neighbours or not.
struct LaneCentres {
  const float* entry[kLanes];
};

/// fit_footprint_lanes() of kLanes cells anywhere in the window (a lane not
/// in `wanted` may repeat another's entry): a row's marked cells with gaps
/// between them fill every lane. The same bits per cell.
void fit_footprint_cells(const FootholdStencil& stencil, PartialInverses& inverses, const LaneCentres& centres,
                         std::ptrdiff_t stride, unsigned wanted, LaneFits& out);

/// The inverse of the least-squares normal matrix of `count` cells with
/// these coordinate sums; false when the cells are collinear.
bool invert_normal_matrix(std::size_t count, double sx, double sy, double sxx, double sxy, double syy,
                          double cell_size_m, Eigen::Matrix3d& inverse);

}  // namespace stridemap::foothold
