#pragma once
// Fill-in of unknown cells by a certainty-weighted median of known
// neighbours (eq. 11). Only cells surrounded by enough evidence are filled,
// so that large occlusions stay unknown (Fig. 23d): small holes inside a
// continuous surface get a value, the shadow behind an obstacle does not.
#include <array>
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
  // Whether every sum of a window's weights is exact, so that any order of
  // adding them gives the sorted walk's sum (fill_exact_windows.cpp).
  bool window_sums_exact() const;
  // neighbours_ for the window radius and near factor.
  void list_neighbours();
  // The median of the known neighbours of padded cell `centre` by sorting
  // them; NaN when the quartiles spread too far.
  float sorted_walk(std::size_t centre, float total_weight);
  // result_ for every unknown cell the window admits: the exact path
  // (radius 1 or 2, exact sums) and the row path (any window).
  void fill_exact_windows();
  void fill_row_by_row();
  // result_ into the map; the number of cells filled.
  std::size_t write_results_to(ElevationMap& map);

  static constexpr int kMaxWindowCells = 15 * 15;  // radius 7
  struct Neighbour {
    std::ptrdiff_t offset;  // in the padded copy
    float factor;           // the near factor or 1
    unsigned quadrant_bit;
  };

  FillOptions options_;
  std::vector<float> result_;  // per slot, NaN = leave unknown
  std::vector<std::uint8_t> reset_;  // per slot: no value, every layer reset
  // The padded copy (prepare()), kept to reuse storage: known or not, the
  // same as all ones or zeros (32-bit lanes for the row pass), value (+inf
  // where unknown), weight (0 where unknown).
  std::size_t margin_ = 0, pitch_ = 0, cells_per_side_ = 0;
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
  // The window's neighbours in the order the fill has always visited them,
  // and the sorted walk's scratch (a whole window, and room for 8 more).
  std::array<Neighbour, kMaxWindowCells> neighbours_{};
  std::size_t neighbour_count_ = 0;
  std::array<Candidate, kMaxWindowCells> candidates_{}, gathered_{};
  alignas(64) std::array<float, kMaxWindowCells + 8> scratch_{};
  alignas(64) std::array<std::uint32_t, kMaxWindowCells + 8> ranks_{};
};

}  // namespace stridemap
