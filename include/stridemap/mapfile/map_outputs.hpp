#pragma once
// A map's layers written the way every command writes them: elevation.png
// (filled cells hatched) and certainty.png with legends, and one <layer>.csv
// per exported layer: elevation.csv, certainty.csv, state.csv and any layer
// a user added, and foothold_score.png, slope_deg.png, step_height_m.png
// when the map has the foothold layers (docs/outputs.md). Deterministic: the same map gives the
// same bytes.
#include <cstdint>
#include <optional>
#include <string>

#include <Eigen/Core>

#include "stridemap/core/exported_map.hpp"

namespace stridemap::io {

struct MapOutputOptions {
  std::string elevation_title = "Elevation";
  /// Ends of the elevation colour scale; empty: from the values.
  std::optional<double> elevation_min_m;
  std::optional<double> elevation_max_m;
  /// Top of the certainty scale (UpdateOptions::certainty_max).
  double certainty_max = 1.0;
};

/// Writes the files into `directory` (created if missing), each appearing
/// only when complete. Needs the elevation, certainty and state layers.
/// Throws InputError naming the file.
void write_map_layers(const ExportedMap& layers, const std::string& directory, const MapOutputOptions& options);

}  // namespace stridemap::io
