#include "stridemap_ros/node_parameters.hpp"

#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <sstream>
#include <string_view>

#include <ros/ros.h>

#include "stridemap/core/error.hpp"

namespace stridemap::ros_adapter {
namespace {

std::string type_name(const XmlRpc::XmlRpcValue& value) {
  switch (value.getType()) {
    case XmlRpc::XmlRpcValue::TypeBoolean: return "a boolean";
    case XmlRpc::XmlRpcValue::TypeInt: return "an integer";
    case XmlRpc::XmlRpcValue::TypeDouble: return "a double";
    case XmlRpc::XmlRpcValue::TypeString: return "a string";
    case XmlRpc::XmlRpcValue::TypeArray: return "a list";
    case XmlRpc::XmlRpcValue::TypeStruct: return "a dictionary";
    default: return "of another type";
  }
}

std::string shown(XmlRpc::XmlRpcValue value) {
  std::string text = value.toXml();
  if (value.getType() == XmlRpc::XmlRpcValue::TypeString) text = "'" + static_cast<std::string>(value) + "'";
  if (value.getType() == XmlRpc::XmlRpcValue::TypeInt) text = std::to_string(static_cast<int>(value));
  if (value.getType() == XmlRpc::XmlRpcValue::TypeDouble) {
    std::ostringstream out;
    out << static_cast<double>(value);
    text = out.str();
  }
  return text.size() > 60 ? text.substr(0, 57) + "..." : text;
}

[[noreturn]] void wrong(const std::string& name, const std::string& what) {
  throw InputError("~" + name + ": " + what + " (" + "docs/ros.md lists the parameters; `--help` too)");
}

std::string number_text(double v) {
  std::ostringstream out;
  out << v;
  return out.str();
}

}  // namespace

ServerParameters::ServerParameters(const ros::NodeHandle& private_handle) : handle_(private_handle) {}

std::optional<XmlRpc::XmlRpcValue> ServerParameters::get(const std::string& name) const {
  XmlRpc::XmlRpcValue value;
  if (!handle_.getParam(name, value)) return std::nullopt;
  return value;
}

std::vector<std::string> ServerParameters::names() const {
  std::vector<std::string> all, mine;
  if (!ros::param::getParamNames(all)) return mine;
  const std::string prefix = handle_.getNamespace() + "/";
  for (const std::string& name : all) {
    if (name.compare(0, prefix.size(), prefix) == 0) mine.push_back(name.substr(prefix.size()));
  }
  return mine;
}

std::optional<XmlRpc::XmlRpcValue> TableParameters::get(const std::string& name) const {
  const auto it = values_.find(name);
  if (it == values_.end()) return std::nullopt;
  return it->second;
}

std::vector<std::string> TableParameters::names() const {
  std::vector<std::string> names;
  for (const auto& entry : values_) names.push_back(entry.first);
  return names;
}

std::optional<XmlRpc::XmlRpcValue> ParameterReader::lookup(const std::string& name) const { return source_.get(name); }

std::string ParameterReader::text(const std::string& name, const std::string& fallback, const std::string& help) {
  std::string value = fallback;
  if (auto v = lookup(name)) {
    if (v->getType() != XmlRpc::XmlRpcValue::TypeString) {
      wrong(name, shown(*v) + " is " + type_name(*v) + ", not a string");
    }
    value = static_cast<std::string>(*v);
  }
  declared_.push_back({name, "string", "'" + fallback + "'", help, "'" + value + "'"});
  return value;
}

std::string ParameterReader::path(const std::string& name, const std::string& fallback, const std::string& base,
                                  const std::string& help) {
  std::string value = text(name, fallback, help);
  declared_.back().type = "path";
  if (!value.empty() && std::filesystem::path(value).is_relative()) {
    value = (std::filesystem::path(base) / value).lexically_normal().string();
  }
  declared_.back().value_text = "'" + value + "'";
  return value;
}

double ParameterReader::number(const std::string& name, double fallback, double min, double max,
                               const std::string& help) {
  double value = fallback;
  if (auto v = lookup(name)) {
    if (v->getType() == XmlRpc::XmlRpcValue::TypeInt) {
      value = static_cast<int>(*v);
    } else if (v->getType() == XmlRpc::XmlRpcValue::TypeDouble) {
      value = static_cast<double>(*v);
    } else {
      wrong(name, shown(*v) + " is " + type_name(*v) + ", not a number");
    }
    if (!std::isfinite(value) || value < min || value > max) {
      wrong(name, number_text(value) + " is outside [" + number_text(min) + ", " + number_text(max) + "]");
    }
  }
  declared_.push_back({name, "double", number_text(fallback), help + ", range [" + number_text(min) + ", " + number_text(max) + "]",
                       number_text(value)});
  return value;
}

int ParameterReader::integer(const std::string& name, int fallback, int min, int max, const std::string& help) {
  int value = fallback;
  if (auto v = lookup(name)) {
    if (v->getType() != XmlRpc::XmlRpcValue::TypeInt) wrong(name, shown(*v) + " is " + type_name(*v) + ", not an integer");
    value = static_cast<int>(*v);
    if (value < min || value > max) {
      wrong(name, std::to_string(value) + " is outside [" + std::to_string(min) + ", " + std::to_string(max) + "]");
    }
  }
  declared_.push_back({name, "int", std::to_string(fallback),
                       help + ", range [" + std::to_string(min) + ", " + std::to_string(max) + "]", std::to_string(value)});
  return value;
}

void ParameterReader::refuse_unknown() const {
  std::vector<std::string> unknown;
  for (const std::string& name : source_.names()) {
    // A dictionary parameter arrives as its leaves; none of ours is one.
    const std::string top = name.substr(0, name.find('/'));
    bool known = false;
    for (const DeclaredParameter& p : declared_) known = known || p.name == top;
    if (!known) unknown.push_back("~" + name);
  }
  if (unknown.empty()) return;
  std::string message = unknown.size() == 1 ? "unknown parameter " : "unknown parameters ";
  for (std::size_t k = 0; k < unknown.size(); ++k) message += (k ? ", " : "") + unknown[k];
  message += "; this node reads";
  for (const DeclaredParameter& p : declared_) message += " ~" + p.name;
  throw InputError(message);
}

std::string ParameterReader::summary() const {
  std::string line;
  for (const DeclaredParameter& p : declared_) line += (line.empty() ? "" : " ") + p.name + "=" + p.value_text;
  return line;
}

std::string ParameterReader::help_text() const {
  std::size_t width = 0;
  for (const DeclaredParameter& p : declared_) width = std::max(width, p.name.size() + p.type.size() + 5);
  std::string text;
  for (const DeclaredParameter& p : declared_) {
    std::string head = "  _" + p.name + ":=" + p.type;
    head.resize(std::max(head.size() + 2, width + 4), ' ');
    text += head + p.help + " (default " + p.default_text + ")\n";
  }
  return text;
}

std::string ros_home() {
  if (const char* home = std::getenv("ROS_HOME"); home && *home) return home;
  if (const char* home = std::getenv("HOME"); home && *home) return std::string(home) + "/.ros";
  return ".";
}

bool asks_for_help(int argc, const char* const* argv) {
  for (int k = 1; k < argc; ++k) {
    const std::string_view arg = argv[k];
    if (arg == "-h" || arg == "--help") return true;
  }
  return false;
}

}  // namespace stridemap::ros_adapter
