#include "foothold_score.hpp"

#include <cstdint>

#include "foothold_cells.hpp"

namespace stridemap::foothold {
namespace {

constexpr int kScoreLanes = 4;
using Doubles = double __attribute__((vector_size(kScoreLanes * sizeof(double))));

}  // namespace

// Four cells a pass: the divisions go four at a time, and the clamps become
// selects where the scalar code branched on factors that fall either side
// of their bounds at random. Per lane the operations and their order are
// the scalar score's (no FMA in either copy, a product has no add to fuse).
STRIDEMAP_FOOTHOLD_CLONES void score_cells(const ScoreCells& c, float* score) {
  const Doubles zero = {0.0, 0.0, 0.0, 0.0}, one = {1.0, 1.0, 1.0, 1.0};
  const auto unit_clamp = [&](Doubles v) {  // std::clamp(v, 0.0, 1.0)
    v = v < zero ? zero : v;
    return one < v ? one : v;
  };
  for (std::size_t first = 0; first < c.count; first += kScoreLanes) {
    // A last pass short of lanes repeats its last cell and stores it once.
    std::size_t s[kScoreLanes];
    double edge[kScoreLanes];
    for (int l = 0; l < kScoreLanes; ++l) {
      const std::size_t k = first + l < c.count ? first + l : c.count - 1;
      s[l] = c.slots[k];
      edge[l] = c.edge_factors[k];
    }
    const Doubles slope = {c.slope_deg[s[0]], c.slope_deg[s[1]], c.slope_deg[s[2]], c.slope_deg[s[3]]};
    const Doubles step = {c.step_height_m[s[0]], c.step_height_m[s[1]], c.step_height_m[s[2]], c.step_height_m[s[3]]};
    const Doubles rough = {c.roughness_m[s[0]], c.roughness_m[s[1]], c.roughness_m[s[2]], c.roughness_m[s[3]]};
    const Doubles certainty = {c.certainty[s[0]], c.certainty[s[1]], c.certainty[s[2]], c.certainty[s[3]]};
    const Doubles edge_factor = {edge[0], edge[1], edge[2], edge[3]};
    const Doubles product = unit_clamp(one - slope / c.max_slope_deg) * unit_clamp(one - step / c.max_step_m) *
                            unit_clamp(one - rough / c.max_roughness_m) * edge_factor *
                            unit_clamp(certainty / c.full_certainty);
    for (int l = 0; l < kScoreLanes && first + l < c.count; ++l) score[s[l]] = static_cast<float>(product[l]);
  }
}

}  // namespace stridemap::foothold
