// The module stridemap._stridemap (docs/python.md); stridemap/__init__.py
// re-exports it. The library's InputError and GridSizeError become Python
// exceptions with the same message text.
#include "bindings.hpp"
#include "stridemap/core/error.hpp"
#include "stridemap/core/grid_map.hpp"

namespace stridemap::python {

void register_errors(py::module_& m) {
  // A ValueError, so that code catching bad values catches these too.
  static py::exception<InputError> input_error(m, "InputError", PyExc_ValueError);
  input_error.doc() = "Bad input (files, configs, scans, poses, arguments): the message names the input, the place "
                      "and what is wrong, as the library and CLI word it. A ValueError.";
  // Registered after InputError, so tried first: the more specific type wins.
  static py::exception<GridSizeError> grid_size_error(m, "GridSizeError", input_error.ptr());
  grid_size_error.doc() = "A map grid too large for memory or a cell size out of range. An InputError.";
  py::register_exception_translator([](std::exception_ptr p) {
    try {
      if (p) std::rethrow_exception(p);
    } catch (const GridSizeError& e) {
      PyErr_SetString(grid_size_error.ptr(), e.what());
    } catch (const InputError& e) {
      PyErr_SetString(input_error.ptr(), e.what());
    }
  });
}

}  // namespace stridemap::python

PYBIND11_MODULE(_stridemap, m) {
  namespace sp = stridemap::python;
  m.doc() = "stridemap: terrain elevation maps for walking robots from a tilted 2D laser scanner or a "
            "structured-light sensor (docs/python.md).";
  m.attr("__version__") = STRIDEMAP_PYTHON_VERSION;
  sp::register_errors(m);
  sp::register_options(m);
  sp::register_map(m);
  sp::register_pipeline(m);
  sp::register_simulation(m);
  sp::register_experiments(m);
}
