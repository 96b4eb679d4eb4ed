#include "stridemap/io/scene_yaml.hpp"

#include <algorithm>
#include <cerrno>
#include <charconv>
#include <cstdint>
#include <cstring>
#include <fstream>
#include <initializer_list>
#include <map>
#include <optional>
#include <sstream>
#include <string>
#include <vector>

#include <yaml-cpp/yaml.h>

#include "stridemap/core/error.hpp"

namespace stridemap {
namespace {

std::string describe(const YAML::Node& node) {
  if (node.IsNull()) return "nothing";
  if (node.IsSequence()) return "a list";
  if (node.IsMap()) return "a map";
  return "\"" + node.Scalar() + "\"";
}

int line_of(const YAML::Node& node) { return node.Mark().line + 1; }

std::string join(const std::string& path, const std::string& field) { return path.empty() ? field : path + "." + field; }

std::string list_of(std::initializer_list<const char*> names) {
  std::string text;
  for (const char* name : names) text += (text.empty() ? "" : ", ") + std::string(name);
  return text;
}

struct Field {
  YAML::Node key, value;
};

// Reads one scene document. Remembers the line of every field path it
// reads, so that problems found later on the finished Scene (by the rules
// in sim/, shared with scenes built in code) point at the right line.
class SceneReader {
 public:
  explicit SceneReader(std::string source) : source_(std::move(source)) {}

  Scene read(const YAML::Node& root) {
    if (!root.IsMap()) {
      fail(root, "", "expected a scene (a map with terrain, boxes, cylinders, cart_rail), got " + describe(root));
    }
    const auto fields = read_map(root, "", {"terrain", "boxes", "cylinders", "cart_rail"});
    Scene scene;
    const auto terrain = fields.find("terrain");
    if (terrain == fields.end()) fail(root, "terrain", "required section is missing");
    scene.terrain = read_terrain(terrain->second.value);
    if (const auto it = fields.find("boxes"); it != fields.end()) {
      for_each_item(it->second.value, "boxes", [&](const YAML::Node& item, const std::string& path) {
        scene.boxes.push_back(read_box(item, path));
      });
    }
    if (const auto it = fields.find("cylinders"); it != fields.end()) {
      for_each_item(it->second.value, "cylinders", [&](const YAML::Node& item, const std::string& path) {
        scene.cylinders.push_back(read_cylinder(item, path));
      });
    }
    if (const auto it = fields.find("cart_rail"); it != fields.end()) scene.cart_rail = read_rail(it->second.value);
    if (auto problem = scene.first_problem()) fail_at(problem->field_path, problem->message);
    return scene;
  }

 private:
  using Fields = std::map<std::string, Field>;

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
                  std::initializer_list<const char*> other_kind = {}) {
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
      if (is_one_of(other_kind)) fail(key, field_path, "only allowed with kind: procedural");
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

  void read_extent(const Fields& fields, const std::string& path, double& min_x, double& min_y, double& max_x,
                   double& max_y) {
    const Field* extent = find(fields, "extent");
    if (!extent) return;
    const std::string extent_path = join(path, "extent");
    const auto sub = read_map(extent->value, extent_path, {"min_x_m", "min_y_m", "max_x_m", "max_y_m"});
    min_x = number(sub, extent->value, extent_path, "min_x_m");
    min_y = number(sub, extent->value, extent_path, "min_y_m");
    max_x = number(sub, extent->value, extent_path, "max_x_m");
    max_y = number(sub, extent->value, extent_path, "max_y_m");
  }

  HeightField read_terrain(const YAML::Node& node) {
    const std::string path = "terrain";
    if (!node.IsMap()) fail(node, path, "expected a map of fields, got " + describe(node));
    const YAML::Node kind_node = node["kind"];
    if (!kind_node) fail(node, "terrain.kind", "required field is missing (flat or procedural)");
    const std::string kind = kind_node.IsScalar() ? kind_node.Scalar() : "";
    if (kind == "flat") {
      const auto fields = read_map(node, path, {"kind", "extent", "base_elevation_m", "reflectance"},
                                   {"seed", "amplitude_m", "wavelength_m", "resolution_m", "octaves"});
      HeightField terrain;
      read_extent(fields, path, terrain.min_x_m, terrain.min_y_m, terrain.max_x_m, terrain.max_y_m);
      terrain.base_elevation_m = number(fields, node, path, "base_elevation_m", 0.0);
      terrain.reflectance = number(fields, node, path, "reflectance", 0.5);
      return terrain;
    }
    if (kind != "procedural") fail(kind_node, "terrain.kind", "expected flat or procedural, got " + describe(kind_node));
    const auto fields = read_map(node, path, {"kind", "extent", "base_elevation_m", "reflectance", "seed",
                                              "amplitude_m", "wavelength_m", "resolution_m", "octaves"});
    ProceduralTerrainOptions options;
    read_extent(fields, path, options.min_x_m, options.min_y_m, options.max_x_m, options.max_y_m);
    options.base_elevation_m = number(fields, node, path, "base_elevation_m", 0.0);
    options.reflectance = number(fields, node, path, "reflectance", 0.5);
    options.amplitude_m = number(fields, node, path, "amplitude_m");
    options.wavelength_m = number(fields, node, path, "wavelength_m");
    options.resolution_m = number(fields, node, path, "resolution_m", options.resolution_m);
    const std::uint64_t octaves = whole_number(fields, node, path, "octaves", static_cast<std::uint64_t>(options.octaves));
    if (octaves < 1 || octaves > 8) {
      fail_at(join(path, "octaves"), "expected a whole number from 1 to 8, got " + std::to_string(octaves));
    }
    options.octaves = static_cast<int>(octaves);
    const std::uint64_t seed = whole_number(fields, node, path, "seed");
    if (auto problem = options.first_problem()) fail_at(join(path, problem->field_path), problem->message);
    return make_procedural_height_field(options, seed);
  }

  BoxObject read_box(const YAML::Node& node, const std::string& path) {
    const auto fields = read_map(node, path, {"name", "center_x_m", "center_y_m", "base_elevation_m", "length_m",
                                              "width_m", "height_m", "yaw_rad", "reflectance"});
    BoxObject box;
    box.name = text(fields, node, path, "name");
    box.center_x_m = number(fields, node, path, "center_x_m");
    box.center_y_m = number(fields, node, path, "center_y_m");
    box.base_elevation_m = number(fields, node, path, "base_elevation_m", 0.0);
    box.length_m = number(fields, node, path, "length_m");
    box.width_m = number(fields, node, path, "width_m");
    box.height_m = number(fields, node, path, "height_m");
    box.yaw_rad = number(fields, node, path, "yaw_rad", 0.0);
    box.reflectance = number(fields, node, path, "reflectance", 0.5);
    return box;
  }

  CylinderObject read_cylinder(const YAML::Node& node, const std::string& path) {
    const auto fields = read_map(node, path, {"name", "center_x_m", "center_y_m", "base_elevation_m", "radius_m",
                                              "height_m", "reflectance"});
    CylinderObject cylinder;
    cylinder.name = text(fields, node, path, "name");
    cylinder.center_x_m = number(fields, node, path, "center_x_m");
    cylinder.center_y_m = number(fields, node, path, "center_y_m");
    cylinder.base_elevation_m = number(fields, node, path, "base_elevation_m", 0.0);
    cylinder.radius_m = number(fields, node, path, "radius_m");
    cylinder.height_m = number(fields, node, path, "height_m");
    cylinder.reflectance = number(fields, node, path, "reflectance", 0.5);
    return cylinder;
  }

  CartRailPath read_rail(const YAML::Node& node) {
    const std::string path = "cart_rail";
    const auto fields = read_map(node, path, {"start_x_m", "end_x_m", "y_m", "step_m", "yaw_rad"});
    CartRailPath rail;
    rail.start_x_m = number(fields, node, path, "start_x_m");
    rail.end_x_m = number(fields, node, path, "end_x_m");
    rail.y_m = number(fields, node, path, "y_m", 0.0);
    rail.step_m = number(fields, node, path, "step_m");
    rail.yaw_rad = number(fields, node, path, "yaw_rad", 0.0);
    return rail;
  }

  std::string source_;
  std::map<std::string, int> lines_;
};

}  // namespace

Scene parse_scene_yaml(const std::string& text, const std::string& source_name) {
  std::vector<YAML::Node> documents;
  try {
    documents = YAML::LoadAll(text);
  } catch (const YAML::Exception& error) {
    throw InputError(source_name + ":" + std::to_string(std::max(1, error.mark.line + 1)) + ": not valid YAML: " + error.msg);
  }
  if (documents.size() > 1) {
    throw InputError(source_name + ":" + std::to_string(std::max(1, documents[1].Mark().line + 1)) +
                     ": expected one YAML document, found " + std::to_string(documents.size()));
  }
  return SceneReader(source_name).read(documents.empty() ? YAML::Node() : documents.front());
}

Scene load_scene_yaml(const std::string& path) {
  std::ifstream file(path, std::ios::binary);
  if (!file) throw InputError(path + ": cannot read scene file: " + std::strerror(errno));
  std::ostringstream contents;
  contents << file.rdbuf();
  if (file.bad()) throw InputError(path + ": cannot read scene file: " + std::strerror(errno));
  return parse_scene_yaml(contents.str(), path);
}

}  // namespace stridemap
