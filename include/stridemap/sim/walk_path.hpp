#pragma once
// The route a walking robot's trunk follows over a scene: a start pose and
// a list of straight segments and turns (in place or on an arc). Read from a
// scene file's `walk_path:` section or from a file of its own
// (config/walk_path_yaml.hpp; schema in docs/walking.md). The gait that carries
// the trunk along it is sim/trunk_motion.hpp.
#include <cstdint>
#include <optional>
#include <vector>

#include "stridemap/sim/height_field.hpp"
#include "stridemap/sim/scene_problem.hpp"

namespace stridemap {

struct WalkSegment {
  enum class Kind : std::uint8_t {
    straight,  ///< walk length_m ahead
    turn,      ///< change the heading by turn_rad, in place or on an arc
  };
  Kind kind = Kind::straight;
  double length_m = 0.0;  ///< straight: distance walked, > 0 [m]
  /// turn: heading change, counter-clockwise positive, non-zero, at most
  /// two full turns either way [rad].
  double turn_rad = 0.0;
  /// turn: 0 turns in place; > 0 walks an arc of this radius (of the trunk
  /// reference point's track) [m].
  double radius_m = 0.0;
};

struct WalkPath {
  double start_x_m = 0.0;  ///< trunk reference point at the start [m]
  double start_y_m = 0.0;
  double start_yaw_rad = 0.0;  ///< heading at the start, 0 = +X [rad]
  std::vector<WalkSegment> segments;
};

/// The trunk's place on the path: position, heading, and how far it has
/// come (distance along its track and heading turned, both as magnitudes).
struct PathPoint {
  double x_m = 0.0, y_m = 0.0, yaw_rad = 0.0;
  double distance_m = 0.0;
  double turned_rad = 0.0;
};

/// Where the end of `segment` leaves a trunk that starts at `from`;
/// `fraction` in [0, 1] gives points inside the segment.
PathPoint advance_along(const PathPoint& from, const WalkSegment& segment, double fraction);

/// Longest path accepted: 100 km of track or 10,000 full turns, beyond
/// which a number is a typo rather than an experiment.
inline constexpr double max_walk_path_length_m = 1.0e5;

/// The first problem of the path itself (non-finite start, no segments, a
/// straight of zero length, a turn of zero, a negative radius, ...), with
/// field paths as the file spells them ("walk_path.segments[2].turn_deg"):
/// angles are degrees in files, so messages state them in degrees.
std::optional<SceneProblem> walk_path_problem(const WalkPath& path);

/// Whether the trunk reference point stays inside the terrain's extent (the
/// area the scene describes) all along the path; the field path names the
/// first segment that leaves it, the message the point where it does.
std::optional<SceneProblem> walk_path_extent_problem(const WalkPath& path, const HeightField& terrain);

/// Points every `spacing_m` of track and every `spacing_rad` of turning,
/// both ends of every segment included (for drawing the path and for the
/// extent check). Throws InputError for a path with a problem.
std::vector<PathPoint> sample_walk_path(const WalkPath& path, double spacing_m = 0.01, double spacing_rad = 0.01);

}  // namespace stridemap
