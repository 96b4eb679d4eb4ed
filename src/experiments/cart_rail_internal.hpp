#pragma once
// Pieces the two sensors' cart-rail runs share (cart_rail.cpp,
// cart_rail_structured_light.cpp); not part of the public API.
#include <functional>
#include <vector>

#include <Eigen/Core>

#include "stridemap/experiments/cart_rail.hpp"
#include "stridemap/experiments/top_visibility.hpp"
#include "stridemap/pipeline/mapping_pipeline.hpp"
#include "stridemap/pipeline/top_point_observer.hpp"

namespace stridemap::detail {

/// The pipeline of a rail run: a fixed map window (cells of
/// options.cell_size_m, options.cells_per_side or sized to hold [lo, hi]
/// with a margin), the options' update rule and map filter, and `mount`.
/// The map keeps the top-point layers (core/top_point.hpp) for the objects'
/// sub-cell edges: a TopPointObserver must write them. The sensor fields
/// are left to the caller.
PipelineOptions rail_pipeline_options(const Eigen::Vector2d& lo, const Eigen::Vector2d& hi,
                                      const CartRailOptions& options, const SensorMount& mount);

/// Centres the pipeline's map on the swept area [lo, hi].
void centre_rail_map(const Eigen::Vector2d& lo, const Eigen::Vector2d& hi, MappingPipeline& pipeline);

/// How much of each top the ideal sensor sees from the rail: a sample is
/// seen within 0.75 of a rail step of a hit (the step is the widest gap
/// between the hits of a fully seen top; see TopVisibility).
TopVisibility rail_top_visibility(const Scene& scene, const CartRailPath& rail);

/// Map filter, snapshot with truth, swept area, score, object extents and
/// their seen shares.
void finish_rail_map(const Scene& scene, const CartRailOptions& options, MappingPipeline& pipeline,
                     const std::function<CellMask(const ElevationMap&)>& swept_area,
                     const TopVisibility& visibility, CartRailResult& result);

/// The structured-light run over the poses (cart_rail_structured_light.cpp).
void run_structured_light_rail(const Scene& scene, const CartRailOptions& options,
                               const std::vector<TrunkPose>& poses, CartRailResult& result);

}  // namespace stridemap::detail
