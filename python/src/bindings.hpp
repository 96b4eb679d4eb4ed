#pragma once
// Shared by the binding files of the Python module (docs/python.md): the
// registration functions, one per file, and the checks every NumPy input
// goes through so that a wrong shape, dtype or value is a Python exception
// naming the argument, never a crash.
#include <cstddef>
#include <cstdint>
#include <optional>
#include <string>

#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>

#include "stridemap/core/grid_map.hpp"
#include "stridemap/core/pose.hpp"
#include "stridemap/mapfile/map_file.hpp"

namespace stridemap::python {

namespace py = pybind11;

/// A file or folder argument: a str or any os.PathLike (pathlib.Path), as
/// Python's own file functions take.
struct FilePath {
  std::string value;
  operator const std::string&() const { return value; }
};

void register_errors(py::module_& m);
void register_options(py::module_& m);
void register_map(py::module_& m);
void register_pipeline(py::module_& m);
void register_simulation(py::module_& m);
void register_experiments(py::module_& m);
/// Map.submap, Map.from_arrays and map[name] (map_build.cpp), on the class
/// register_map binds.
void add_map_builders(py::class_<ElevationMap>& map_class);

/// created_by of a map file saved from a Pipeline unless the caller names it.
inline constexpr const char* kPipelineCreatedBy = "Python stridemap.Pipeline";

/// The metadata the CLI would record for `map` when it is the map a live
/// Pipeline builds (its mount, configuration, last pose and time), else
/// nothing: a Map of its own or a copy knows no settings.
std::optional<io::MapFileMetadata> pipeline_map_metadata(const ElevationMap& map, const std::string& created_by);

/// `map`, its foothold layers brought up to date first when it is the map a
/// live Pipeline builds (MappingPipeline::map(): they are computed when read,
/// not after every scan). Every Map method that reads layers goes through it.
const ElevationMap& layers_current(const ElevationMap& map);

/// Raises stridemap.InputError (a ValueError) with `message`.
[[noreturn]] void raise_input_error(const std::string& message);

// Every array argument reaches C++ through these, so that a copy NumPy
// cannot allocate is a MemoryError naming the argument (never a null array
// dereferenced: pybind11's array_t::ensure hides the failure).

/// numpy.asarray(obj): no copy for an array. MemoryError naming `argument`
/// when the conversion cannot be allocated, TypeError for anything else
/// NumPy refuses.
py::array as_array(const py::handle& obj, const std::string& argument);

/// A C-contiguous float64 array of `obj`, which must be numeric (integers
/// or floats; not bool, object or complex): TypeError naming `argument`
/// otherwise. No copy when it already is one.
py::array_t<double, py::array::c_style> as_float64(const py::handle& obj, const std::string& argument);

/// `array` as C-contiguous uint8, copied only when it is not; MemoryError
/// naming `argument` when the copy cannot be allocated.
py::array_t<std::uint8_t, py::array::c_style> as_contiguous_uint8(const py::array& array, const std::string& argument);

/// `pose`: a sequence of 5 numbers (x_m, y_m, roll_rad, pitch_rad, yaw_rad:
/// the paper's model, the sensor at the mount's height above the reference
/// elevation) or 6 (x_m, y_m, z_m, roll_rad, pitch_rad, yaw_rad: a 6-DoF
/// state, the mount applied rigidly). Every value finite.
TrunkPose pose_from_values(const double* values, std::size_t count, double reference_elevation_m,
                           double height_change_m, const std::string& argument);
TrunkPose pose_from_object(const py::handle& pose, double reference_elevation_m, double height_change_m,
                           const std::string& argument);

/// Past this |roll| or |pitch| a walking robot has fallen over; the number
/// is far likelier degrees passed where radians belong (a 10 deg pitch
/// passed as 10 is 573 deg).
inline constexpr double kImplausibleTiltRad = 60.0 * 3.14159265358979323846 / 180.0;

/// A UserWarning naming the angle when `pose`'s |roll| or |pitch| is beyond
/// kImplausibleTiltRad. Not an error: a test rig may tilt that far.
void warn_implausible_tilt(const TrunkPose& pose, const std::string& argument);
/// The same for an array of poses (K, 5) or (K, 6), checked already: one
/// warning for the call, naming how many and the first.
void warn_implausible_tilts(const py::array_t<double, py::array::c_style>& poses, const std::string& argument);

/// "poses[3]": one element of an argument, for messages.
std::string element_name(const std::string& argument, long long index);

/// The shortest text that reads back as `value` (Python's repr of a float),
/// for messages.
std::string number_text(double value);

/// A finite number, InputError naming `argument` otherwise.
double finite_number(double value, const std::string& argument);

}  // namespace stridemap::python

namespace pybind11::detail {

template <>
struct type_caster<stridemap::python::FilePath> {
  PYBIND11_TYPE_CASTER(stridemap::python::FilePath, const_name("str | os.PathLike"));
  bool load(handle source, bool) {
    // os.fspath(): str as it is, bytes, or what __fspath__ returns.
    object path = reinterpret_steal<object>(PyOS_FSPath(source.ptr()));
    if (!path) {
      PyErr_Clear();
      return false;
    }
    if (PyUnicode_Check(path.ptr())) {
      value.value = path.cast<std::string>();
      return true;
    }
    if (PyBytes_Check(path.ptr())) {
      value.value = std::string(PyBytes_AS_STRING(path.ptr()), static_cast<std::size_t>(PyBytes_GET_SIZE(path.ptr())));
      return true;
    }
    return false;
  }
  static handle cast(const stridemap::python::FilePath& path, return_value_policy, handle) {
    return str(path.value).release();
  }
};

}  // namespace pybind11::detail
