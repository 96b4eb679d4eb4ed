#pragma once
// The foothold layers' plane fits (core/foothold.hpp): slope, roughness and
// step height of one cell from the least-squares plane through its
// footprint. Private to the core library.
#include <cstddef>
#include <cstdint>

#include <Eigen/Core>

#include "stridemap/core/foothold_stencil.hpp"
#include "stridemap/core/grid_map.hpp"

namespace stridemap::foothold {

/// Footprints up to this size keep their cells for the residuals and are
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
/// Lanes not in `wanted` (bit l: lane l) are left NaN: the plane, the
/// atan and the hypot of a cell whose fit will not be stored are skipped.
void fit_footprint_lanes(const FootholdStencil& stencil, PartialInverses& inverses, const float* centre,
                         std::ptrdiff_t stride, unsigned wanted, LaneFits& out);

/// The inverse of the least-squares normal matrix of `count` cells with
/// these coordinate sums; false when the cells are collinear.
bool invert_normal_matrix(std::size_t count, double sx, double sy, double sxx, double sxy, double syy,
                          double cell_size_m, Eigen::Matrix3d& inverse);

}  // namespace stridemap::foothold
