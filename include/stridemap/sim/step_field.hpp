#pragma once
// Random step fields (paper Figs. 5 and 7): a flat floor with a grid of
// square blocks of random height, the terrain the sensor-mount analysis
// walks the robot through.
#include <cstdint>
#include <optional>
#include <string>

#include "stridemap/sim/scene.hpp"

namespace stridemap {

struct StepFieldOptions {
  /// Area covered by blocks [m]; the robot walks along +X through it.
  double min_x_m = 0.6, min_y_m = -0.6, max_x_m = 2.6, max_y_m = 0.6;
  /// Side of a block [m]. 0.1 m: a foot fits on one, as on the step fields
  /// legged robots are tested on.
  double block_size_m = 0.10;
  /// Block heights are drawn uniformly from [min_height_m, max_height_m]
  /// [m]; 0.10 m stays within what Messor climbs (section 4.2).
  double min_height_m = 0.02;
  double max_height_m = 0.10;
  /// Share of grid places left empty (floor), in [0, 1).
  double empty_fraction = 0.4;
  /// Floor beyond the blocks, on every side, inside the scene's extent [m]:
  /// room for the approach and for the sensor's look-ahead.
  double margin_m = 1.0;
  double reflectance = 0.5;  ///< of floor and blocks

  /// "step field options: <field>: <problem>", if any.
  std::optional<std::string> first_problem() const;
};

/// A flat floor at 0 with the blocks as boxes named "block_<i>_<j>".
/// Deterministic for a seed. Throws InputError for unusable options.
Scene make_step_field(const StepFieldOptions& options, std::uint64_t seed);

}  // namespace stridemap
