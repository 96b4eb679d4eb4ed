#pragma once
// A simulated scene: terrain height field plus boxes and cylinders, each with
// a diffuse reflectance, and optionally the rail a measuring cart runs on.
// Scenes are read from YAML by config/scene_yaml.hpp (schema: docs/scenes.md).
#include <cstddef>
#include <optional>
#include <string>
#include <vector>

#include <Eigen/Core>

#include "stridemap/sim/height_field.hpp"
#include "stridemap/sim/primitives.hpp"
#include "stridemap/sim/scene_problem.hpp"
#include "stridemap/sim/walk_path.hpp"

namespace stridemap {

/// The straight rail of the cart experiment (paper Fig. 16b): the cart moves
/// along X from start_x_m to end_x_m at lateral position y_m, one scan every
/// step_m, heading yaw_rad (0 = facing +X).
struct CartRailPath {
  double start_x_m = 0, end_x_m = 1, y_m = 0, step_m = 0.01, yaw_rad = 0;
};

/// Most boxes and most cylinders one scene may hold. Every simulated beam is
/// tested against every object, so the cost of a run grows with their count
/// (10^5 boxes: 314 s and 719 MB for one cart-rail run); a thousand of each
/// is far more than any test bed, and the rocks of a procedural terrain
/// (at most 100000, in the height field) cost nothing per beam.
inline constexpr std::size_t kMaxSceneBoxes = 1000;
inline constexpr std::size_t kMaxSceneCylinders = 1000;

class Scene {
 public:
  HeightField terrain;
  std::vector<BoxObject> boxes;
  std::vector<CylinderObject> cylinders;
  /// From the scene file's optional `cart_rail:` section.
  std::optional<CartRailPath> cart_rail;
  /// From the optional `walk_path:` section: the route of a walking robot
  /// (sim/walk_path.hpp); it must stay inside the terrain's extent.
  std::optional<WalkPath> walk_path;

  /// Nearest hit of terrain, boxes and cylinders within max_range_m.
  /// object_index: -1 terrain, 0..boxes.size()-1 boxes, then cylinders.
  /// For many rays against one scene, SceneRayCaster is faster.
  std::optional<RayHit> cast_ray(const Eigen::Vector3d& origin, const Eigen::Vector3d& unit_dir,
                                 double max_range_m) const;
  /// Highest surface at a point: terrain or the top of an object whose
  /// footprint contains it.
  double surface_height_at(double x_m, double y_m) const;
  /// Ground truth of a map cell: the highest terrain or object point inside
  /// the closed rectangle. Objects count when their footprint shares an area
  /// with the rectangle (see footprint_overlaps), terrain exactly. NaN when
  /// a coordinate is not finite.
  double max_height_in_rect(double min_x_m, double min_y_m, double max_x_m, double max_y_m) const;

  /// The scene at `time_s`: the boxes present then (BoxObject::present_at).
  Scene at_time(double time_s) const;
  /// Whether any box comes or goes (at_time() differs from the scene).
  bool changes_over_time() const;

  /// The first problem found, in the order terrain, boxes, cylinders,
  /// cart_rail, walk_path, duplicate names; nothing when the scene is usable.
  std::optional<SceneProblem> first_problem() const;
  /// Throws InputError "scene: <field path> (<object name>): <problem>".
  void validate() const;
};

}  // namespace stridemap
