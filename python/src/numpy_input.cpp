// The checks between NumPy and the library: dtype, shape, finiteness, each
// failure naming the argument as the caller wrote it.
#include <cmath>
#include <string>

#include "bindings.hpp"
#include "stridemap/core/error.hpp"

namespace stridemap::python {

void raise_input_error(const std::string& message) { throw InputError(message); }

py::array_t<double, py::array::c_style> as_float64(const py::handle& obj, const std::string& argument) {
  const py::module_ np = py::module_::import("numpy");
  py::array array;
  try {
    array = np.attr("asarray")(obj);
  } catch (const py::error_already_set& e) {
    throw py::type_error(argument + ": expected an array of numbers: " + e.what());
  }
  const char kind = array.dtype().kind();
  // 'b' is bool: True as 1.0 m is a caller's slip, not a measurement.
  if (kind != 'f' && kind != 'i' && kind != 'u') {
    throw py::type_error(argument + ": expected an array of numbers, got dtype " +
                         py::str(array.dtype()).cast<std::string>());
  }
  return py::array_t<double, py::array::c_style>::ensure(array);
}

std::string element_name(const std::string& argument, long long index) {
  // Appended piece by piece: GCC 12 warns (-Wrestrict, a false positive)
  // about "[" + std::to_string(i) + "]".
  std::string name = argument;
  name += '[';
  name += std::to_string(index);
  name += ']';
  return name;
}

double finite_number(double value, const std::string& argument) {
  if (!std::isfinite(value)) raise_input_error(argument + ": expected a finite number, got " + std::to_string(value));
  return value;
}

TrunkPose pose_from_values(const double* v, std::size_t count, double reference_elevation_m, double height_change_m,
                           const std::string& argument) {
  static const char* const kFive[] = {"x_m", "y_m", "roll_rad", "pitch_rad", "yaw_rad"};
  static const char* const kSix[] = {"x_m", "y_m", "z_m", "roll_rad", "pitch_rad", "yaw_rad"};
  if (count != 5 && count != 6) {
    raise_input_error(argument + ": expected 5 values (x_m, y_m, roll_rad, pitch_rad, yaw_rad) or 6 (x_m, y_m, "
                      "z_m, roll_rad, pitch_rad, yaw_rad), got " + std::to_string(count));
  }
  for (std::size_t i = 0; i < count; ++i) {
    if (!std::isfinite(v[i])) {
      raise_input_error(argument + ": " + (count == 5 ? kFive[i] : kSix[i]) + " is not finite (" +
                        std::to_string(v[i]) + ")");
    }
  }
  TrunkPose pose;
  pose.x_m = v[0];
  pose.y_m = v[1];
  std::size_t k = 2;
  if (count == 6) pose.z_m = v[k++];
  pose.roll_rad = v[k++];
  pose.pitch_rad = v[k++];
  pose.yaw_rad = v[k];
  pose.reference_elevation_m = finite_number(reference_elevation_m, "reference_elevation_m");
  pose.height_change_m = finite_number(height_change_m, "height_change_m");
  return pose;
}

TrunkPose pose_from_object(const py::handle& pose, double reference_elevation_m, double height_change_m,
                           const std::string& argument) {
  const auto values = as_float64(pose, argument);
  if (values.ndim() != 1) {
    raise_input_error(argument + ": expected one pose (a sequence of 5 or 6 numbers), got an array of " +
                      std::to_string(values.ndim()) + " dimensions");
  }
  return pose_from_values(values.data(), static_cast<std::size_t>(values.shape(0)), reference_elevation_m,
                          height_change_m, argument);
}

}  // namespace stridemap::python
