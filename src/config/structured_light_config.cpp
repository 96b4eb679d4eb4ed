#include "stridemap/config/structured_light_config.hpp"

#include <algorithm>
#include <charconv>
#include <cmath>
#include <map>
#include <numbers>
#include <optional>
#include <vector>

#include <yaml-cpp/yaml.h>

#include "stridemap/core/error.hpp"
#include "strict_yaml.hpp"

namespace stridemap {
namespace {

using namespace io_detail;

constexpr double kDegToRadian = std::numbers::pi / 180.0;

// A section of the file: its fields checked against the allowed names by the
// shared strict reader, with the lookups this file needs.
class Section {
 public:
  Section(StrictYamlReader& reader, const YAML::Node& node, std::string path, std::initializer_list<const char*> allowed)
      : reader_(reader), node_(node), path_(std::move(path)), fields_(reader.read_map(node, path_, allowed)) {}

  bool has(const std::string& name) const { return fields_.count(name) != 0; }
  const YAML::Node& node() const { return node_; }
  std::string field_path(const std::string& name) const { return join(path_, name); }
  int line(const std::string& name) const {
    const auto it = fields_.find(name);
    if (it == fields_.end()) return std::max(1, line_of(node_));
    return std::max(1, line_of(it->second.value.IsNull() ? it->second.key : it->second.value));
  }
  double number(const char* name, std::optional<double> default_value = std::nullopt) const {
    return reader_.number(fields_, node_, path_, name, default_value);
  }
  int whole_number(const std::string& name) const {
    const auto it = fields_.find(name);
    if (it == fields_.end()) fail(node_, field_path(name), "required field is missing");
    const YAML::Node& value = it->second.value;
    if (value.IsScalar() && value.Tag() != "!") {
      const std::string& text = value.Scalar();
      long long result = 0;
      const auto [end, error] = std::from_chars(text.data(), text.data() + text.size(), result);
      if (error == std::errc() && end == text.data() + text.size() && result >= 0 && result <= 1000000000) {
        return static_cast<int>(result);
      }
    }
    fail(value.IsNull() ? it->second.key : value, field_path(name),
         "expected a whole number of pixels, got " + describe(value));
  }
  [[noreturn]] void fail(const YAML::Node& where, const std::string& path, const std::string& what) const {
    reader_.fail(where, path, what);
  }

 private:
  StrictYamlReader& reader_;
  YAML::Node node_;
  std::string path_;
  Fields fields_;
};

[[noreturn]] void fail_at(const std::string& source, int line, const std::string& path, const std::string& what) {
  throw InputError(source + ":" + std::to_string(line) + ": " + path + ": " + what);
}

StructuredLightConfig read_config(const YAML::Node& root, const std::string& source) {
  if (!root.IsMap()) {
    throw InputError(source + ":1: expected a structured-light configuration (a map with structured_light, mount, "
                              "errors), got " + describe(root));
  }
  StrictYamlReader reader(source);
  const Section top(reader, root, "", {"structured_light", "mount", "errors"});
  if (!top.has("structured_light")) top.fail(root, "structured_light", "required section is missing");

  StructuredLightConfig config;
  StructuredLightParameters& p = config.parameters;
  // Where each parameter came from, for the checks on the finished set.
  std::map<std::string, std::pair<std::string, int>> origin;
  const auto note = [&origin](const std::string& field, const Section& section, const std::string& name) {
    origin[field] = {section.field_path(name), section.line(name)};
  };

  const Section sensor(reader, root["structured_light"], "structured_light",
                       {"baseline_m", "sheet_angle_deg", "image_width_px", "image_height_px", "half_fov_vertical_deg",
                        "half_fov_horizontal_deg", "focal_length_px"});
  p.baseline_m = sensor.number("baseline_m");
  note("baseline_m", sensor, "baseline_m");
  p.sheet_angle_rad = sensor.number("sheet_angle_deg") * kDegToRadian;
  note("sheet_angle_rad", sensor, "sheet_angle_deg");
  p.image_width_px = sensor.whole_number("image_width_px");
  note("image_width_px", sensor, "image_width_px");
  p.image_height_px = sensor.whole_number("image_height_px");
  note("image_height_px", sensor, "image_height_px");

  const bool by_angle = sensor.has("half_fov_vertical_deg") || sensor.has("half_fov_horizontal_deg");
  if (sensor.has("focal_length_px")) {
    if (by_angle) {
      sensor.fail(sensor.node(), sensor.field_path("focal_length_px"),
                  "give either focal_length_px or half_fov_vertical_deg and half_fov_horizontal_deg, not both");
    }
    // Eq. (2) with one focal length for both image sides.
    const double focal = sensor.number("focal_length_px");
    if (!(std::isfinite(focal) && focal > 0.0)) {
      fail_at(source, sensor.line("focal_length_px"), sensor.field_path("focal_length_px"),
              "must be a positive number of pixels, got " + describe(sensor.node()["focal_length_px"]));
    }
    if (p.image_width_px > 0 && p.image_height_px > 0) {
      p.half_fov_vertical_rad = half_fov_from_focal_length_rad(p.image_height_px, focal);
      p.half_fov_horizontal_rad = half_fov_from_focal_length_rad(p.image_width_px, focal);
    }
    note("half_fov_vertical_rad", sensor, "focal_length_px");
    note("half_fov_horizontal_rad", sensor, "focal_length_px");
  } else {
    if (!by_angle) {
      sensor.fail(sensor.node(), "structured_light",
                  "give the viewing angles (half_fov_vertical_deg and half_fov_horizontal_deg) or focal_length_px");
    }
    p.half_fov_vertical_rad = sensor.number("half_fov_vertical_deg") * kDegToRadian;
    note("half_fov_vertical_rad", sensor, "half_fov_vertical_deg");
    p.half_fov_horizontal_rad = sensor.number("half_fov_horizontal_deg") * kDegToRadian;
    note("half_fov_horizontal_rad", sensor, "half_fov_horizontal_deg");
  }

  if (top.has("mount")) {
    const Section mount(reader, root["mount"], "mount",
                        {"pitch_deg", "height_m", "forward_offset_m", "lateral_offset_m", "roll_deg", "yaw_deg"});
    config.has_mount = true;
    p.mount.pitch_rad = mount.number("pitch_deg") * kDegToRadian;
    note("mount.pitch_rad", mount, "pitch_deg");
    p.mount.height_m = mount.number("height_m");
    note("mount.height_m", mount, "height_m");
    p.mount.forward_offset_m = mount.number("forward_offset_m", 0.0);
    note("mount.forward_offset_m", mount, "forward_offset_m");
    p.mount.lateral_offset_m = mount.number("lateral_offset_m", 0.0);
    note("mount.lateral_offset_m", mount, "lateral_offset_m");
    p.mount.roll_rad = mount.number("roll_deg", 0.0) * kDegToRadian;
    note("mount.roll_rad", mount, "roll_deg");
    p.mount.yaw_rad = mount.number("yaw_deg", 0.0) * kDegToRadian;
    note("mount.yaw_rad", mount, "yaw_deg");
  }

  if (top.has("errors")) {
    const Section errors(reader, root["errors"], "errors",
                         {"baseline_m", "sheet_angle_deg", "half_fov_vertical_deg", "row_px", "column_px"});
    p.baseline_error_m = errors.number("baseline_m", p.baseline_error_m);
    note("baseline_error_m", errors, "baseline_m");
    p.sheet_angle_error_rad = errors.number("sheet_angle_deg", p.sheet_angle_error_rad / kDegToRadian) * kDegToRadian;
    note("sheet_angle_error_rad", errors, "sheet_angle_deg");
    p.half_fov_vertical_error_rad =
        errors.number("half_fov_vertical_deg", p.half_fov_vertical_error_rad / kDegToRadian) * kDegToRadian;
    note("half_fov_vertical_error_rad", errors, "half_fov_vertical_deg");
    p.row_error_px = errors.number("row_px", p.row_error_px);
    note("row_error_px", errors, "row_px");
    p.column_error_px = errors.number("column_px", p.column_error_px);
    note("column_error_px", errors, "column_px");
  }

  if (const auto problem = p.first_problem()) {
    const auto it = origin.find(problem->field);
    if (it == origin.end()) throw InputError(source + ": " + problem->field + ": " + problem->what);
    fail_at(source, it->second.second, it->second.first, problem->what);
  }
  return config;
}

}  // namespace

StructuredLightConfig parse_structured_light_config(const std::string& text, const std::string& source_name) {
  return read_config(load_single_document(text, source_name), source_name);
}

StructuredLightConfig load_structured_light_config(const std::string& path) {
  return parse_structured_light_config(read_text_file(path, "structured-light config"), path);
}

}  // namespace stridemap
