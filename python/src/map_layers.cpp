// The one place the bindings read a map's layers (docs/python.md, "Zero
// copy"): names, dtypes and where each layer's storage is, from the map's
// own layer registry, so a layer a user declared is there like the rest.
//
// ElevationMap keeps every layer as an N x N block indexed by slot
// (ix mod N, iy mod N): a circular buffer, so that moving the window copies
// nothing. A view of that block is exact and free; it is the window's order
// (element [i, j] = cell min_cell + (i, j)) only when the window's corner
// cell sits in slot (0, 0). Otherwise the window order is the block rolled,
// which NumPy can only do by copying.
#include <optional>
#include <cstdint>
#include <string>
#include <utility>
#include <vector>

#include "bindings.hpp"
#include "map_layers.hpp"
#include "stridemap/core/grid_map.hpp"

namespace stridemap::python {
namespace {

template <class T>
py::array view_of(const T* data, int n, py::handle base) {
  const auto side = static_cast<py::ssize_t>(n);
  py::array array(py::dtype::of<T>(), {side, side},
                  {side * static_cast<py::ssize_t>(sizeof(T)), static_cast<py::ssize_t>(sizeof(T))}, data, base);
  // The map's invariants (state agrees with certainty, NaN where unknown)
  // belong to the update rule: a view only reads.
  array.attr("setflags")(py::arg("write") = false);
  return array;
}

const char* numpy_type_name(LayerType type) {
  switch (type) {
    case LayerType::f32: return "float32";
    case LayerType::u16: return "uint16";
    case LayerType::u8: break;
  }
  return "uint8";
}

}  // namespace

std::vector<std::string> layer_names(const ElevationMap& map) {
  std::vector<std::string> names;
  for (std::size_t i = 0; i < map.layer_count(); ++i) names.push_back(map.layer_spec(i).name);
  return names;
}

std::string layer_descriptions(std::span<const LayerSpec> specs) {
  std::string text;
  for (const LayerSpec& spec : specs) {
    text += "  " + spec.name + ": " + numpy_type_name(spec.type) + (spec.unit.empty() ? "" : " [" + spec.unit + "]") +
            ", " + spec.description + "\n";
  }
  return text;
}

py::array storage_view(const ElevationMap& map, const std::string& name, py::handle base) {
  const std::optional<std::size_t> index = map.find_layer(name);
  if (!index) raise_input_error("layer: '" + name + "' is not a layer of this map; its layers are " + map.layer_names());
  const int n = map.cells_per_side();
  const void* bytes = map.layer_bytes(*index);
  switch (map.layer_spec(*index).type) {
    case LayerType::f32: return view_of(static_cast<const float*>(bytes), n, base);
    case LayerType::u16: return view_of(static_cast<const std::uint16_t*>(bytes), n, base);
    case LayerType::u8: break;
  }
  return view_of(static_cast<const std::uint8_t*>(bytes), n, base);
}

std::pair<int, int> storage_corner(const ElevationMap& map) {
  const std::size_t slot = map.slot(map.min_cell());
  const auto n = static_cast<std::size_t>(map.cells_per_side());
  return {static_cast<int>(slot / n), static_cast<int>(slot % n)};
}

py::array window_layer(const ElevationMap& map, const std::string& name, py::handle base) {
  py::array view = storage_view(map, name, base);
  const auto [row, col] = storage_corner(map);
  if (row == 0 && col == 0) return view;
  py::array rolled = py::module_::import("numpy").attr("roll")(view, py::make_tuple(-row, -col),
                                                               py::make_tuple(0, 1));
  return rolled;
}

void add_layer(ElevationMap& map, const std::string& name, const std::string& dtype, double reset_value,
               const std::string& unit, const std::string& description) {
  LayerSpec spec;
  spec.name = name;
  if (dtype == "float32") {
    spec.type = LayerType::f32;
  } else if (dtype == "uint16") {
    spec.type = LayerType::u16;
  } else if (dtype == "uint8") {
    spec.type = LayerType::u8;
  } else {
    raise_input_error("add_layer: dtype: expected 'float32', 'uint16' or 'uint8', got '" + dtype + "'");
  }
  spec.reset_value = reset_value;
  spec.unit = unit;
  spec.description = description;
  map.add_layer(spec);
}

}  // namespace stridemap::python
