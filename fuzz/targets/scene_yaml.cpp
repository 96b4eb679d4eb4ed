// Scene files for the simulator. Whatever the reader accepts must be a
// usable scene: rays cast against it and its ground truth come out without
// an exception, and hits are finite.
#include <cmath>
#include <string>

#include "fuzz_target.hpp"
#include "stridemap/config/scene_yaml.hpp"
#include "stridemap/core/error.hpp"
#include "stridemap/sim/scene_ray_caster.hpp"

STRIDEMAP_FUZZ_TARGET(scene_yaml) {
  using namespace stridemap;
  Scene scene;
  try {
    scene = parse_scene_yaml(std::string(fuzz::as_text(data)), "fuzz.yaml");
  } catch (const InputError&) {
    return;
  }
  try {
    const SceneRayCaster caster(scene);
    for (int k = 0; k < 8; ++k) {
      const double a = 0.7 * k;
      const Eigen::Vector3d origin(0.1 * k, -0.2 * k, 0.5);
      const Eigen::Vector3d direction = Eigen::Vector3d(std::cos(a), std::sin(a), -0.6).normalized();
      if (const auto hit = caster.cast(origin, direction, 6.0)) {
        fuzz::check(std::isfinite(hit->range_m) && hit->range_m >= 0.0 && hit->point_m.allFinite() &&
                        hit->normal.allFinite(),
                    "a ray hit that is not finite");
      }
      (void)scene.max_height_in_rect(origin.x(), origin.y(), origin.x() + 0.05, origin.y() + 0.05);
    }
  } catch (const InputError& e) {
    fuzz::failure(std::string("the reader accepted a scene the ray caster rejects: ") + e.what());
  }
}
