#pragma once
// A map's layers as NumPy arrays (map_layers.cpp says how and why).
#include <span>
#include <string>
#include <utility>
#include <vector>

#include "bindings.hpp"
#include "stridemap/core/grid_map.hpp"

namespace stridemap::python {

/// This map's layers, from its registry: the built-in ones, then any the
/// pipeline or a user declared.
std::vector<std::string> layer_names(const ElevationMap& map);
/// Declares a layer on the map (ElevationMap::add_layer); dtype is a NumPy
/// type name: float32, uint16 or uint8. InputError for a bad declaration.
void add_layer(ElevationMap& map, const std::string& name, const std::string& dtype, double reset_value,
               const std::string& unit, const std::string& description);
/// One line per declaration: its name, dtype and meaning, for docstrings.
std::string layer_descriptions(std::span<const LayerSpec> specs);
/// A read-only zero-copy view of the layer's storage (slot order), kept
/// alive by `base`. InputError for an unknown name.
py::array storage_view(const ElevationMap& map, const std::string& name, py::handle base);
/// The storage row and column holding the window's corner cell.
std::pair<int, int> storage_corner(const ElevationMap& map);
/// The layer in window order: the storage view itself when the corner is
/// in slot (0, 0), otherwise a writable copy.
py::array window_layer(const ElevationMap& map, const std::string& name, py::handle base);

/// Map.from_arrays (map_from_arrays.cpp): a map of the arrays' cells, every
/// argument checked and named in any error.
ElevationMap map_from_arrays(const py::object& elevation_m, const py::object& certainty, double cell_size_m,
                             const py::object& corner_m, const py::object& state, const py::object& layers);

}  // namespace stridemap::python
