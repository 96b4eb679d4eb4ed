#pragma once
// A map's layers as NumPy arrays (map_layers.cpp says how and why).
#include <string>
#include <utility>
#include <vector>

#include "bindings.hpp"
#include "stridemap/core/grid_map.hpp"

namespace stridemap::python {

/// elevation, certainty, state, mean_elevation, mean_count,
/// pending_elevation, contradictions: the map file's layers.
std::vector<std::string> layer_names();
/// One line per layer: its name, dtype and meaning, for docstrings.
std::string layer_descriptions();
/// A read-only zero-copy view of the layer's storage (slot order), kept
/// alive by `base`. InputError for an unknown name.
py::array storage_view(const ElevationMap& map, const std::string& name, py::handle base);
/// The storage row and column holding the window's corner cell.
std::pair<int, int> storage_corner(const ElevationMap& map);
/// The layer in window order: the storage view itself when the corner is
/// in slot (0, 0), otherwise a writable copy.
py::array window_layer(const ElevationMap& map, const std::string& name, py::handle base);

}  // namespace stridemap::python
