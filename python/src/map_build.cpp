// Maps made from other maps or from a user's arrays (docs/python.md): a box
// cut out of a map (Map.submap), a map from NumPy arrays (Map.from_arrays)
// and a layer by name (map["elevation"]). Arrays follow the layers' order:
// element [i, j] is the cell min_cell + (i, j), i along +X, j along +Y.
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdint>
#include <cstring>
#include <limits>
#include <optional>
#include <string>
#include <vector>

#include "bindings.hpp"
#include "map_layers.hpp"
#include "stridemap/core/cell_box.hpp"
#include "stridemap/core/grid_map.hpp"
#include "stridemap/core/map_integrity.hpp"

namespace stridemap::python {
namespace {

constexpr double kFloat32Max = std::numeric_limits<float>::max();
// Cell indices stay far inside int64 so that window arithmetic (corner + N,
// differences of corners) cannot overflow.
constexpr double kMaxCellIndex = 0x1p60;

std::string number_text(double value) {
  char text[64];
  std::snprintf(text, sizeof text, "%.17g", value);
  return text;
}

std::string cell_name(const std::string& argument, py::ssize_t i, py::ssize_t j) {
  return argument + "[" + std::to_string(i) + ", " + std::to_string(j) + "]";
}

std::string shape_text(const py::array& a) { return py::str(py::object(a.attr("shape"))).cast<std::string>(); }

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

// Every layer of `from` for the cells of `box` (which both maps' windows
// hold), into `to`, whose layers are `from`'s in the same order.
void copy_cells(const ElevationMap& from, ElevationMap& to, const CellBox& box) {
  for (std::size_t k = 0; k < from.layer_count(); ++k) {
    const std::size_t width = layer_type_bytes(from.layer_spec(k).type);
    const auto* in = static_cast<const unsigned char*>(from.layer_bytes(k));
    auto* out = static_cast<unsigned char*>(to.layer_bytes(k));
    for (std::int64_t x = box.min.x; x <= box.max.x; ++x) {
      for (std::int64_t y = box.min.y; y <= box.max.y; ++y) {
        std::memcpy(out + to.slot({x, y}) * width, in + from.slot({x, y}) * width, width);
      }
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

// --- Map.from_arrays ---

py::array_t<double, py::array::c_style> square_like(const py::handle& obj, const std::string& argument, py::ssize_t n) {
  const auto a = as_float64(obj, argument);
  if (a.ndim() != 2 || a.shape(0) != n || a.shape(1) != n) {
    raise_input_error(argument + ": expected shape (" + std::to_string(n) + ", " + std::to_string(n) +
                      ") like elevation_m, got " + shape_text(a));
  }
  return a;
}

CellIndex corner_cell(const py::handle& corner_m, double cell_size_m, int n) {
  if (corner_m.is_none()) return {-n / 2, -n / 2};  // centred on the origin, as Map(N, cell_size_m)
  const auto c = as_float64(corner_m, "corner_m");
  if (c.ndim() != 1 || c.shape(0) != 2) {
    raise_input_error("corner_m: expected 2 numbers (min_x_m, min_y_m), got shape " + shape_text(c));
  }
  CellIndex cell;
  for (int k = 0; k < 2; ++k) {
    const std::string name = element_name("corner_m", k);
    const double cells = finite_number(c.at(k), name) / cell_size_m;
    if (!(std::abs(cells) < kMaxCellIndex)) {
      raise_input_error(name + ": " + number_text(c.at(k)) + " m is beyond the cell grid at " +
                        number_text(cell_size_m) + " m cells");
    }
    const double whole = std::round(cells);
    // The map's cells are whole multiples of the cell size from the origin;
    // a corner between them would shift every cell by a fraction.
    if (std::abs(cells - whole) > 1e-6) {
      raise_input_error(name + ": " + number_text(c.at(k)) + " m is not on the grid of " + number_text(cell_size_m) +
                        " m cells (a corner is a whole number of cells from the origin; the nearest is " +
                        number_text(whole * cell_size_m) + " m)");
    }
    (k == 0 ? cell.x : cell.y) = static_cast<std::int64_t>(whole);
  }
  return cell;
}

// A float32 element of `argument`: NaN passes when `nan_ok`, infinity when
// `inf_ok`; a finite value beyond float32 would silently become infinite.
float to_float32(double v, const std::string& argument, py::ssize_t i, py::ssize_t j, bool nan_ok, bool inf_ok) {
  if ((std::isnan(v) && !nan_ok) || (std::isinf(v) && !inf_ok)) {
    raise_input_error(cell_name(argument, i, j) + ": expected a finite number" + (nan_ok ? " or NaN" : "") + ", got " +
                      number_text(v));
  }
  if (std::isfinite(v) && std::abs(v) > kFloat32Max) {
    raise_input_error(cell_name(argument, i, j) + ": " + number_text(v) + " does not fit float32");
  }
  return static_cast<float>(v);
}

double whole_in(double v, double max, const std::string& argument, py::ssize_t i, py::ssize_t j) {
  if (!(v >= 0.0 && v <= max && v == std::floor(v))) {
    raise_input_error(cell_name(argument, i, j) + ": expected a whole number from 0 to " + number_text(max) +
                      ", got " + number_text(v));
  }
  return v;
}

const char* state_word(int state) { return state == 0 ? "unknown" : state == 1 ? "measured" : "filled"; }

// The state a cell's elevation and certainty make, or the one given checked
// against them: the rules the map file reader holds every cell to
// (core/map_integrity.hpp), said in the arguments' names.
std::uint8_t cell_state(float elevation, float certainty, std::optional<double> given, py::ssize_t i, py::ssize_t j) {
  const std::string e = cell_name("elevation_m", i, j), c = cell_name("certainty", i, j);
  if (!given) {
    if (certainty > 0.0f && std::isnan(elevation)) {
      raise_input_error(e + ": NaN (unknown) where " + c + " is " + number_text(certainty) +
                        " > 0: a measured cell needs an elevation");
    }
    return certainty > 0.0f ? 1 : std::isnan(elevation) ? 0 : 2;
  }
  const int state = static_cast<int>(*given);
  const std::string s = cell_name("state", i, j) + " is " + std::to_string(state) + " (" + state_word(state) + ")";
  if (state == 0 && !std::isnan(elevation)) raise_input_error(s + " but " + e + " is " + number_text(elevation) + ", not NaN");
  if (state != 0 && std::isnan(elevation)) raise_input_error(s + " but " + e + " is NaN");
  if (state == 1 && !(certainty > 0.0f)) raise_input_error(s + " but " + c + " is " + number_text(certainty) + ", not > 0");
  if (state != 1 && certainty != 0.0f) raise_input_error(s + " but " + c + " is " + number_text(certainty) + ", not 0");
  return static_cast<std::uint8_t>(state);
}

template <class T>
void set_cell(ElevationMap& map, std::size_t layer, std::size_t slot, T value) {
  static_cast<T*>(map.layer_bytes(layer))[slot] = value;
}

// One array of `layers`: into the built-in layer of that name, or a layer
// it declares (uint8 and uint16 arrays keep their type, others float32).
void set_extra_layer(ElevationMap& map, const std::string& name, const py::handle& values, py::ssize_t n) {
  const std::string argument = "layers['" + name + "']";
  if (name == "elevation" || name == "certainty" || name == "state") {
    raise_input_error(argument + ": pass it as " + (name == "elevation" ? std::string("elevation_m") : name) +
                      ", not in layers");
  }
  const py::array given = as_array(values, argument);
  std::optional<std::size_t> index = map.find_layer(name);
  const bool builtin = index.has_value();
  if (!index) {
    LayerSpec spec;
    spec.name = name;
    const char kind = given.dtype().kind();
    const auto bytes = given.dtype().itemsize();
    spec.type = kind == 'u' && bytes == 1 ? LayerType::u8 : kind == 'u' && bytes == 2 ? LayerType::u16 : LayerType::f32;
    spec.reset_value = spec.type == LayerType::f32 ? std::numeric_limits<double>::quiet_NaN() : 0.0;
    spec.description = "from Map.from_arrays";
    try {
      index = map.add_layer(spec);
    } catch (const InputError& e) {
      raise_input_error(argument + ": " + e.what());
    }
  }
  const auto a = square_like(values, argument, n);
  const LayerType type = map.layer_spec(*index).type;
  for (py::ssize_t i = 0; i < n; ++i) {
    for (py::ssize_t j = 0; j < n; ++j) {
      const std::size_t slot = map.slot(map.cell_at_local(static_cast<int>(i), static_cast<int>(j)));
      const double v = a.at(i, j);
      switch (type) {
        case LayerType::f32: set_cell(map, *index, slot, to_float32(v, argument, i, j, true, !builtin)); break;
        case LayerType::u16: set_cell(map, *index, slot, static_cast<std::uint16_t>(whole_in(v, 65535, argument, i, j))); break;
        case LayerType::u8: set_cell(map, *index, slot, static_cast<std::uint8_t>(whole_in(v, 255, argument, i, j))); break;
      }
    }
  }
}

ElevationMap from_arrays(const py::object& elevation_m, const py::object& certainty, double cell_size_m,
                         const py::object& corner_m, const py::object& state, const py::object& layers) {
  const auto e = as_float64(elevation_m, "elevation_m");
  if (e.ndim() != 2 || e.shape(0) != e.shape(1) || e.shape(0) < 1) {
    raise_input_error("elevation_m: expected a square array (N, N) with N >= 1 (every Map is N x N cells), got shape " +
                      shape_text(e));
  }
  const py::ssize_t n = e.shape(0);
  if (n > kMaxGridCellsPerSide) {
    throw GridSizeError("elevation_m: " + std::to_string(n) + " x " + std::to_string(n) + " cells; a Map holds at most " +
                        std::to_string(kMaxGridCellsPerSide) + " a side");
  }
  if (!(std::isfinite(cell_size_m) && cell_size_m >= kMinCellSizeM && cell_size_m <= kMaxCellSizeM)) {
    throw GridSizeError("cell_size_m: expected " + number_text(kMinCellSizeM) + " to " + number_text(kMaxCellSizeM) +
                        " m, got " + number_text(cell_size_m));
  }
  const CellIndex corner = corner_cell(corner_m, cell_size_m, static_cast<int>(n));
  const auto c = square_like(certainty, "certainty", n);
  std::optional<py::array_t<double, py::array::c_style>> s;
  if (!state.is_none()) s = square_like(state, "state", n);

  ElevationMap map(GridOptions{static_cast<int>(n), cell_size_m});
  map.move_corner_to(corner);
  float* elevation_out = map.elevation_data();
  float* certainty_out = map.certainty_data();
  std::uint8_t* state_out = map.state_data();
  float* mean_out = map.mean_elevation_data();
  std::uint16_t* count_out = map.mean_count_data();
  for (py::ssize_t i = 0; i < n; ++i) {
    for (py::ssize_t j = 0; j < n; ++j) {
      const float h = to_float32(e.at(i, j), "elevation_m", i, j, true, false);
      const float w = to_float32(c.at(i, j), "certainty", i, j, false, false);
      if (w < 0.0f) raise_input_error(cell_name("certainty", i, j) + ": expected a number >= 0, got " + number_text(w));
      if (c.at(i, j) > 0.0 && w == 0.0f) {
        raise_input_error(cell_name("certainty", i, j) + ": " + number_text(c.at(i, j)) + " is 0 in float32");
      }
      const std::optional<double> given = s ? std::optional<double>(whole_in(s->at(i, j), 2, "state", i, j)) : std::nullopt;
      const std::size_t slot = map.slot(map.cell_at_local(static_cast<int>(i), static_cast<int>(j)));
      elevation_out[slot] = h;
      certainty_out[slot] = w;
      state_out[slot] = cell_state(h, w, given, i, j);
      // A measured cell's running mean starts as if its elevation were one
      // reading, so that mapping resumed from this map goes on from it
      // (a NaN mean with count 0 would stay NaN).
      if (state_out[slot] == 1) {
        mean_out[slot] = h;
        count_out[slot] = 1;
      }
    }
  }
  if (!layers.is_none()) {
    if (!py::isinstance<py::dict>(layers)) {
      throw py::type_error("layers: expected a dict {name: (N, N) array}, got " +
                           py::str(py::type::handle_of(layers).attr("__name__")).cast<std::string>());
    }
    for (const auto& [key, values] : layers.cast<py::dict>()) {
      if (!py::isinstance<py::str>(key)) {
        throw py::type_error("layers: expected layer names (str) as keys, got " +
                             py::str(py::type::handle_of(key).attr("__name__")).cast<std::string>());
      }
      set_extra_layer(map, key.cast<std::string>(), values, n);
    }
  }
  // The checks above are the file reader's rules; this is the reader's own
  // check, so that a map made here always saves and loads.
  const MapIntegrity integrity = check_map_integrity(map, kFloat32Max);
  if (!integrity.ok()) raise_input_error("from_arrays: " + integrity.first_problem);
  return map;
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
      .def_static("from_arrays", &from_arrays, py::arg("elevation_m"), py::arg("certainty"), py::kw_only(),
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
