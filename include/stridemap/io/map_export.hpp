#pragma once
// A map for other software (docs/map_file.md, "Exports"): one NumPy .npy
// array per layer, a PLY surface mesh with per-vertex colour (MeshLab,
// CloudCompare, Blender), and a CSV with one line per cell. Every array
// and the CSV use the map file's order: element [i][j] is the cell
// (min_cell.x + i, min_cell.y + j), i along +X (forward), j along +Y (left).
// Each file appears only when complete.
#include <cstddef>
#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "stridemap/core/grid_map.hpp"
#include "stridemap/io/grid_render.hpp"

namespace stridemap::io {

/// NumPy format v1.0 bytes for a row-major array of `rows` x `cols`
/// little-endian elements; `descr` is NumPy's type string ("<f4", "|u1",
/// "<u2"), `data` the elements' bytes (rows * cols * element size).
std::string encode_npy(const std::string& descr, std::size_t rows, std::size_t cols, const std::string& data);

/// Writes <layer>.npy for each layer of the map file (elevation, certainty,
/// state, mean_elevation, mean_count, pending_elevation, contradictions)
/// into `directory` (created if missing). Returns the paths written.
std::vector<std::string> export_npy(const ElevationMap& map, const std::string& directory);

/// The names of the files export_npy writes.
std::vector<std::string> npy_file_names();

struct PlyOptions {
  ColourScale colours = ColourScale::viridis;
  /// Ends of the colour scale [m]; empty: the lowest and highest known cell.
  std::optional<double> elevation_min_m;
  std::optional<double> elevation_max_m;
};

struct PlyStats {
  std::size_t vertices = 0;   ///< one per known (measured or filled) cell
  std::size_t triangles = 0;  ///< over every 2 x 2 block with 3 or 4 known cells
};

/// A binary little-endian PLY mesh: a vertex at the centre of every known
/// cell at its elevation (map frame, metres), coloured by elevation;
/// triangles join neighbouring known cells, facing up. Unknown cells are
/// holes. Throws InputError naming the path.
PlyStats export_ply(const ElevationMap& map, const std::string& path, const PlyOptions& options = {});

/// `cells.csv`: a header line stating the row order and units, the column
/// names, then one line per cell of the window (unknown cells too, with
/// nan). Numbers read back to the same float. Returns the path written.
std::string export_cells_csv(const ElevationMap& map, const std::string& directory);

}  // namespace stridemap::io
