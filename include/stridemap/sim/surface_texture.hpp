#pragma once
// Reflectance texture of the scene's surfaces at the millimetre scale of a
// laser footprint: the grain of wood, paper and paint, dust, worn edges.
//
// A Lambertian reflectance per object is right for a beam that lands on one
// surface, but a beam split between two surfaces reads a range weighted by
// how much each part returns, and that share depends on the few square
// millimetres the footprint covers on each side. With uniform surfaces the
// mixed readings along an edge would all read the same proportion; with
// texture they scatter between the surfaces, which is what the paper's scan-
// sequence test (Fig. 14b, eq. 12) sees on a real URG-04LX.
//
// The texture is a fixed property of the place, not noise: space is cut into
// cubes of `grain_m`, and each cube (of each object) gets a mean-one
// log-normal gain from a hash of its index. The same point returns the same
// gain in every scan, nearby beams whose footprints overlap share gains, and
// nothing is stored.
#include <cstdint>

#include <Eigen/Core>

namespace stridemap {

struct SurfaceTextureOptions {
  /// Standard deviation of the logarithm of the gain. 0.35 (a patch returns
  /// within about +-35 % of its object's mean) is an assumption for wood,
  /// cardboard and paint under a 785 nm beam: not measured for the paper's
  /// objects. 0 switches the texture off (every gain is exactly 1).
  double log_sigma = 0.35;
  /// Edge of the texture cubes [m]. 2 mm: below the URG-04LX's footprint at
  /// terrain ranges (5-10 mm), so that a footprint averages a few grains and
  /// the part of it beyond an edge covers one or two.
  double grain_m = 0.002;
  /// Picks another texture of the same statistics.
  std::uint64_t salt = 0;

  /// Throws InputError "surface texture options: <field>: <problem>".
  void validate() const;
};

class SurfaceTexture {
 public:
  explicit SurfaceTexture(const SurfaceTextureOptions& options = {});

  /// Gain (mean 1 over many grains) of the surface of `object_index`
  /// (RayHit::object_index) at `point_m`.
  double gain(const Eigen::Vector3d& point_m, int object_index) const;

  const SurfaceTextureOptions& options() const { return options_; }

 private:
  SurfaceTextureOptions options_;
  double inverse_grain_ = 0.0;
};

}  // namespace stridemap
