#include "stridemap/sim/surface_texture.hpp"

#include <algorithm>
#include <cmath>
#include <numbers>
#include <string>

#include "stridemap/core/error.hpp"
#include "stridemap/sim/hash_mix.hpp"
#include "stridemap/sim/scene_problem.hpp"

namespace stridemap {
namespace {

void check_texture_option(const char* field, const std::optional<std::string>& problem) {
  if (problem) throw InputError(std::string("surface texture options: ") + field + ": " + *problem);
}

}  // namespace

void SurfaceTextureOptions::validate() const {
  check_texture_option("log_sigma", scene_rules::non_negative(log_sigma));
  check_texture_option("grain_m", scene_rules::positive(grain_m));
}

SurfaceTexture::SurfaceTexture(const SurfaceTextureOptions& options) : options_(options) {
  options_.validate();
  inverse_grain_ = 1.0 / options_.grain_m;
}

double SurfaceTexture::gain(const Eigen::Vector3d& point_m, int object_index) const {
  if (options_.log_sigma == 0.0) return 1.0;
  // The key chains the object and the cube's three indices; the last mix is
  // hashed_standard_normal's own.
  std::uint64_t key = options_.salt ^ static_cast<std::uint64_t>(static_cast<std::int64_t>(object_index));
  for (int axis = 0; axis < 3; ++axis) {
    // Clamped so that a far-off point cannot overflow the conversion.
    const double index = std::clamp(std::floor(point_m[axis] * inverse_grain_), -1e15, 1e15);
    key = mix64(key) ^ static_cast<std::uint64_t>(static_cast<std::int64_t>(index));
  }
  const double z = hashed_standard_normal(key);
  const double sigma = options_.log_sigma;
  return std::exp(sigma * z - 0.5 * sigma * sigma);
}

}  // namespace stridemap
