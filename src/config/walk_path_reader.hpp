#pragma once
// Internal to the config layer: the `walk_path:` section, shared by scene files
// and path files (schema: docs/walking.md).
#include <numbers>
#include <string>

#include "stridemap/sim/walk_path.hpp"
#include "strict_yaml.hpp"

namespace stridemap::io_detail {

inline WalkPath read_walk_path(StrictYamlReader& reader, const YAML::Node& node, const std::string& path) {
  constexpr double deg = std::numbers::pi / 180.0;
  const auto fields = reader.read_map(node, path, {"start", "segments"});
  WalkPath walk;
  if (const Field* start = reader.find(fields, "start")) {
    const std::string at = join(path, "start");
    const auto sub = reader.read_map(start->value, at, {"x_m", "y_m", "yaw_deg"});
    walk.start_x_m = reader.number(sub, start->value, at, "x_m");
    walk.start_y_m = reader.number(sub, start->value, at, "y_m");
    walk.start_yaw_rad = reader.number(sub, start->value, at, "yaw_deg", 0.0) * deg;
  }
  const Field* segments = reader.find(fields, "segments");
  if (!segments) reader.fail(node, join(path, "segments"), "required field is missing");
  reader.for_each_item(segments->value, join(path, "segments"), [&](const YAML::Node& item, const std::string& at) {
    const auto sub = reader.read_map(item, at, {"straight_m", "turn_deg", "radius_m"});
    const bool straight = reader.find(sub, "straight_m") != nullptr;
    const bool turn = reader.find(sub, "turn_deg") != nullptr;
    if (straight == turn) reader.fail(item, at, "expected exactly one of straight_m and turn_deg");
    WalkSegment segment;
    if (straight) {
      if (reader.find(sub, "radius_m")) reader.fail(item, join(at, "radius_m"), "only allowed with turn_deg");
      segment.kind = WalkSegment::Kind::straight;
      segment.length_m = reader.number(sub, item, at, "straight_m");
    } else {
      segment.kind = WalkSegment::Kind::turn;
      segment.turn_rad = reader.number(sub, item, at, "turn_deg") * deg;
      segment.radius_m = reader.number(sub, item, at, "radius_m", 0.0);
    }
    walk.segments.push_back(segment);
  });
  return walk;
}

}  // namespace stridemap::io_detail
