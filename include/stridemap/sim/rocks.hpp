#pragma once
// Rocks on a procedural terrain (the rocky mock-up of paper section 6.2,
// Figs. 22-24): rounded boulders of several size classes, baked into the
// height field so that ray casting and ground truth stay exact.
//
// A rock has an elliptical footprint (semi-axes radius and radius * aspect,
// turned by a random yaw) and the profile
//   z(rho) = g - s H + (1 + s) H (1 - rho^p)^(1/p),   rho = elliptical radius in [0, 1)
// over the ground height g at its centre: H above the ground at the centre,
// sides that steepen towards the rim (p = profile_exponent; 2 would be a
// half-ellipsoid) and a foot buried by s = buried_fraction of its height,
// so that it meets uneven ground with a visible step. The terrain takes the
// higher of ground and rocks.
#include <array>
#include <cstdint>
#include <optional>
#include <string>
#include <vector>

namespace stridemap {

struct HeightField;
struct SceneProblem;

/// One size class: `count` rocks with radius and height drawn uniformly
/// from the ranges.
struct RockClass {
  int count = 0;
  double min_radius_m = 0.05, max_radius_m = 0.10;  ///< semi-axis of the longer side [m]
  double min_height_m = 0.03, max_height_m = 0.06;  ///< above the ground at the centre [m]
};

struct RockFieldOptions {
  std::vector<RockClass> classes;  ///< none: no rocks
  /// Rectangle the rock centres are drawn in (min x, min y, max x, max y)
  /// [m]; unset: the terrain's extent.
  std::optional<std::array<double, 4>> area;
  /// Shortest side over longest, drawn uniformly from [min_aspect, 1].
  double min_aspect = 0.6;
  double profile_exponent = 2.5;  ///< p above, >= 1
  double buried_fraction = 0.25;  ///< s above, in [0, 1)
};

/// First unusable option, field paths relative to the terrain section
/// ("rocks[1].max_radius_m", "rocks_area.max_x_m").
std::optional<SceneProblem> rock_field_problem(const RockFieldOptions& options);

/// Adds the rocks to a sampled height field. Deterministic for a seed.
void add_rocks(const RockFieldOptions& options, std::uint64_t seed, HeightField& field);

}  // namespace stridemap
