// Map.from_arrays (docs/python.md): a Map from a user's NumPy arrays, held
// to the rules the map file reader holds every cell to, each failure naming
// the argument and the cell.
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>
#include <optional>
#include <string>
#include <vector>

#include "bindings.hpp"
#include "map_layers.hpp"
#include "stridemap/core/grid_map.hpp"
#include "stridemap/core/map_integrity.hpp"

namespace stridemap::python {
namespace {

constexpr double kFloat32Max = std::numeric_limits<float>::max();
// Cell indices stay far inside int64 so that window arithmetic (corner + N,
// differences of corners) cannot overflow.
constexpr double kMaxCellIndex = 0x1p60;

std::string cell_name(const std::string& argument, py::ssize_t i, py::ssize_t j) {
  return argument + "[" + std::to_string(i) + ", " + std::to_string(j) + "]";
}

std::string shape_text(const py::array& a) { return py::str(py::object(a.attr("shape"))).cast<std::string>(); }

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

constexpr int kNoState = -1;

// The state a cell's elevation and certainty make (given is kNoState), or
// the one given checked against them: the rules the map file reader holds
// every cell to (core/map_integrity.hpp), said in the arguments' names.
std::uint8_t cell_state(float elevation, float certainty, int given, py::ssize_t i, py::ssize_t j) {
  // Names are built only for a message: this runs for every cell.
  const auto e = [&] { return cell_name("elevation_m", i, j); };
  const auto c = [&] { return cell_name("certainty", i, j); };
  if (given == kNoState) {
    if (certainty > 0.0f && std::isnan(elevation)) {
      raise_input_error(e() + ": NaN (unknown) where " + c() + " is " + number_text(certainty) +
                        " > 0: a measured cell needs an elevation");
    }
    return certainty > 0.0f ? 1 : std::isnan(elevation) ? 0 : 2;
  }
  const auto s = [&] {
    return cell_name("state", i, j) + " is " + std::to_string(given) + " (" + state_word(given) + ") but ";
  };
  if (given == 0 && !std::isnan(elevation)) raise_input_error(s() + e() + " is " + number_text(elevation) + ", not NaN");
  if (given != 0 && std::isnan(elevation)) raise_input_error(s() + e() + " is NaN");
  if (given == 1 && !(certainty > 0.0f)) raise_input_error(s() + c() + " is " + number_text(certainty) + ", not > 0");
  if (given != 1 && certainty != 0.0f) raise_input_error(s() + c() + " is " + number_text(certainty) + ", not 0");
  return static_cast<std::uint8_t>(given);
}

template <class T>
void set_cell(ElevationMap& map, std::size_t layer, std::size_t slot, T value) {
  static_cast<T*>(map.layer_bytes(layer))[slot] = value;
}

// The type a new layer takes from the array given for it: uint8 and uint16
// keep theirs, everything else is float32.
LayerType layer_type_for(const py::handle& values, const std::string& argument) {
  const py::array given = as_array(values, argument);
  const char kind = given.dtype().kind();
  const auto bytes = given.dtype().itemsize();
  return kind == 'u' && bytes == 1 ? LayerType::u8 : kind == 'u' && bytes == 2 ? LayerType::u16 : LayerType::f32;
}

// One array of `layers`: into the built-in layer of that name, or a layer
// it declares of `type`.
void set_extra_layer(ElevationMap& map, const std::string& name, const py::handle& values, LayerType new_type,
                     py::ssize_t n) {
  const std::string argument = "layers['" + name + "']";
  if (name == "elevation" || name == "certainty" || name == "state") {
    raise_input_error(argument + ": pass it as " + (name == "elevation" ? std::string("elevation_m") : name) +
                      ", not in layers");
  }
  std::optional<std::size_t> index = map.find_layer(name);
  const bool builtin = index.has_value();
  if (!index) {
    LayerSpec spec;
    spec.name = name;
    spec.type = new_type;
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

}  // namespace

ElevationMap map_from_arrays(const py::object& elevation_m, const py::object& certainty, double cell_size_m,
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
      const int given = s ? static_cast<int>(whole_in(s->at(i, j), 2, "state", i, j)) : kNoState;
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
    struct Given {
      std::string name;
      py::handle values;
      LayerType type;
    };
    std::vector<Given> given;
    for (const auto& [key, values] : layers.cast<py::dict>()) {
      if (!py::isinstance<py::str>(key)) {
        throw py::type_error("layers: expected layer names (str) as keys, got " +
                             py::str(py::type::handle_of(key).attr("__name__")).cast<std::string>());
      }
      const std::string name = key.cast<std::string>();
      given.push_back({name, values, layer_type_for(values, "layers['" + name + "']")});
    }
    // Declared in the map file's order (widest first, core/map_layer.hpp),
    // so that the map loads back with the same layer_names.
    std::stable_sort(given.begin(), given.end(), [](const Given& a, const Given& b) {
      return layer_type_bytes(a.type) > layer_type_bytes(b.type);
    });
    for (const Given& layer : given) set_extra_layer(map, layer.name, layer.values, layer.type, n);
  }
  // The checks above are the file reader's rules; this is the reader's own
  // check, so that a map made here always saves and loads.
  const MapIntegrity integrity = check_map_integrity(map, kFloat32Max);
  if (!integrity.ok()) raise_input_error("from_arrays: " + integrity.first_problem);
  return map;
}

}  // namespace stridemap::python
