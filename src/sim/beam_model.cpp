#include "stridemap/sim/beam_model.hpp"

#include <algorithm>
#include <cmath>

namespace stridemap {

double lambertian_amplitude(double reflectance, double cos_incidence, double range_m) {
  if (!(cos_incidence > 0.0)) return 0.0;
  // A return from (almost) zero range is not a number the receiver can
  // see; capping the range at 1 mm keeps the amplitude finite.
  const double r = std::max(range_m, 1e-3);
  return reflectance * cos_incidence / (r * r);
}

BeamEcho SingleRayBeamModel::trace(const SceneRayCaster& scene, const BeamRequest& beam, std::mt19937_64& /*rng*/) {
  BeamEcho echo;
  const std::optional<RayHit> hit = scene.cast(beam.origin_m, beam.direction, beam.max_range_m);
  if (!hit) return echo;
  echo.has_return = true;
  echo.range_m = hit->range_m;
  last_range_m_ = hit->range_m;
  echo.amplitude = lambertian_amplitude(hit->reflectance, -hit->normal.dot(beam.direction), hit->range_m);
  echo.label = BeamLabel::clean;
  return echo;
}

BeamLabel SingleRayBeamModel::label_for_range(double range_m) const {
  return std::abs(range_m - last_range_m_) > single_ray_mixed_tolerance_m ? BeamLabel::mixed : BeamLabel::clean;
}

}  // namespace stridemap
