// stridemap.Map (an ElevationMap), stridemap.MapFile and the map's files:
// the .smap map file (mapfile/map_file.hpp), NumPy/PLY/CSV exports and the PNG
// pictures every command writes.
#include <cmath>
#include <cstdio>
#include <optional>
#include <span>
#include <string>

#include <pybind11/stl.h>

#include "bindings.hpp"
#include "map_layers.hpp"
#include "stridemap/core/foothold.hpp"
#include "stridemap/core/grid_map.hpp"
#include "stridemap/io/output_folder.hpp"
#include "stridemap/mapfile/map_file.hpp"
#include "stridemap/mapfile/map_outputs.hpp"
#include "stridemap/render/map_export.hpp"
#include "stridemap/render/map_export_formats.hpp"
#include "stridemap/render/png_image.hpp"

namespace stridemap::python {
namespace {

// A coordinate whose cell index fits a 64-bit integer; beyond it the
// conversion would be undefined (it gave INT64_MIN).
double on_cell_grid(const ElevationMap& map, double value_m, const std::string& argument) {
  finite_number(value_m, argument);
  const double limit_m = 0x1p62 * map.cell_size_m();
  if (!(std::abs(value_m) < limit_m)) {
    raise_input_error(argument + ": " + std::to_string(value_m) + " m is beyond the cell grid (|" + argument +
                      "| below " + std::to_string(limit_m) + " m at " + std::to_string(map.cell_size_m()) + " m cells)");
  }
  return value_m;
}

// A pose as the map file spells it (its last_pose object), so that a
// loaded file's metadata can be handed back to Map.save unchanged.
py::dict pose_dict(const TrunkPose& p) {
  py::dict d;
  d["x_m"] = p.x_m;
  d["y_m"] = p.y_m;
  d["z_m"] = p.z_m ? py::cast(*p.z_m) : py::none();
  d["roll_rad"] = p.roll_rad;
  d["pitch_rad"] = p.pitch_rad;
  d["yaw_rad"] = p.yaw_rad;
  d["reference_elevation_m"] = p.reference_elevation_m;
  d["height_change_m"] = p.height_change_m;
  return d;
}

TrunkPose pose_from_dict(const py::dict& d, const std::string& argument) {
  const auto number = [&](const char* key) {
    if (!d.contains(key)) raise_input_error(argument + ": '" + key + "' is missing");
    const py::object value = d[key];
    // bool is an int to Python, but True is no coordinate.
    if (py::isinstance<py::bool_>(value) || !(py::isinstance<py::float_>(value) || py::isinstance<py::int_>(value))) {
      throw py::type_error(argument + "." + key + ": expected a number, got " +
                           py::str(py::type::of(value).attr("__name__")).cast<std::string>());
    }
    return finite_number(value.cast<double>(), argument + "." + key);
  };
  TrunkPose pose;
  pose.x_m = number("x_m");
  pose.y_m = number("y_m");
  pose.roll_rad = number("roll_rad");
  pose.pitch_rad = number("pitch_rad");
  pose.yaw_rad = number("yaw_rad");
  pose.reference_elevation_m = number("reference_elevation_m");
  pose.height_change_m = number("height_change_m");
  if (d.contains("z_m") && !d["z_m"].is_none()) pose.z_m = number("z_m");
  warn_implausible_tilt(pose, argument);
  return pose;
}

// Every field of io::MapFileMetadata.
py::dict metadata_dict(const io::MapFileMetadata& metadata) {
  py::dict d;
  d["tool_version"] = metadata.tool_version;
  d["created_by"] = metadata.created_by;
  d["config_text"] = metadata.config_text;
  d["mount"] = metadata.mount ? py::cast(*metadata.mount) : py::none();
  d["last_scan_time_s"] = metadata.last_scan_time_s ? py::cast(*metadata.last_scan_time_s) : py::none();
  d["last_pose"] = metadata.last_pose ? py::object(pose_dict(*metadata.last_pose)) : py::none();
  return d;
}

std::string shape_of(const py::array& a) { return py::str(py::object(a.attr("shape"))).cast<std::string>(); }

py::array_t<std::int64_t> cells_of(const ElevationMap& map, const py::handle& points_m) {
  const auto p = as_float64(points_m, "points_m");
  if (p.ndim() != 2 || p.shape(1) != 2) raise_input_error("points_m: expected shape (N, 2), got " + shape_of(p));
  py::array_t<std::int64_t> out({p.shape(0), py::ssize_t{2}});
  auto o = out.mutable_unchecked<2>();
  for (py::ssize_t i = 0; i < p.shape(0); ++i) {
    const std::string row = element_name("points_m", i);
    const CellIndex c = map.cell_of(on_cell_grid(map, p.at(i, 0), row + "[0]"), on_cell_grid(map, p.at(i, 1), row + "[1]"));
    o(i, 0) = c.x;
    o(i, 1) = c.y;
  }
  return out;
}

py::array_t<double> centers_of(const ElevationMap& map, const py::handle& cells) {
  // Through float64 like every array argument (numpy_input.cpp): whole
  // numbers up to 2^53 are exact, far beyond any map's cells.
  const auto c = as_float64(cells, "cells");
  if (c.ndim() != 2 || c.shape(1) != 2) raise_input_error("cells: expected shape (N, 2), got " + shape_of(c));
  py::array_t<double> out({c.shape(0), py::ssize_t{2}});
  auto o = out.mutable_unchecked<2>();
  const auto index = [&](py::ssize_t i, py::ssize_t k) {
    const double v = c.at(i, k);
    if (!(std::abs(v) <= 0x1p53) || v != std::floor(v)) {
      raise_input_error(element_name("cells", i) + "[" + std::to_string(k) + "]: expected a whole number, got " +
                        std::to_string(v));
    }
    return static_cast<std::int64_t>(v);
  };
  for (py::ssize_t i = 0; i < c.shape(0); ++i) {
    const Eigen::Vector2d centre = map.cell_center({index(i, 0), index(i, 1)});
    o(i, 0) = centre.x();
    o(i, 1) = centre.y();
  }
  return out;
}

py::array_t<double> axis_centers(const ElevationMap& map, std::int64_t first_cell) {
  py::array_t<double> out(map.cells_per_side());
  auto o = out.mutable_unchecked<1>();
  for (int i = 0; i < map.cells_per_side(); ++i) {
    o(i) = map.cell_center({first_cell + i, first_cell}).x();
  }
  return out;
}

std::string map_repr(const ElevationMap& map) {
  std::size_t measured = 0;
  const std::size_t cells = static_cast<std::size_t>(map.cells_per_side()) * static_cast<std::size_t>(map.cells_per_side());
  for (std::size_t s = 0; s < cells; ++s) measured += map.state_data()[s] == static_cast<std::uint8_t>(CellState::measured);
  const double s = map.cell_size_m(), x = static_cast<double>(map.min_cell().x) * s, y = static_cast<double>(map.min_cell().y) * s;
  char text[256];
  std::snprintf(text, sizeof text, "<stridemap.Map %d x %d cells of %g m, x %g..%g m, y %g..%g m, %zu layers, %.1f %% measured>",
                map.cells_per_side(), map.cells_per_side(), s, x, x + map.cells_per_side() * s, y,
                y + map.cells_per_side() * s, map.layer_count(), cells ? 100.0 * static_cast<double>(measured) / static_cast<double>(cells) : 0.0);
  return text;
}

// A pipeline's map starts from what the pipeline knows; every argument
// given replaces its part.
void save(const ElevationMap& map, const FilePath& path, const std::optional<std::string>& created_by,
          const std::optional<std::string>& config_text, const std::optional<SensorMount>& mount,
          std::optional<double> last_scan_time_s, const std::optional<py::dict>& last_pose,
          bool overwrite_other_files) {
  io::MapFileMetadata metadata =
      pipeline_map_metadata(map, created_by.value_or(kPipelineCreatedBy)).value_or(io::MapFileMetadata{});
  if (created_by) metadata.created_by = *created_by;
  if (config_text) metadata.config_text = *config_text;
  if (mount) metadata.mount = mount;
  if (last_scan_time_s) metadata.last_scan_time_s = finite_number(*last_scan_time_s, "last_scan_time_s");
  if (last_pose) metadata.last_pose = pose_from_dict(*last_pose, "last_pose");
  io::save_map_file(path, layers_current(map), metadata, {overwrite_other_files});
}

void write_png_array(const FilePath& path, const py::handle& pixels) {
  const py::array array = as_array(pixels, "pixels");
  if (array.dtype().kind() != 'u' || array.dtype().itemsize() != 1) {
    throw py::type_error("pixels: expected a uint8 array, got dtype " + py::str(array.dtype()).cast<std::string>());
  }
  if (array.ndim() != 3 || array.shape(2) != 3) {
    raise_input_error("pixels: expected shape (height, width, 3) of RGB values, got " +
                      py::str(py::object(array.attr("shape"))).cast<std::string>());
  }
  const auto contiguous = as_contiguous_uint8(array, "pixels");
  io::RgbImage image;
  image.height = static_cast<int>(contiguous.shape(0));
  image.width = static_cast<int>(contiguous.shape(1));
  image.rgb.assign(contiguous.data(), contiguous.data() + contiguous.size());
  io::write_png(path, image);
}

}  // namespace

void register_map(py::module_& m) {
  py::class_<ElevationMap> map_class(m, "Map",
                           ("The local terrain map (core/grid_map.hpp): an N x N window of cells, each with these "
                            "layers:\n" +
                            layer_descriptions(builtin_layers()) +
                            "A Pipeline's map (with the foothold layers on, the default) also has:\n" +
                            layer_descriptions(foothold_layer_specs()) +
                            "and add_layer declares more; layer_names lists a map's own. Arrays are indexed [i, j]: "
                            "cell (min_cell[0] + i, min_cell[1] + j), i along +X (forward), j along +Y (left), as in "
                            "the map file.")
                               .c_str());
  map_class.def(py::init([](int cells_per_side, double cell_size_m) {
             return ElevationMap(GridOptions{cells_per_side, cell_size_m});
           }),
           py::arg("cells_per_side") = 100, py::arg("cell_size_m") = 0.01,
           "An empty map (every cell unknown). Raises GridSizeError for a grid too large or a cell size out of "
           "range.")
      .def("copy", [](const ElevationMap& map) { return ElevationMap(layers_current(map)); }, "An independent copy.")
      .def_property_readonly("cells_per_side", &ElevationMap::cells_per_side, "N.")
      .def_property_readonly("cell_size_m", &ElevationMap::cell_size_m, "Edge of a cell [m].")
      .def_property_readonly(
          "min_cell", [](const ElevationMap& map) { return py::make_tuple(map.min_cell().x, map.min_cell().y); },
          "Global index (ix, iy) of the window's corner cell (smallest x and y).")
      .def_property_readonly(
          "extent_m",
          [](const ElevationMap& map) {
            const double s = map.cell_size_m(), n = map.cells_per_side();
            const double x = static_cast<double>(map.min_cell().x) * s, y = static_cast<double>(map.min_cell().y) * s;
            return py::make_tuple(x, y, x + n * s, y + n * s);
          },
          "The window in the map frame: (min_x_m, min_y_m, max_x_m, max_y_m).")
      .def("cell_of", [](const ElevationMap& map, double x_m, double y_m) {
             const CellIndex c = map.cell_of(on_cell_grid(map, x_m, "x_m"), on_cell_grid(map, y_m, "y_m"));
             return py::make_tuple(c.x, c.y);
           }, py::arg("x_m"), py::arg("y_m"), "Global index (ix, iy) of the cell holding the point (x_m, y_m).")
      .def("cell_center", [](const ElevationMap& map, std::int64_t ix, std::int64_t iy) {
             const auto c = map.cell_center({ix, iy});
             return py::make_tuple(c.x(), c.y());
           }, py::arg("ix"), py::arg("iy"), "Centre (x_m, y_m) of the cell with global index (ix, iy).")
      .def("cells_of", &cells_of, py::arg("points_m"),
           "Global indices (N, 2) int64 of the cells holding points (N, 2) [m]: cell_of for many points at once.")
      .def("centers_of", &centers_of, py::arg("cells"),
           "Centres (N, 2) [m] of cells given by global index (N, 2): cell_center for many cells at once.")
      .def("x_m", [](const ElevationMap& map) { return axis_centers(map, map.min_cell().x); },
           "x [m] of the cells' centres along axis 0 of layer() (i): with y_m(), np.meshgrid(m.x_m(), m.y_m(), "
           "indexing='ij') gives every cell's centre.")
      .def("y_m", [](const ElevationMap& map) { return axis_centers(map, map.min_cell().y); },
           "y [m] of the cells' centres along axis 1 of layer() (j).")
      .def("__repr__", &map_repr)
      .def(py::pickle(
          [](const ElevationMap& map) {
            const std::string bytes = io::encode_map_file(layers_current(map), io::MapFileMetadata{});
            return py::bytes(bytes);
          },
          [](const py::bytes& bytes) {
            return io::decode_map_file(std::string_view(bytes), "pickled stridemap.Map").map;
          }))
      .def("contains", [](const ElevationMap& map, std::int64_t ix, std::int64_t iy) { return map.contains({ix, iy}); },
           py::arg("ix"), py::arg("iy"), "Whether the cell with global index (ix, iy) is inside the window.")
      .def(
          "layer",
          [](const py::object& self, const std::string& name) {
            return window_layer(layers_current(self.cast<const ElevationMap&>()), name, self);
          },
          py::arg("name"),
          "The layer in window order. A read-only zero-copy view (its .base keeps this map alive) when the window's "
          "corner cell is in storage slot (0, 0) (storage_corner == (0, 0)); otherwise a writable copy. A view "
          "shows later scans as they arrive; take .copy() for a snapshot. Raises InputError for an unknown name.")
      .def(
          "storage_view",
          [](const py::object& self, const std::string& name) {
            return storage_view(layers_current(self.cast<const ElevationMap&>()), name, self);
          },
          py::arg("name"),
          "Always a read-only zero-copy view of the layer's storage: element [a, b] is the cell whose global index "
          "is (a, b) modulo N (the circular buffer). np.roll(v, (-r, -c), (0, 1)) with (r, c) = storage_corner "
          "gives the window order.")
      .def_property_readonly(
          "storage_corner",
          [](const ElevationMap& map) {
            const auto [row, col] = storage_corner(map);
            return py::make_tuple(row, col);
          },
          "Storage (row, column) holding the window's corner cell; (0, 0) when layer() returns views.")
      .def_property_readonly(
          "layer_names",
          [](const ElevationMap& map) { return py::tuple(py::cast(layer_names(map))); },
          "Names of every layer this map holds, in its registry's order: the built-in ones, then those the "
          "pipeline declared (the foothold layers) and any declared with add_layer.")
      .def(
          "layers",
          [](const py::object& self) {
            py::dict d;
            for (const std::string& name : layer_names(layers_current(self.cast<const ElevationMap&>()))) {
              d[py::str(name)] = window_layer(self.cast<const ElevationMap&>(), name, self);
            }
            return d;
          },
          "Every layer of this map by name (the built-in ones, then any declared with add_layer), in window "
          "order (see layer()).")
      .def("add_layer", &add_layer, py::arg("name"), py::arg("dtype") = "float32", py::arg("reset_value") = 0.0,
           py::arg("unit") = "", py::arg("description") = "",
           "Declares a layer of your own (core/map_layer.hpp): a name of lower-case letters, digits and '_', a "
           "dtype ('float32', 'uint16' or 'uint8') and the value every cell starts with (NaN allowed for "
           "float32). It is saved in map files and selected by name like the built-in layers. Raises InputError "
           "for a bad or repeated name or a reset value the dtype cannot hold.")
      .def("save", &save, py::arg("path"), py::kw_only(), py::arg("created_by") = py::none(),
           py::arg("config_text") = py::none(), py::arg("mount") = py::none(),
           py::arg("last_scan_time_s") = py::none(), py::arg("last_pose") = py::none(),
           py::arg("overwrite_other_files") = false,
           "Writes the map file (.smap, docs/map_file.md) atomically. The map a Pipeline builds (pipeline.map) "
           "records that pipeline's mount, configuration, last pose and time, as Pipeline.save; any other map "
           "records only what is given, and `stridemap map --resume` refuses a file without a mount and a "
           "configuration. Given arguments replace the pipeline's: last_pose is a dict as MapFile.metadata gives "
           "it. An existing map file is replaced; any other existing file is refused (InputError) unless "
           "overwrite_other_files.")
      .def("export_npy", [](const ElevationMap& map, const FilePath& directory) { return io::export_npy(layers_current(map), directory); },
           py::arg("directory"), "Writes <layer>.npy for every layer into directory; returns the paths.")
      .def("export_ply",
           [](const ElevationMap& map, const FilePath& path) {
             const io::PlyStats stats = io::export_ply(layers_current(map), path);
             py::dict d;
             d["vertices"] = stats.vertices;
             d["triangles"] = stats.triangles;
             return d;
           },
           py::arg("path"), "A binary PLY mesh of the known cells, coloured by elevation; returns its counts.")
      .def("export_csv", [](const ElevationMap& map, const FilePath& directory) {
             return io::export_cells_csv(layers_current(map), directory);
           }, py::arg("directory"), "Writes cells.csv (one line per cell) into directory; returns its path.")
      .def("export",
           [](const ElevationMap& map, const std::string& format, const FilePath& path,
              const std::vector<std::string>& layers) {
             const io::MapExportRequest request{format, path.value};
             const ElevationMap& current = layers_current(map);
             std::vector<std::string> written = io::map_export_outputs(current, std::span(&request, 1), layers);
             io::export_map(current, std::span(&request, 1), layers);
             return written;
           },
           py::arg("format"), py::arg("path"), py::arg("layers") = std::vector<std::string>{},
           "Writes the map in a format of export_formats() (as `stridemap export --<format>`): path is the "
           "folder or the file; layers selects the layers of a format that takes a selection (empty: its "
           "default). Returns the paths written.")
      .def("write_pictures",
           [](const ElevationMap& map, const FilePath& directory, const std::string& title, double certainty_max) {
             io::MapOutputOptions options;
             options.elevation_title = title;
             options.certainty_max = certainty_max;
             // The set replaces the folder whole, and a folder holding anything
             // but earlier outputs is refused: a user's files are never lost.
             io::OutputFolder staged(directory, "directory");
             io::write_map_layers(export_map(layers_current(map)), staged.path(), options);
             staged.commit();
           },
           py::arg("directory"), py::kw_only(), py::arg("title") = "Elevation", py::arg("certainty_max") = 100.0,
           "Writes elevation.png and certainty.png (with legends) and elevation/certainty/state.csv as the "
           "folder `directory`, as the CLI's commands do (docs/outputs.md): the set appears whole, replacing an "
           "earlier set; a folder holding other files is refused (InputError).");
  add_map_builders(map_class);


  py::class_<io::MapFile>(m, "MapFile", "A loaded map file: the map, what it was made with, the format version.")
      .def_property_readonly(
          "map", [](io::MapFile& file) -> ElevationMap& { return file.map; }, py::return_value_policy::reference_internal,
          "The Map (kept alive by this object and by any view of it).")
      .def_property_readonly("metadata", [](const io::MapFile& file) { return metadata_dict(file.metadata); },
                             "dict of everything the file records of its making: tool_version, created_by, "
                             "config_text (the mapper configuration as JSON, or ''), mount (SensorMount or None), "
                             "last_scan_time_s (float or None), last_pose (dict of x_m, y_m, z_m (None unless "
                             "6-DoF), roll_rad, pitch_rad, yaw_rad, reference_elevation_m, height_change_m; or "
                             "None). The geometry and layers are the map's own (MapFile.map).")
      .def_readonly("version", &io::MapFile::version, "The file format's version.");

  // From the registry, so a format registered in C++ is listed too.
  m.def(
      "export_formats",
      [] {
        py::list formats;
        for (const io::MapExportFormat& format : io::map_export_formats()) {
          formats.append(py::dict(py::arg("name") = format.name, py::arg("description") = format.description,
                                  py::arg("folder") = format.folder, py::arg("takes_layers") = format.takes_layers));
        }
        return formats;
      },
      "The formats Map.export writes, in registration order, each as {'name', 'description', 'folder' (the "
      "path is a folder, else a file), 'takes_layers'}.");
  m.def("load_map", [](const FilePath& path) { return io::load_map_file(path); }, py::arg("path"),
        "Reads a map file (.smap). Raises InputError '<path>: <what is wrong>' for a missing file, a wrong magic "
        "or version, a checksum mismatch, bad metadata.");
  m.def("is_map_file", [](const FilePath& path) { return io::is_map_file(path); }, py::arg("path"), "Whether the file starts with the map file's signature.");
  m.def("write_png", &write_png_array, py::arg("path"), py::arg("pixels"),
        "Writes an RGB uint8 array of shape (height, width, 3) as a PNG (the library's libpng writer). The file "
        "appears only when complete and replaces any file at path, as numpy.save does.");
}

}  // namespace stridemap::python
