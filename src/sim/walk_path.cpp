#include "stridemap/sim/walk_path.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <numbers>
#include <string>

#include "stridemap/core/error.hpp"

namespace stridemap {
namespace {

constexpr double kRadToDeg = 180.0 / std::numbers::pi;

std::optional<SceneProblem> problem(std::string field, std::string message) {
  return SceneProblem{"walk_path." + std::move(field), "", std::move(message)};
}

std::string segment_path(std::size_t k) { return "segments[" + std::to_string(k) + "]"; }

double segment_track_m(const WalkSegment& s) {
  if (s.kind == WalkSegment::Kind::straight) return s.length_m;
  return s.radius_m * std::abs(s.turn_rad);
}

}  // namespace

PathPoint advance_along(const PathPoint& from, const WalkSegment& segment, double fraction) {
  PathPoint to = from;
  if (segment.kind == WalkSegment::Kind::straight) {
    const double d = segment.length_m * fraction;
    to.x_m += d * std::cos(from.yaw_rad);
    to.y_m += d * std::sin(from.yaw_rad);
    to.distance_m += d;
    return to;
  }
  const double turned = segment.turn_rad * fraction;
  to.yaw_rad = from.yaw_rad + turned;
  to.turned_rad += std::abs(turned);
  if (segment.radius_m > 0.0) {
    // The centre lies on the side the robot turns to; the trunk keeps its
    // distance from it and its heading tangent to the circle.
    const double side = segment.turn_rad > 0.0 ? 1.0 : -1.0;
    const double r = segment.radius_m;
    const double cx = from.x_m - side * r * std::sin(from.yaw_rad);
    const double cy = from.y_m + side * r * std::cos(from.yaw_rad);
    to.x_m = cx + side * r * std::sin(to.yaw_rad);
    to.y_m = cy - side * r * std::cos(to.yaw_rad);
    to.distance_m += r * std::abs(turned);
  }
  return to;
}

std::optional<SceneProblem> walk_path_problem(const WalkPath& path) {
  using namespace scene_rules;
  if (auto m = finite(path.start_x_m)) return problem("start.x_m", *m);
  if (auto m = finite(path.start_y_m)) return problem("start.y_m", *m);
  if (auto m = finite(path.start_yaw_rad)) return problem("start.yaw_deg", *m);
  if (path.segments.empty()) return problem("segments", "expected at least one segment (straight_m or turn_deg)");
  double track = 0.0, turned = 0.0;
  for (std::size_t k = 0; k < path.segments.size(); ++k) {
    const WalkSegment& s = path.segments[k];
    const std::string at = segment_path(k);
    if (s.kind == WalkSegment::Kind::straight) {
      if (auto m = positive(s.length_m)) return problem(at + ".straight_m", *m);
    } else {
      const double deg = s.turn_rad * kRadToDeg;
      if (!std::isfinite(s.turn_rad) || s.turn_rad == 0.0 || std::abs(deg) > 720.0) {
        return problem(at + ".turn_deg", "expected a non-zero turn of at most 720 degrees either way, got " +
                                             format_number(deg));
      }
      if (auto m = non_negative(s.radius_m)) return problem(at + ".radius_m", *m);
    }
    track += segment_track_m(s);
    turned += std::abs(s.turn_rad);
    if (track > max_walk_path_length_m || turned > 2.0 * std::numbers::pi * 1e4) {
      return problem(at, "the path is longer than the limit of " + format_number(max_walk_path_length_m) +
                             " m of track or 10000 turns");
    }
  }
  return std::nullopt;
}

std::vector<PathPoint> sample_walk_path(const WalkPath& path, double spacing_m, double spacing_rad) {
  if (auto p = walk_path_problem(path)) throw InputError(p->field_path + ": " + p->message);
  if (!(spacing_m > 0.0) || !(spacing_rad > 0.0)) throw InputError("sample_walk_path: spacings must be positive");
  std::vector<PathPoint> points;
  PathPoint at{path.start_x_m, path.start_y_m, path.start_yaw_rad, 0.0, 0.0};
  points.push_back(at);
  for (const WalkSegment& s : path.segments) {
    const double pieces = std::max(segment_track_m(s) / spacing_m, std::abs(s.turn_rad) / spacing_rad);
    const auto n = static_cast<std::size_t>(std::max(1.0, std::ceil(pieces)));
    for (std::size_t i = 1; i <= n; ++i) points.push_back(advance_along(at, s, static_cast<double>(i) / static_cast<double>(n)));
    at = points.back();
  }
  return points;
}

std::optional<SceneProblem> walk_path_extent_problem(const WalkPath& path, const HeightField& terrain) {
  if (auto p = walk_path_problem(path)) return p;
  PathPoint at{path.start_x_m, path.start_y_m, path.start_yaw_rad, 0.0, 0.0};
  const auto outside = [&](const PathPoint& p) { return !terrain.in_extent(p.x_m, p.y_m); };
  const std::string extent = "x " + scene_rules::format_number(terrain.min_x_m) + ".." +
                             scene_rules::format_number(terrain.max_x_m) + " m, y " +
                             scene_rules::format_number(terrain.min_y_m) + ".." +
                             scene_rules::format_number(terrain.max_y_m) + " m";
  if (outside(at)) {
    return problem("start", "the start (" + scene_rules::format_number(at.x_m) + ", " +
                                scene_rules::format_number(at.y_m) + ") lies outside the scene's terrain extent (" +
                                extent + ")");
  }
  for (std::size_t k = 0; k < path.segments.size(); ++k) {
    const WalkSegment& s = path.segments[k];
    const double pieces = std::max(segment_track_m(s) / 0.01, std::abs(s.turn_rad) / 0.01);
    const auto n = static_cast<std::size_t>(std::max(1.0, std::ceil(pieces)));
    for (std::size_t i = 1; i <= n; ++i) {
      const PathPoint p = advance_along(at, s, static_cast<double>(i) / static_cast<double>(n));
      if (outside(p)) {
        char where[96];
        std::snprintf(where, sizeof where, "(%.3f, %.3f)", p.x_m, p.y_m);
        return problem(segment_path(k), std::string("the path leaves the scene's terrain extent (") + extent +
                                            ") at " + where);
      }
    }
    at = advance_along(at, s, 1.0);
  }
  return std::nullopt;
}

}  // namespace stridemap
