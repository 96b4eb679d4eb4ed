#pragma once
// A map's layers copied out of the circular window, for scoring, images,
// summaries and files: the geometry plus any of the map's layers by name,
// each an Eigen matrix in window order (row = local x index, forward;
// column = local y index, left). The one exported form of a map.
#include <cstddef>
#include <cstdint>
#include <span>
#include <string>
#include <string_view>
#include <vector>

#include <Eigen/Core>

#include "stridemap/core/cell_center.hpp"
#include "stridemap/core/grid_map.hpp"
#include "stridemap/core/map_layer.hpp"

namespace stridemap {

using CellMask = Eigen::Matrix<std::uint8_t, Eigen::Dynamic, Eigen::Dynamic>;
using CountMatrix = Eigen::Matrix<std::uint16_t, Eigen::Dynamic, Eigen::Dynamic>;

/// One layer; only the matrix of its type is filled.
struct ExportedLayer {
  LayerSpec spec;
  Eigen::MatrixXf f32;
  CountMatrix u16;
  CellMask u8;

  /// The element at (i, j) as a float, whatever the type (exact for all three).
  float value(Eigen::Index i, Eigen::Index j) const {
    switch (spec.type) {
      case LayerType::f32: return f32(i, j);
      case LayerType::u16: return u16(i, j);
      case LayerType::u8: break;
    }
    return u8(i, j);
  }
};

struct ExportedMap {
  CellIndex min_cell;        ///< global index of element (0, 0)
  double cell_size_m = 0.0;
  int cells_per_side = 0;
  std::vector<ExportedLayer> layers;

  /// Centre of element (i, j) in the map frame [m]; (0, 0) gives the
  /// origin that grid files and messages name.
  Eigen::Vector2d cell_center(Eigen::Index i, Eigen::Index j) const {
    return stridemap::cell_center(CellIndex{min_cell.x + i, min_cell.y + j}, cell_size_m);
  }
  /// Centre of a cell by global index in the map frame [m].
  Eigen::Vector2d cell_center(CellIndex cell) const { return stridemap::cell_center(cell, cell_size_m); }

  /// The named layer, or null.
  const ExportedLayer* find(std::string_view name) const;
  ExportedLayer* find(std::string_view name);
  /// The named layer; throws InputError listing the layers exported.
  const ExportedLayer& layer(std::string_view name) const;
  ExportedLayer& layer(std::string_view name);
  /// "elevation, certainty, state": for messages.
  std::string layer_names() const;

  /// The planner's layers (a look-up by name each: bind the result once
  /// outside a loop).
  const Eigen::MatrixXf& elevation_m() const { return layer("elevation").f32; }  ///< NaN where unknown
  const Eigen::MatrixXf& certainty() const { return layer("certainty").f32; }
  const CellMask& state() const { return layer("state").u8; }  ///< CellState values
  Eigen::MatrixXf& elevation_m() { return layer("elevation").f32; }
  Eigen::MatrixXf& certainty() { return layer("certainty").f32; }
  CellMask& state() { return layer("state").u8; }
};

/// The layers declared `exported` (elevation, certainty, state and, by
/// default, every layer a user adds).
ExportedMap export_map(const ElevationMap& map);
/// The named layers, in the order given. Throws InputError naming an
/// unknown layer and listing the map's layers.
ExportedMap export_map(const ElevationMap& map, std::span<const std::string> layer_names);

/// Known (measured or filled) cells over all cells; 0 for an empty map.
double map_coverage(const ExportedMap& map);

}  // namespace stridemap
