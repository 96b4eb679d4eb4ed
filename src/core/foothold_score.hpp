#pragma once
// The foothold score (core/foothold.hpp) of many cells at once. Private to
// the core library.
#include <cstddef>

namespace stridemap::foothold {

/// The cells a refresh scores (storage slots, with the edge factor of each)
/// and what the score reads.
struct ScoreCells {
  const std::size_t* slots;
  const double* edge_factors;
  std::size_t count;
  const float *slope_deg, *step_height_m, *roughness_m, *certainty;
  /// FootholdOptions' limits (each > 0, as validated) and full_certainty.
  double max_slope_deg, max_step_m, max_roughness_m, full_certainty;
};

/// Writes each cell's score: the product, in this order, of the ramps
/// clamp(1 - value / limit, 0, 1) of slope, step and roughness, the edge
/// factor and clamp(certainty / full_certainty, 0, 1), rounded to float.
void score_cells(const ScoreCells& cells, float* score);

}  // namespace stridemap::foothold
