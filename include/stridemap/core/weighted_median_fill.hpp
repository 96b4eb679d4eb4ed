#pragma once
// Fill-in of unknown cells by a certainty-weighted median of known
// neighbours (eq. 11). Only cells surrounded by enough evidence are filled,
// so that large occlusions stay unknown (Fig. 23d): small holes inside a
// continuous surface get a value, the shadow behind an obstacle does not.
#include <cstddef>
#include <cstdint>
#include <vector>

#include "stridemap/core/grid_map.hpp"

namespace stridemap {

struct FillOptions {
  /// w: the window is (2w + 1) x (2w + 1) cells around the unknown cell.
  int window_radius_cells = 2;
  /// Fewest measured cells in the window for a fill (8 of 24 by default).
  int min_known_neighbours = 8;
  /// Measured neighbours must lie in at least this many of the four
  /// quadrants around the cell, so that values are interpolated, never
  /// extrapolated across the edge of an occlusion.
  int min_quadrants = 3;
  /// Weight factor of the 8 nearest neighbours relative to farther cells;
  /// each neighbour's weight is its certainty times this factor (or 1).
  double near_weight = 2.0;
  /// A cell whose known neighbours disagree by more than this between their
  /// weighted quartiles sits on a step (the edge of an obstacle and the
  /// shadow behind it): the median would pick a side at random, so the cell
  /// stays unknown [m]. Non-positive disables the test. Default: 3 cm,
  /// between the URG's noise and a step a foot must not be placed on.
  double max_quartile_spread_m = 0.03;
};

class WeightedMedianFill {
 public:
  /// Throws InputError for a window radius outside 1..7, negative counts or
  /// quadrants outside 1..4, a non-positive weight or a non-finite spread.
  explicit WeightedMedianFill(const FillOptions& options = {});

  /// Re-estimates every filled cell and fills unknown cells from measured
  /// ones. Filled cells keep certainty 0 and state `filled`; values computed
  /// in this pass are not used as inputs to it. Returns the number of cells
  /// in state `filled` afterwards.
  std::size_t apply(ElevationMap& map);

  const FillOptions& options() const { return options_; }

 private:
  friend class CasFilter;  // shares the padded copy (prepare, forget)
  struct Candidate {
    float value;
    float weight;
  };
  // The map in local order with `margin` unknown cells around it.
  void prepare(const ElevationMap& map, int margin);
  // Makes local cell i * n + j of the padded copy unknown.
  void forget(std::size_t local_cell, int n);
  // apply() on the padded copy of `map` made by prepare().
  std::size_t fill_prepared(ElevationMap& map);

  FillOptions options_;
  std::vector<float> result_;  // per slot, NaN = leave unknown
  std::vector<std::uint8_t> reset_;  // per slot: no value, every layer reset
  // The padded copy (prepare()), kept to reuse storage: known or not, the
  // same as all ones or zeros (32-bit lanes for the row pass), value (+inf
  // where unknown), weight (0 where unknown).
  std::size_t margin_ = 0, pitch_ = 0;
  std::vector<std::uint8_t> known_;
  std::vector<std::uint32_t> known_mask_;
  std::vector<float> value_, weight_;
  std::vector<std::size_t> slot_;  // slot of local cell i * n + j
  // Per cell of the row being filled: known neighbours, their quadrants
  // (a bit each) and their total weight (the row pass, inexact sums).
  std::vector<std::uint32_t> count_, quadrants_;
  std::vector<float> total_;
  std::vector<std::size_t> unknown_columns_;  // of the row being filled
  // The exact path (fill_exact_windows.hpp): bits per padded cell (known,
  // zero or NaN) and per row of a window around it,
  // windows left to the sorted walk and their total weights, a row's
  // unknown columns.
  std::vector<std::uint16_t> cell_bits_, row_bits_;
  std::vector<std::uint32_t> walk_cells_, columns_;
  std::vector<float> walk_totals_;
};

}  // namespace stridemap
