#pragma once
// A map's layers written the way every command writes them: elevation.png
// (filled cells hatched) and certainty.png with legends, and elevation.csv,
// certainty.csv and state.csv (docs/outputs.md). Deterministic: the same
// map gives the same bytes.
#include <cstdint>
#include <optional>
#include <string>

#include <Eigen/Core>

#include "stridemap/core/grid_map.hpp"

namespace stridemap::io {

/// The layers in window order (row = local x, column = local y).
struct MapLayers {
  Eigen::MatrixXf elevation_m;  ///< NaN where unknown
  Eigen::MatrixXf certainty;
  Eigen::Matrix<std::uint8_t, Eigen::Dynamic, Eigen::Dynamic> state;  ///< CellState values
  CellIndex min_cell;
  double cell_size_m = 0.0;
};

MapLayers export_map_layers(const ElevationMap& map);

struct MapOutputOptions {
  std::string elevation_title = "Elevation";
  /// Ends of the elevation colour scale; empty: from the values.
  std::optional<double> elevation_min_m;
  std::optional<double> elevation_max_m;
  /// Top of the certainty scale (UpdateOptions::certainty_max).
  double certainty_max = 1.0;
};

/// Writes the five files into `directory` (created if missing), each
/// appearing only when complete. Throws InputError naming the file.
void write_map_layers(const MapLayers& layers, const std::string& directory, const MapOutputOptions& options);

/// Known (measured or filled) cells over all cells.
double map_coverage(const MapLayers& layers);

}  // namespace stridemap::io
