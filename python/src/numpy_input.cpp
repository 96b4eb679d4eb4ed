// The checks between NumPy and the library: dtype, shape, finiteness, each
// failure naming the argument as the caller wrote it.
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstdint>
#include <string>

#include "bindings.hpp"
#include "feed/scan_feed.hpp"
#include "stridemap/core/error.hpp"

namespace stridemap::python {

void raise_input_error(const std::string& message) { throw InputError(message); }

namespace {

// "(3, 4) float32": what the caller passed, for a message.
std::string array_text(const py::array& array) {
  return py::str(py::object(array.attr("shape"))).cast<std::string>() + " " +
         py::str(array.dtype()).cast<std::string>();
}

// NumPy reports a failed allocation as MemoryError; the message keeps
// NumPy's words (the size it could not get) and adds the argument's name.
[[noreturn]] void raise_memory_error(const std::string& argument, const std::string& what,
                                     const py::error_already_set& e) {
  const std::string numpy_words = py::str(e.value()).cast<std::string>();
  PyErr_SetString(PyExc_MemoryError, (argument + ": " + what + ": " + numpy_words).c_str());
  throw py::error_already_set();
}

// The one conversion to a C-contiguous T array. pybind11's array_t::ensure
// must not be used: it clears NumPy's error and returns a null array, which
// the next ndim() or data() dereferences (a segfault where the copy could
// not be allocated).
template <class T>
py::array_t<T, py::array::c_style> contiguous(const py::array& array, const std::string& argument) {
  try {
    return py::array_t<T, py::array::c_style>(array);
  } catch (py::error_already_set& e) {
    if (e.matches(PyExc_MemoryError)) {
      raise_memory_error(argument,
                         "cannot allocate the contiguous " + py::str(py::dtype::of<T>()).cast<std::string>() +
                             " copy of the " + array_text(array) + " array",
                         e);
    }
    throw;
  }
}

}  // namespace

py::array as_array(const py::handle& obj, const std::string& argument) {
  try {
    return py::module_::import("numpy").attr("asarray")(obj);
  } catch (py::error_already_set& e) {
    if (e.matches(PyExc_MemoryError)) raise_memory_error(argument, "cannot allocate an array of it", e);
    throw py::type_error(argument + ": expected an array of numbers: " + e.what());
  }
}

py::array_t<double, py::array::c_style> as_float64(const py::handle& obj, const std::string& argument) {
  const py::array array = as_array(obj, argument);
  const char kind = array.dtype().kind();
  // 'b' is bool: True as 1.0 m is a caller's slip, not a measurement.
  if (kind != 'f' && kind != 'i' && kind != 'u') {
    throw py::type_error(argument + ": expected an array of numbers, got dtype " +
                         py::str(array.dtype()).cast<std::string>());
  }
  return contiguous<double>(array, argument);
}

py::array_t<std::uint8_t, py::array::c_style> as_contiguous_uint8(const py::array& array, const std::string& argument) {
  return contiguous<std::uint8_t>(array, argument);
}

std::string element_name(const std::string& argument, long long index) {
  return ArgumentName{argument.c_str()}.element(index);
}

// The shortest text that reads back as `value`, as Python's repr: a user
// who wrote 0.2 reads 0.2, not 0.20000000000000001.
std::string number_text(double value) {
  char text[64];
  for (int digits = 6; digits < 17; ++digits) {
    std::snprintf(text, sizeof text, "%.*g", digits, value);
    if (std::strtod(text, nullptr) == value || std::isnan(value)) return text;
  }
  std::snprintf(text, sizeof text, "%.17g", value);
  return text;
}

double finite_number(double value, const std::string& argument) {
  return finite_value(value, {argument.c_str()});
}

TrunkPose pose_from_values(const double* v, std::size_t count, double reference_elevation_m, double height_change_m,
                           const std::string& argument) {
  return pose_of_values(v, count, reference_elevation_m, height_change_m, {argument.c_str()});
}

namespace {

std::string tilt_text(const char* field, double value_rad) {
  char text[128];
  std::snprintf(text, sizeof text, "%s %g (%.1f deg)", field, value_rad, value_rad * 180.0 / 3.14159265358979323846);
  return text;
}

// "roll_rad 30 (1718.9 deg)", "... and pitch_rad ...", or empty when both
// are plausible.
std::string implausible_tilts(double roll_rad, double pitch_rad) {
  std::string text;
  if (std::abs(roll_rad) > kImplausibleTiltRad) text = tilt_text("roll_rad", roll_rad);
  if (std::abs(pitch_rad) > kImplausibleTiltRad) text += (text.empty() ? "" : " and ") + tilt_text("pitch_rad", pitch_rad);
  return text;
}

void warn(const std::string& message) {
  // An error when the caller's warning filter says so: then it propagates.
  if (PyErr_WarnEx(PyExc_UserWarning, message.c_str(), 1) != 0) throw py::error_already_set();
}

const char* const kRadiansHint = "; poses take radians: degrees passed by mistake?";

}  // namespace

void warn_implausible_tilt(const TrunkPose& pose, const std::string& argument) {
  const std::string tilts = implausible_tilts(pose.roll_rad, pose.pitch_rad);
  if (!tilts.empty()) warn(argument + ": roll or pitch beyond 60 deg: " + tilts + kRadiansHint);
}

void warn_implausible_tilts(const py::array_t<double, py::array::c_style>& poses, const std::string& argument) {
  // Roll and pitch are the last but one pair in either layout.
  const py::ssize_t roll = poses.shape(1) == 6 ? 3 : 2;
  std::size_t count = 0;
  std::string first;
  for (py::ssize_t k = 0; k < poses.shape(0); ++k) {
    const std::string tilts = implausible_tilts(poses.at(k, roll), poses.at(k, roll + 1));
    if (tilts.empty()) continue;
    if (count++ == 0) first = element_name(argument, k) + ": " + tilts;
  }
  if (count == 0) return;
  warn(argument + ": " + std::to_string(count) + " of " + std::to_string(poses.shape(0)) +
       " poses tilt beyond 60 deg in roll or pitch, the first " + first + kRadiansHint);
}

TrunkPose pose_from_object(const py::handle& pose, double reference_elevation_m, double height_change_m,
                           const std::string& argument) {
  const auto values = as_float64(pose, argument);
  if (values.ndim() != 1) {
    raise_input_error(argument + ": expected one pose (a sequence of 5 or 6 numbers), got an array of " +
                      std::to_string(values.ndim()) + " dimensions");
  }
  const TrunkPose p = pose_from_values(values.data(), static_cast<std::size_t>(values.shape(0)), reference_elevation_m,
                                       height_change_m, argument);
  warn_implausible_tilt(p, argument);
  return p;
}

}  // namespace stridemap::python
