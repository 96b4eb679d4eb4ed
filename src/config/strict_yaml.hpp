#pragma once
// Internal to the config layer (not installed): strict reading of YAML files for
// scenes and configurations. Unknown or repeated keys, wrong types and
// missing fields are errors that name the file, the line and the field path
// ("scene.yaml:12: boxes[1].length_m: expected a number, got \"abc\""), so
// that a typo never passes silently.
#include <charconv>
#include <cstdint>
#include <initializer_list>
#include <map>
#include <optional>
#include <string>

#include <yaml-cpp/yaml.h>

#include "stridemap/core/error.hpp"

namespace stridemap::io_detail {

inline std::string describe(const YAML::Node& node) {
  if (node.IsNull()) return "nothing";
  if (node.IsSequence()) return "a list";
  if (node.IsMap()) return "a map";
  return "\"" + node.Scalar() + "\"";
}

inline int line_of(const YAML::Node& node) { return node.Mark().line + 1; }

inline std::string join(const std::string& path, const std::string& field) { return path.empty() ? field : path + "." + field; }

inline std::string list_of(std::initializer_list<const char*> names) {
  std::string text;
  for (const char* name : names) text += (text.empty() ? "" : ", ") + std::string(name);
  return text;
}

struct Field {
  YAML::Node key, value;
};

using Fields = std::map<std::string, Field>;

// Remembers the line of every field path it reads, so that problems found
// later on the finished object point at the right line.
class StrictYamlReader {
 public:
  explicit StrictYamlReader(std::string source) : source_(std::move(source)) {}


  [[noreturn]] void fail_line(int line, const std::string& path, const std::string& what) const {
    throw InputError(source_ + ":" + std::to_string(line) + ": " + (path.empty() ? "" : path + ": ") + what);
  }
  [[noreturn]] void fail(const YAML::Node& node, const std::string& path, const std::string& what) const {
    fail_line(std::max(1, line_of(node)), path, what);
  }
  // A problem found on the finished scene: the line of the field itself, or
  // of the nearest enclosing field that came from the file.
  [[noreturn]] void fail_at(const std::string& path, const std::string& what) const {
    for (std::string prefix = path; !prefix.empty();) {
      if (const auto it = lines_.find(prefix); it != lines_.end()) fail_line(it->second, path, what);
      const auto cut = prefix.find_last_of(".[");
      prefix = cut == std::string::npos ? "" : prefix.substr(0, cut);
    }
    fail_line(1, path, what);
  }

  Fields read_map(const YAML::Node& node, const std::string& path, std::initializer_list<const char*> allowed,
                  std::initializer_list<const char*> other_kind = {}, const std::string& other_kind_message = "") {
    if (!node.IsMap()) fail(node, path, "expected a map of fields, got " + describe(node));
    lines_[path] = line_of(node);
    Fields fields;
    for (const auto& entry : node) {
      const YAML::Node& key = entry.first;
      if (!key.IsScalar()) fail(key, path, "expected field names, got " + describe(key));
      const std::string name = key.Scalar();
      const std::string field_path = join(path, name);
      const auto is_one_of = [&](std::initializer_list<const char*> names) {
        for (const char* candidate : names) {
          if (name == candidate) return true;
        }
        return false;
      };
      if (is_one_of(other_kind)) fail(key, field_path, other_kind_message);
      if (!is_one_of(allowed)) fail(key, field_path, "unknown field (expected one of: " + list_of(allowed) + ")");
      if (const auto previous = fields.find(name); previous != fields.end()) {
        fail(key, field_path, "appears twice (first on line " + std::to_string(line_of(previous->second.key)) + ")");
      }
      fields.emplace(name, Field{key, entry.second});
      lines_[field_path] = line_of(entry.second.IsNull() ? key : entry.second);
    }
    return fields;
  }

  const Field* find(const Fields& fields, const char* name) const {
    const auto it = fields.find(name);
    return it == fields.end() ? nullptr : &it->second;
  }

  double number(const Fields& fields, const YAML::Node& parent, const std::string& path, const char* name,
                std::optional<double> default_value = std::nullopt) const {
    const Field* field = find(fields, name);
    if (!field) {
      if (default_value) return *default_value;
      fail(parent, join(path, name), "required field is missing");
    }
    const YAML::Node& value = field->value;
    const std::string field_path = join(path, name);
    if (!value.IsScalar()) fail(field->value.IsNull() ? field->key : value, field_path, "expected a number, got " + describe(value));
    if (value.Tag() == "!") fail(value, field_path, "expected a number, got the quoted text " + describe(value));
    try {
      return value.as<double>();
    } catch (const YAML::Exception&) {
      fail(value, field_path, "expected a number, got " + describe(value));
    }
  }

  std::uint64_t whole_number(const Fields& fields, const YAML::Node& parent, const std::string& path,
                             const char* name, std::optional<std::uint64_t> default_value = std::nullopt) const {
    const Field* field = find(fields, name);
    const std::string field_path = join(path, name);
    if (!field) {
      if (default_value) return *default_value;
      fail(parent, field_path, "required field is missing");
    }
    const YAML::Node& value = field->value;
    std::uint64_t result = 0;
    if (value.IsScalar() && value.Tag() != "!") {
      const std::string& text = value.Scalar();
      const auto [end, error] = std::from_chars(text.data(), text.data() + text.size(), result);
      if (error == std::errc() && end == text.data() + text.size()) return result;
    }
    fail(value.IsNull() ? field->key : value, field_path, "expected a whole number >= 0, got " + describe(value));
  }

  std::string text(const Fields& fields, const YAML::Node& parent, const std::string& path, const char* name) const {
    const Field* field = find(fields, name);
    const std::string field_path = join(path, name);
    if (!field) fail(parent, field_path, "required field is missing");
    if (!field->value.IsScalar()) {
      fail(field->value.IsNull() ? field->key : field->value, field_path, "expected a text, got " + describe(field->value));
    }
    return field->value.Scalar();
  }

  template <typename Visit>
  void for_each_item(const YAML::Node& node, const std::string& path, Visit&& visit) {
    if (node.IsNull()) return;  // "boxes:" with nothing under it: no boxes
    if (!node.IsSequence()) fail(node, path, "expected a list, got " + describe(node));
    std::size_t index = 0;
    for (const auto& item : node) {
      const std::string item_path = path + "[" + std::to_string(index++) + "]";
      lines_[item_path] = line_of(item);
      visit(item, item_path);
    }
  }

  bool boolean(const Fields& fields, const YAML::Node& parent, const std::string& path, const char* name,
               std::optional<bool> default_value = std::nullopt) const {
    const Field* field = find(fields, name);
    const std::string field_path = join(path, name);
    if (!field) {
      if (default_value) return *default_value;
      fail(parent, field_path, "required field is missing");
    }
    const YAML::Node& value = field->value;
    if (value.IsScalar() && value.Tag() != "!") {
      if (value.Scalar() == "true") return true;
      if (value.Scalar() == "false") return false;
    }
    fail(value.IsNull() ? field->key : value, field_path, "expected true or false, got " + describe(value));
  }

 protected:
  std::string source_;
  std::map<std::string, int> lines_;
};

/// The one YAML document of a file's text; errors name the source and line.
YAML::Node load_single_document(const std::string& text, const std::string& source_name);
/// The whole file; `what` names it in errors ("scene file").
std::string read_text_file(const std::string& path, const std::string& what);

}  // namespace stridemap::io_detail
