#pragma once
// Casts many rays against one fixed scene. It keeps its own copy of the scene
// (so nothing can change under it) and precomputes what every ray would
// otherwise recompute: the highest terrain sample, which lets rays skip the
// part of their path above all terrain, and each object's bounding box.
#include <optional>
#include <vector>

#include <Eigen/Core>

#include "stridemap/sim/scene.hpp"

namespace stridemap {

class SceneRayCaster {
 public:
  /// Validates the scene (InputError when it is not usable).
  explicit SceneRayCaster(Scene scene);

  const Scene& scene() const { return scene_; }
  /// Same answer as Scene::cast_ray.
  std::optional<RayHit> cast(const Eigen::Vector3d& origin, const Eigen::Vector3d& unit_dir,
                             double max_range_m) const;

 private:
  struct Bounds {
    Eigen::Vector3d min_m, max_m;
  };
  Scene scene_;
  double terrain_top_m_ = 0.0;
  std::vector<Bounds> object_bounds_;  ///< boxes then cylinders
};

}  // namespace stridemap
