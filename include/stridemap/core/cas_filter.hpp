#pragma once
// The Certainty Assisted Spatial (CAS) filter of Ye and Borenstein, as the
// paper uses it with structured light (section 5.3): it deletes cells whose
// elevation breaks the spatial continuity of the map while their certainty
// is low against their neighbourhood, then fills unknown cells with the
// weighted median (eq. 11). The original thresholds were not published in a
// form we could read; these rules are a well-defined reconstruction
// (../shared/research/algorithms.md 1.6, 1.8), free of the datum dependence
// of the authors' implementation.
#include <cstddef>
#include <cstdint>
#include <vector>

#include "stridemap/core/grid_map.hpp"
#include "stridemap/core/weighted_median_fill.hpp"

namespace stridemap {

struct CasOptions {
  /// w: the continuity tests look at a (2w + 1)^2 window (7 x 7 by default,
  /// the size used by the paper's authors).
  int window_radius_cells = 3;
  /// Neighbours within this height of a cell agree with it [m].
  double elevation_tolerance_m = 0.025;
  /// A cell with fewer agreeing measured 8-neighbours than this, standing
  /// higher than its window's median by more than the tolerance, is an
  /// isolated peak.
  int min_agreeing_neighbours = 2;
  /// Certainty below this fraction of the window's median certainty is
  /// weak support (0.34: one hit where the neighbours have three).
  double certainty_ratio = 0.34;
  /// A window whose certainties add up to less than this holds too little
  /// evidence to trust any peak in it (10 a with a = 3).
  double min_window_certainty = 30.0;
  /// Only cells with certainty up to this can be removed (W = a: accepted
  /// once).
  double max_removable_certainty = 3.0;
  /// Fill-in applied after the removal (rule 2).
  FillOptions fill{};
};

struct CasResult {
  std::size_t removed = 0;  ///< measured cells reset to unknown
  std::size_t filled = 0;   ///< cells in state filled afterwards
};

class CasFilter {
 public:
  /// Throws InputError naming the bad option.
  explicit CasFilter(const CasOptions& options = {});
  /// Removal decisions are taken on the map as it comes in (one pass), then
  /// the weighted median fills.
  CasResult apply(ElevationMap& map);
  const CasOptions& options() const { return options_; }

 private:
  // The window test of the cell at padded index q (height hs): an isolated
  // peak whose certainty is weak against its window's.
  bool is_weak_isolated_peak(std::size_t q, float hs);

  CasOptions options_;
  WeightedMedianFill fill_;
  std::vector<std::size_t> to_remove_;  // local cells i * n + j
  std::vector<float> window_values_;
  std::vector<float> window_certainties_;
  std::vector<std::uint32_t> candidates_;  // removable columns of the row being tested
};

}  // namespace stridemap
