#pragma once
// Pieces the two sensors' cart-rail runs share (cart_rail.cpp,
// cart_rail_structured_light.cpp); not part of the public API.
#include <functional>
#include <vector>

#include <Eigen/Core>

#include "stridemap/experiments/cart_rail.hpp"

namespace stridemap::detail {

/// A fixed map window (cells of options.cell_size_m, options.cells_per_side
/// or sized to hold [lo, hi] with a margin) centred on the swept area.
TerrainMapper make_rail_mapper(const Eigen::Vector2d& lo, const Eigen::Vector2d& hi, const CartRailOptions& options,
                               const SensorMount& mount);

/// Map filter, snapshot with truth, swept area, score, object extents.
void finish_rail_map(const Scene& scene, const CartRailOptions& options, TerrainMapper& mapper,
                     const std::function<CellMask(const ElevationMap&)>& swept_area, CartRailResult& result);

/// The structured-light run over the poses (cart_rail_structured_light.cpp).
void run_structured_light_rail(const Scene& scene, const CartRailOptions& options,
                               const std::vector<TrunkPose>& poses, CartRailResult& result);

}  // namespace stridemap::detail
