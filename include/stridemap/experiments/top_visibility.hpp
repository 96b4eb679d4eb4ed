#pragma once
// How much of each object's top a sensor could see on a run. The ideal
// sensor's hits (no noise, no mixed measurement, the same poses and beams)
// are gathered per object; a point of a top counts as seen when a hit on
// that top lies near it. An object the swath leaves partly outside, or one
// that another object hides, is partly seen: its extents measure the
// sensor's reach rather than the map, so the harness scores it apart.
#include <vector>

#include <Eigen/Core>

#include "stridemap/sim/scene.hpp"

namespace stridemap {

struct TopVisibilityOptions {
  /// Spacing of the sample points laid over each top [m].
  double sample_spacing_m = 0.002;
  /// Samples closer than this to a top's rim are left out: whether the
  /// last scan line falls just inside a rim or just past it is luck [m].
  double rim_inset_m = 0.003;
  /// A hit belongs to a top when it lies at most this far below it [m].
  double top_tolerance_m = 0.001;
};

class TopVisibility {
 public:
  /// `reach_m`: a sample is seen when a hit on its top lies within this
  /// horizontal distance. Just over half the widest gap between
  /// neighbouring hits on a fully seen top (the rail's step, the spacing of
  /// beams or image columns) marks a fully seen top as fully seen.
  /// Throws InputError for a reach or an option that is not positive.
  TopVisibility(const Scene& scene, double reach_m, const TopVisibilityOptions& options = {});

  /// One hit of the ideal sensor; `object_index` as RayHit's (-1, the
  /// terrain, and hits below the object's top are not counted).
  void add_hit(int object_index, const Eigen::Vector3d& point_m);

  /// Per object, boxes then cylinders (the scene's order), the share of
  /// its top's samples that are seen, in [0, 1].
  std::vector<double> seen_shares() const;

 private:
  struct Top {
    Eigen::Vector2d centre_m;
    double yaw_rad = 0.0;
    double half_length_m = 0.0, half_width_m = 0.0;  // boxes
    double radius_m = 0.0;                           // cylinders, 0 for boxes
    double top_m = 0.0;
  };
  double seen_share(const Top& top, const std::vector<Eigen::Vector2d>& hits) const;

  double reach_m_;
  TopVisibilityOptions options_;
  std::vector<Top> tops_;
  std::vector<std::vector<Eigen::Vector2d>> hits_;
};

}  // namespace stridemap
