// Fields of an option class are its settable properties (def_readwrite and
// def_property both make a Python property with a setter); read-only ones
// (UrgParameters.beam_count) are derived and neither set nor shown.
#include "option_fields.hpp"

#include <string>
#include <vector>

namespace stridemap::python {
namespace {

std::string type_name(const py::handle value) {
  return py::str(py::type::handle_of(value).attr("__name__")).cast<std::string>();
}

std::vector<std::string> field_names(const py::handle cls) {
  std::vector<std::string> names;
  const py::dict members = cls.attr("__dict__").attr("copy")();
  for (const auto& [name, member] : members) {
    if (py::isinstance(member, py::module_::import("builtins").attr("property")) && !member.attr("fset").is_none()) {
      names.push_back(name.cast<std::string>());
    }
  }
  return names;
}

std::string joined(const std::vector<std::string>& names) {
  std::string text;
  for (const std::string& name : names) text += (text.empty() ? "" : ", ") + name;
  return text;
}

// pybind11 converts what it can (True to 1, 1 to True): a flag given as a
// count, or a count as a flag, is a caller's slip, so the kind of the
// field's default decides. Other fields (nested options) take their own
// class.
bool fits(const py::handle current, const py::handle value) {
  const py::module_ numbers = py::module_::import("numbers");
  const bool is_bool = py::isinstance<py::bool_>(value) || type_name(value) == "bool_";
  if (py::isinstance<py::bool_>(current)) return is_bool;
  if (is_bool) return false;
  if (py::isinstance<py::int_>(current)) return py::isinstance(value, numbers.attr("Integral"));
  if (py::isinstance<py::float_>(current)) return py::isinstance(value, numbers.attr("Real"));
  if (py::isinstance<py::str>(current)) return py::isinstance<py::str>(value);
  return py::isinstance(value, py::type::handle_of(current));
}

void set_field(py::handle instance, const std::string& class_name, const std::string& name, const py::handle value) {
  const py::object current = instance.attr(name.c_str());
  if (!fits(current, value)) {
    throw py::type_error(class_name + "." + name + ": expected " + type_name(current) + ", got " + type_name(value) +
                         " (" + py::repr(value).cast<std::string>() + ")");
  }
  try {
    instance.attr(name.c_str()) = value;
  } catch (py::error_already_set& e) {
    // The setter's own words (the library's "'foo' is not a sensor; use
    // ...") do not say which field they are about.
    const std::string message = class_name + "." + name + ": " + py::str(e.value()).cast<std::string>();
    PyErr_SetString(e.type().ptr(), message.c_str());
    throw py::error_already_set();
  }
}

}  // namespace

void set_fields(py::handle instance, const py::args& args, const py::kwargs& kwargs, bool positional) {
  const py::handle cls = py::type::handle_of(instance);
  const std::string class_name = py::str(cls.attr("__name__")).cast<std::string>();
  const std::vector<std::string> names = field_names(cls);
  if (!positional && !args.empty()) {
    throw py::type_error(class_name + "() takes keyword arguments only (its fields: " + joined(names) + "), got " +
                         std::to_string(args.size()) + " positional");
  }
  if (args.size() > names.size()) {
    throw py::type_error(class_name + "() takes at most " + std::to_string(names.size()) + " positional arguments (" +
                         joined(names) + "), got " + std::to_string(args.size()));
  }
  for (std::size_t i = 0; i < args.size(); ++i) set_field(instance, class_name, names[i], args[i]);
  for (const auto& [key, value] : kwargs) {
    const std::string name = key.cast<std::string>();
    bool known = false;
    for (const std::string& field : names) known = known || field == name;
    if (!known) {
      throw py::type_error(class_name + "() got an unknown keyword '" + name + "'; its fields are " + joined(names));
    }
    for (std::size_t i = 0; i < args.size(); ++i) {
      if (names[i] == name) throw py::type_error(class_name + "() got " + name + " both by position and by keyword");
    }
    set_field(instance, class_name, name, value);
  }
}

std::string fields_repr(py::handle instance) {
  const py::handle cls = py::type::handle_of(instance);
  std::string text = py::str(cls.attr("__name__")).cast<std::string>() + "(";
  bool first = true;
  for (const std::string& name : field_names(cls)) {
    text += (first ? "" : ", ") + name + "=" + py::repr(instance.attr(name.c_str())).cast<std::string>();
    first = false;
  }
  return text + ")";
}

}  // namespace stridemap::python
