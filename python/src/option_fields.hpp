#pragma once
// Keyword construction and a repr for every option struct bound in Python,
// written once from the class's own properties so that a field added to a
// binding is constructible and shown without touching anything here.
#include "bindings.hpp"

namespace stridemap::python {

/// Sets `instance`'s fields from `kwargs` (and, when `positional`, from
/// `args` in the order the fields were bound). A keyword that is no field
/// is a TypeError naming it and listing the fields; a value of the wrong
/// type a TypeError naming the field; a value a field's setter refuses
/// keeps its exception type with "<Class>.<field>: " in front.
void set_fields(py::handle instance, const py::args& args, const py::kwargs& kwargs, bool positional);

/// "PipelineOptions(sensor='urg', cells_per_side=100, ...)": every settable
/// field with its value's repr, in binding order.
std::string fields_repr(py::handle instance);

/// Gives `cls` __init__(**fields) (also positional fields when
/// `Positional`) and __repr__. Call it after every field is bound.
template <bool Positional = false, class T>
void add_field_init_and_repr(py::class_<T>& cls, const char* init_doc) {
  cls.def(py::init([](const py::args& args, const py::kwargs& kwargs) {
            py::object instance = py::cast(T{});
            set_fields(instance, args, kwargs, Positional);
            return instance.cast<T>();
          }),
          init_doc);
  cls.def("__repr__", [](const py::handle self) { return fields_repr(self); });
}

}  // namespace stridemap::python
