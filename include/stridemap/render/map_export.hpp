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
#include <span>
#include <string>
#include <vector>

#include "stridemap/core/grid_map.hpp"
#include "stridemap/render/grid_render.hpp"

namespace stridemap::io {

/// NumPy format v1.0 bytes for a row-major array of `rows` x `cols`
/// little-endian elements; `descr` is NumPy's type string ("<f4", "|u1",
/// "<u2"), `data` the elements' bytes (rows * cols * element size).
std::string encode_npy(const std::string& descr, std::size_t rows, std::size_t cols, const std::string& data);

/// The map's layers named in `layer_names`, in that order; every layer when
/// it is empty. Throws InputError for an unknown name (listing the layers
/// the map has) or a name given twice.
std::vector<std::size_t> select_layers(const ElevationMap& map, std::span<const std::string> layer_names);

/// Writes <layer>.npy for each selected layer (default: every layer of the
/// map, the built-in ones elevation, certainty, mean_elevation,
/// pending_elevation, mean_count, state, contradictions and any a user
/// added) into `directory` (created if missing). Returns the paths written.
std::vector<std::string> export_npy(const ElevationMap& map, const std::string& directory,
                                    std::span<const std::string> layer_names = {});

/// The names of the files export_npy writes for this selection.
std::vector<std::string> npy_file_names(const ElevationMap& map, std::span<const std::string> layer_names = {});

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
/// nan). Columns: ix, iy, x_m, y_m, then one per selected layer, named
/// <layer>_<unit> (elevation_m) or <layer>; the default selection is
/// elevation, certainty, state, mean_elevation, mean_count and every layer a
/// user added. Numbers read back to the same float. Returns the path written.
std::string export_cells_csv(const ElevationMap& map, const std::string& directory,
                             std::span<const std::string> layer_names = {});

}  // namespace stridemap::io
