#pragma once
// The trunk's height above the map's zero from where the stance feet stand:
// h_ref + d_z of eq. (9), read from the map the robot is building (paper
// section 5.2), but from the fused layer (core/height_fusion.hpp), which has
// no upward bias, rather than eq. (10)'s highest readings.
//
// Each stance foot's sole is placed by the robot's kinematics and its pose
// estimate (map frame); the layer's median over the known cells within the
// sole's radius is the ground it stands on, and the trunk stands above it by
// the foot's kinematic depth. The feet are weighted by the layer's variance,
// the spread of heights under the sole (large on a rock's flank) and the
// kinematics' own; a sole mostly over unknown cells (likely in a shadow,
// where what is known is the top of what cast it) has no say, and a foot
// that disagrees with the others beyond a Mahalanobis gate is left out,
// the worst first, while more than two remain.
//
// The rocky walk's `map-footholds` reference is this (docs/walking.md),
// with leg odometry on top when the feet stand on unknown cells for long.
#include <array>
#include <cstddef>
#include <limits>
#include <optional>
#include <span>

#include "stridemap/core/grid_map.hpp"

namespace stridemap {

struct StanceHeightOptions {
  /// The known cells within this radius of a sole's centre give its
  /// ground [m]. 2 cm: a small walking robot's foot.
  double sole_radius_m = 0.02;
  /// Below this share of known cells under a sole the foot has no say.
  double min_known_share = 0.5;
  /// A foot whose trunk height lies further than this many standard
  /// deviations from the other feet's is left out (> 0; infinity keeps
  /// every foot that reads the map).
  double gate_sigmas = 2.5;
  /// Standard deviation of a foot's kinematic depth [m] (joint encoders
  /// over the leg's length): 2 mm.
  double depth_sigma_m = 0.002;

  /// Throws InputError "stance height options: <field>: <problem>".
  void validate() const;
};

/// One stance foot as the robot's kinematics and pose estimate give it.
struct StanceFoot {
  double x_m = 0.0;  ///< the sole's centre, map frame [m]
  double y_m = 0.0;
  /// How far the sole lies below the trunk's reference point (the point
  /// whose height is h_ref + d_z), along the map's z [m]: the kinematics
  /// turned by the estimated attitude.
  double depth_m = 0.0;
};

/// The fused layer under one sole.
struct SoleGround {
  double height_m = 0.0;     ///< median of the known cells' heights [m]
  double variance_m2 = 0.0;  ///< median of their variances [m^2]
  double spread_m2 = 0.0;    ///< variance of their heights about the median [m^2]
  double known_share = 0.0;  ///< of the cells under the sole, the share the layer knows
};

/// What one foot said.
struct StanceFootHeight {
  bool read = false;  ///< its sole stands on known cells (share >= min_known_share)
  bool used = false;  ///< read, and kept by the gate
  double ground_m = std::numeric_limits<double>::quiet_NaN();     ///< the ground under the sole (SoleGround::height_m) [m]
  double trunk_z_m = std::numeric_limits<double>::quiet_NaN();    ///< ground + depth [m]
  double variance_m2 = std::numeric_limits<double>::quiet_NaN();  ///< of trunk_z_m [m^2]
};

struct StanceHeight {
  static constexpr std::size_t kMaxFeet = 8;
  /// The used feet's variance-weighted trunk height [m] and its variance;
  /// NaN when no foot was used.
  double trunk_z_m = std::numeric_limits<double>::quiet_NaN();
  double variance_m2 = std::numeric_limits<double>::quiet_NaN();
  int feet_read = 0;
  int feet_used = 0;
  /// Per foot, in the order given.
  std::array<StanceFootHeight, kMaxFeet> feet{};
};

/// Reads a map's fused layers (HeightFusion fills them; the pipeline's
/// HeightFusionObserver, or the walk's own). Allocates nothing per call.
class StanceHeightReader {
 public:
  /// Finds the layers "fused_elevation" and "fused_variance" (f32) in
  /// `map`, else InputError naming the layers the map has. Validates the
  /// options. The reader stays valid for that map and its copies.
  explicit StanceHeightReader(const ElevationMap& map, const StanceHeightOptions& options = {});

  /// The trunk's height from the stance feet (at most StanceHeight::kMaxFeet).
  /// InputError "stance height: foot <k>: <field> ..." for a position or
  /// depth that is not finite, or for more feet than kMaxFeet. A foot
  /// outside the window reads nothing.
  StanceHeight read(const ElevationMap& map, std::span<const StanceFoot> feet) const;

  /// The fused layer under a sole centred at (x, y); nullopt when no cell
  /// under it is known.
  std::optional<SoleGround> ground_under(const ElevationMap& map, double x_m, double y_m) const;

  const StanceHeightOptions& options() const { return options_; }

 private:
  StanceHeightOptions options_;
  LayerId<float> elevation_;
  LayerId<float> variance_;
};

}  // namespace stridemap
