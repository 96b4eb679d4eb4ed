// The one place the bindings read a map's layers (docs/python.md, "Zero
// copy"): names, dtypes and where each layer's storage is. When the map's
// layers become an open set, only this file changes.
//
// ElevationMap keeps every layer as an N x N block indexed by slot
// (ix mod N, iy mod N): a circular buffer, so that moving the window copies
// nothing. A view of that block is exact and free; it is the window's order
// (element [i, j] = cell min_cell + (i, j)) only when the window's corner
// cell sits in slot (0, 0). Otherwise the window order is the block rolled,
// which NumPy can only do by copying.
#include <array>
#include <cstdint>
#include <string>
#include <utility>
#include <vector>

#include "bindings.hpp"
#include "map_layers.hpp"
#include "stridemap/core/grid_map.hpp"

namespace stridemap::python {
namespace {

struct Layer {
  const char* name;
  const char* doc;
};

// The map file's layer names and order (io/map_export.hpp's .npy files).
constexpr std::array<Layer, 7> kLayers{{
    {"elevation", "float32 [m], NaN where unknown: eq. (10)'s elevation"},
    {"certainty", "float32, 0 where unknown: eq. (9)'s certainty"},
    {"state", "uint8: 0 unknown, 1 measured, 2 filled"},
    {"mean_elevation", "float32 [m], NaN where unknown: mean of the accepted readings"},
    {"mean_count", "uint16: readings in mean_elevation"},
    {"pending_elevation", "float32 [m]: gated rule, highest contradicting reading"},
    {"contradictions", "uint8: gated rule, contradicting readings in a row"},
}};

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

}  // namespace

std::vector<std::string> layer_names() {
  std::vector<std::string> names;
  for (const Layer& layer : kLayers) names.emplace_back(layer.name);
  return names;
}

std::string layer_descriptions() {
  std::string text;
  for (const Layer& layer : kLayers) text += std::string("  ") + layer.name + ": " + layer.doc + "\n";
  return text;
}

py::array storage_view(const ElevationMap& map, const std::string& name, py::handle base) {
  const int n = map.cells_per_side();
  if (name == "elevation") return view_of(map.elevation_data(), n, base);
  if (name == "certainty") return view_of(map.certainty_data(), n, base);
  if (name == "state") return view_of(map.state_data(), n, base);
  if (name == "mean_elevation") return view_of(map.mean_elevation_data(), n, base);
  if (name == "mean_count") return view_of(map.mean_count_data(), n, base);
  if (name == "pending_elevation") return view_of(map.pending_elevation_data(), n, base);
  if (name == "contradictions") return view_of(map.contradiction_data(), n, base);
  std::string known;
  for (const Layer& layer : kLayers) known += (known.empty() ? "" : ", ") + std::string(layer.name);
  raise_input_error("layer: '" + name + "' is not a map layer; the layers are " + known);
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

}  // namespace stridemap::python
