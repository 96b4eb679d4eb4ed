// Maps made from other maps (docs/python.md): a box cut out of a map
// (Map.submap) and a layer by name (map["elevation"]); Map.from_arrays is
// in map_from_arrays.cpp. Arrays follow the layers' order: element [i, j]
// is the cell min_cell + (i, j), i along +X, j along +Y.
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <string>
#include <vector>

#include "bindings.hpp"
#include "map_layers.hpp"
#include "stridemap/core/cell_box.hpp"
#include "stridemap/core/grid_map.hpp"

namespace stridemap::python {
namespace {

// A coordinate divided by the cell size, snapped to the whole number it is
// within rounding of: 0.3 / 0.01 is 29.999999999999996, and the box edge the
// user wrote at 0.3 m is the edge between cells 29 and 30.
double in_cells(double value_m, double cell_size_m) {
  const double cells = value_m / cell_size_m;
  const double whole = std::round(cells);
  return std::abs(cells - whole) <= 1e-9 * std::max(1.0, std::abs(cells)) ? whole : cells;
}

struct AxisRange {
  std::int64_t first = 0, last = -1;  // both inclusive; empty when first > last
};

// The cells of [min_m, max_m] on one axis that overlap it (a box edge on a
// cell edge takes no cell beyond it), clipped to the window's [lo, lo + n).
// A box of zero width takes the cell holding it.
AxisRange box_cells(double min_m, double max_m, double cell_size_m, std::int64_t lo, int n) {
  // Clamped before any conversion so that 1e300 m cannot overflow; clamping
  // to one cell beyond the window changes nothing that survives the clip.
  const double window_lo = static_cast<double>(lo) - 1.0, window_hi = static_cast<double>(lo + n) + 1.0;
  const double a = std::clamp(in_cells(min_m, cell_size_m), window_lo, window_hi);
  const double b = std::clamp(in_cells(max_m, cell_size_m), window_lo, window_hi);
  AxisRange range;
  range.first = static_cast<std::int64_t>(std::floor(a));
  range.last = b > a ? static_cast<std::int64_t>(std::ceil(b)) - 1 : range.first;
  range.first = std::max(range.first, lo);
  range.last = std::min(range.last, lo + n - 1);
  return range;
}

template <class T>
void copy_layer(const T* in, T* out, const std::vector<std::size_t>& in_rows, const std::vector<std::size_t>& in_cols,
                const std::vector<std::size_t>& out_rows, const std::vector<std::size_t>& out_cols) {
  for (std::size_t a = 0; a < in_rows.size(); ++a) {
    for (std::size_t b = 0; b < in_cols.size(); ++b) out[out_rows[a] + out_cols[b]] = in[in_rows[a] + in_cols[b]];
  }
}

// Every layer of `from` for the cells of `box` (which both maps' windows
// hold), into `to`, whose layers are `from`'s in the same order. A slot is
// (ix mod N) N + (iy mod N): the two parts are worked out once per row and
// column, not per cell and layer (a 4096-cell window has 16.8 M cells).
void copy_cells(const ElevationMap& from, ElevationMap& to, const CellBox& box) {
  std::vector<std::size_t> in_rows, out_rows, in_cols, out_cols;
  for (std::int64_t x = box.min.x; x <= box.max.x; ++x) {
    in_rows.push_back(from.slot({x, 0}));
    out_rows.push_back(to.slot({x, 0}));
  }
  for (std::int64_t y = box.min.y; y <= box.max.y; ++y) {
    in_cols.push_back(from.slot({0, y}));
    out_cols.push_back(to.slot({0, y}));
  }
  for (std::size_t k = 0; k < from.layer_count(); ++k) {
    const void* in = from.layer_bytes(k);
    void* out = to.layer_bytes(k);
    switch (from.layer_spec(k).type) {
      case LayerType::f32:
        copy_layer(static_cast<const float*>(in), static_cast<float*>(out), in_rows, in_cols, out_rows, out_cols);
        break;
      case LayerType::u16:
        copy_layer(static_cast<const std::uint16_t*>(in), static_cast<std::uint16_t*>(out), in_rows, in_cols, out_rows,
                   out_cols);
        break;
      case LayerType::u8:
        copy_layer(static_cast<const std::uint8_t*>(in), static_cast<std::uint8_t*>(out), in_rows, in_cols, out_rows,
                   out_cols);
        break;
    }
  }
}

// A map with `like`'s cell size and layers (the built-in ones and every one
// declared after them, in the same order), N cells a side, its corner at
// `corner`; every cell at its layers' reset values.
ElevationMap empty_like(const ElevationMap& like, int n, CellIndex corner) {
  GridOptions grid{n, like.cell_size_m()};
  for (std::size_t k = builtin_layers().size(); k < like.layer_count(); ++k) grid.extra_layers.push_back(like.layer_spec(k));
  ElevationMap map(grid);
  map.move_corner_to(corner);
  return map;
}

ElevationMap submap(const ElevationMap& parent, double min_x_m, double min_y_m, double max_x_m, double max_y_m) {
  finite_number(min_x_m, "min_x_m");
  finite_number(min_y_m, "min_y_m");
  finite_number(max_x_m, "max_x_m");
  finite_number(max_y_m, "max_y_m");
  if (min_x_m > max_x_m) {
    raise_input_error("min_x_m: " + number_text(min_x_m) + " m is greater than max_x_m " + number_text(max_x_m) + " m");
  }
  if (min_y_m > max_y_m) {
    raise_input_error("min_y_m: " + number_text(min_y_m) + " m is greater than max_y_m " + number_text(max_y_m) + " m");
  }
  const ElevationMap& map = layers_current(parent);
  const double s = map.cell_size_m();
  const int n = map.cells_per_side();
  const AxisRange xs = box_cells(min_x_m, max_x_m, s, map.min_cell().x, n);
  const AxisRange ys = box_cells(min_y_m, max_y_m, s, map.min_cell().y, n);
  if (xs.first > xs.last || ys.first > ys.last) {
    const double x = static_cast<double>(map.min_cell().x) * s, y = static_cast<double>(map.min_cell().y) * s;
    raise_input_error("box (min_x_m=" + number_text(min_x_m) + ", min_y_m=" + number_text(min_y_m) + ", max_x_m=" +
                      number_text(max_x_m) + ", max_y_m=" + number_text(max_y_m) +
                      ") holds no cell of the map, whose extent_m is (" + number_text(x) + ", " + number_text(y) +
                      ", " + number_text(x + n * s) + ", " + number_text(y + n * s) + ")");
  }
  const CellBox box{{xs.first, ys.first}, {xs.last, ys.last}};
  const auto side = static_cast<int>(std::max(xs.last - xs.first, ys.last - ys.first) + 1);
  ElevationMap out = empty_like(map, side, box.min);
  copy_cells(map, out, box);
  return out;
}

}  // namespace

void add_map_builders(py::class_<ElevationMap>& map_class) {
  map_class
      .def("submap", &submap, py::arg("min_x_m"), py::arg("min_y_m"), py::arg("max_x_m"), py::arg("max_y_m"),
           "A new Map of the cells inside the box [min_x_m, max_x_m] x [min_y_m, max_y_m] (metres, map frame; the "
           "order of extent_m, so m.submap(*m.extent_m) is a copy) with every layer. A cell is in the box when it "
           "overlaps it: a box edge on a cell edge takes no cell beyond it, a box of zero width the cell holding "
           "it. The box is clipped to this map's window. The cells keep their global indices and centres "
           "(min_cell, centers_of, x_m and y_m agree with this map's). Every Map is square: a box of nx x ny "
           "cells gives a map of max(nx, ny) cells a side, the extra cells (at larger x or y) unknown; "
           "sub.layer(name)[:nx, :ny] is the box. Raises InputError for a bound that is NaN or infinite, a "
           "minimum above its maximum, or a box that holds no cell of the window.")
      .def_static("from_arrays", &map_from_arrays, py::arg("elevation_m"), py::arg("certainty"), py::kw_only(),
                  py::arg("cell_size_m"), py::arg("corner_m") = py::none(), py::arg("state") = py::none(),
                  py::arg("layers") = py::none(),
                  "A Map from arrays of shape (N, N) indexed [i, j] = (x, y) as layer() returns them: elevation_m "
                  "[m] (NaN = unknown; stored as float32) and certainty (>= 0, finite). cell_size_m [m]; corner_m "
                  "= (min_x_m, min_y_m), the window's corner, a whole number of cells from the origin (extent_m[:2]; "
                  "default: the window centred on the origin, as Map(N, cell_size_m)). state (0 unknown, 1 "
                  "measured, 2 filled) defaults to: certainty > 0 measured, else a finite elevation filled, else "
                  "unknown; given, it must agree with them as in a map file. layers: {name: (N, N) array} for the "
                  "other built-in layers or new ones (uint8 and uint16 arrays keep their type, others become "
                  "float32). A measured cell's mean_elevation and mean_count start as its elevation and 1 unless "
                  "given. Raises InputError (TypeError for a non-numeric array) naming the argument and cell.")
      .def(
          "__getitem__",
          [](const py::object& self, const py::handle& key) {
            if (!py::isinstance<py::str>(key)) {
              throw py::type_error("Map[...]: expected a layer name (str), got " +
                                   py::str(py::type::handle_of(key).attr("__name__")).cast<std::string>() +
                                   "; index the layer for cells: m['elevation'][i, j]");
            }
            const ElevationMap& map = layers_current(self.cast<const ElevationMap&>());
            const std::string name = key.cast<std::string>();
            if (!map.find_layer(name)) {
              throw py::key_error("'" + name + "' is not a layer of this map; its layers are " + map.layer_names());
            }
            return window_layer(map, name, self);
          },
          py::arg("name"), "m[name] is m.layer(name); KeyError for a name that is not a layer.")
      .def(
          "__contains__",
          [](const ElevationMap& map, const py::handle& key) {
            return py::isinstance<py::str>(key) && map.find_layer(key.cast<std::string>()).has_value();
          },
          py::arg("name"), "Whether the map has a layer of that name.");
  // m[name] makes Python treat a Map as a sequence indexed 0, 1, ...;
  // iterating it would only raise a confusing TypeError from m[0].
  map_class.attr("__iter__") = py::none();
}

}  // namespace stridemap::python
