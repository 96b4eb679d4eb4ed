#pragma once
// The visibility clean-up's rule with nothing left out: every beam walks all
// its cells from the sensor. The reference the pruned and incremental
// clean-up (core/visibility_clearing.hpp) must match bit for bit.
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <limits>
#include <vector>

#include <gtest/gtest.h>

#include "stridemap/core/visibility_clearing.hpp"

namespace stridemap::test {

class FullWalk {
 public:
  /// `summed`: crossings summed step by step, as the walk before the
  /// pruning took them; otherwise each from its own cell boundary, as the
  /// clean-up takes them (equal in the last bit only for the latter).
  FullWalk(const ElevationMap& map, const VisibilityOptions& options, bool summed = true)
      : options_(options),
        stamp_(static_cast<std::size_t>(map.cells_per_side()) * static_cast<std::size_t>(map.cells_per_side()), 0),
        summed_(summed) {}

  void begin_scan() {
    ++scan_;
    have_last_hit_ = false;
    cleared_.clear();
    changed_.clear();
    stats_ = {};
  }

  void trace(ElevationMap& map, const VisibilityBeam& beam) {
    const Eigen::Vector3d d = beam.hit_m - beam.origin_m;
    const double range = d.norm();
    if (!(range > 0.0) || !std::isfinite(range) || !std::isfinite(beam.range_error_m) ||
        !std::isfinite(beam.height_error_m) || !beam.origin_m.allFinite()) {
      return;
    }
    const double cell = map.cell_size_m();
    const Eigen::Vector2d hit = beam.hit_m.head<2>();
    if (have_last_hit_ && options_.beam_spacing_cells > 0.0 &&
        (hit - last_hit_).squaredNorm() < std::pow(options_.beam_spacing_cells * cell, 2)) {
      return;
    }
    have_last_hit_ = true;
    last_hit_ = hit;
    ++stats_.beams_traced;
    const double t_stop = 1.0 - beam.range_error_m / range;
    if (!(t_stop > 0.0)) return;
    const double margin = options_.uncertainty_factor * beam.height_error_m + options_.relief_factor * cell;
    const double inverse_cell = 1.0 / cell;
    const double ox = beam.origin_m.x() * inverse_cell, oy = beam.origin_m.y() * inverse_cell;
    const double dx = d.x() * inverse_cell, dy = d.y() * inverse_cell;
    auto ix = static_cast<std::int64_t>(std::floor(ox)), iy = static_cast<std::int64_t>(std::floor(oy));
    const std::int64_t step_x = dx > 0 ? 1 : -1, step_y = dy > 0 ? 1 : -1;
    constexpr double kInf = std::numeric_limits<double>::infinity();
    double bx = static_cast<double>(ix + (dx > 0 ? 1 : 0)), by = static_cast<double>(iy + (dy > 0 ? 1 : 0));
    // From its boundary: a direction too small to invert never crosses one.
    const double inv_x = 1.0 / dx, inv_y = 1.0 / dy;
    const bool moves_x = dx != 0.0 && std::isfinite(inv_x), moves_y = dy != 0.0 && std::isfinite(inv_y);
    double next_x = summed_ ? (dx != 0.0 ? (bx - ox) / dx : kInf) : (moves_x ? (bx - ox) * inv_x : kInf);
    double next_y = summed_ ? (dy != 0.0 ? (by - oy) / dy : kInf) : (moves_y ? (by - oy) * inv_y : kInf);
    const double delta_x = dx != 0.0 ? 1.0 / std::abs(dx) : kInf, delta_y = dy != 0.0 ? 1.0 / std::abs(dy) : kInf;
    const double z0 = beam.origin_m.z(), dz = d.z();
    double t_in = 0.0;
    while (true) {
      const double t_out = std::min(next_x, next_y);
      if (t_out > t_stop) break;
      const CellIndex c{ix, iy};
      if (map.contains(c)) {
        ++stats_.cells_crossed;
        const double z_beam_max = z0 + dz * (dz > 0 ? t_out : t_in);
        const std::size_t s = map.slot(c);
        if (map.elevation_data()[s] > z_beam_max + margin) contradict(map, c, s);
      }
      t_in = t_out;
      if (next_x < next_y) {
        ix += step_x;
        bx += static_cast<double>(step_x);
        next_x = summed_ ? next_x + delta_x : (bx - ox) * inv_x;
      } else {
        iy += step_y;
        by += static_cast<double>(step_y);
        next_y = summed_ ? next_y + delta_y : (by - oy) * inv_y;
      }
    }
  }

  const VisibilityStats& stats() const { return stats_; }
  const std::vector<ClearedCell>& cleared() const { return cleared_; }
  const CellBox& changed() const { return changed_; }

 private:
  void contradict(ElevationMap& map, CellIndex cell, std::size_t slot) {
    if (stamp_[slot] == scan_) return;
    stamp_[slot] = scan_;
    ++stats_.cells_contradicted;
    changed_.add(cell);
    if (static_cast<CellState>(map.state_data()[slot]) == CellState::measured) {
      float& certainty = map.certainty_data()[slot];
      certainty -= static_cast<float>(options_.certainty_decrement);
      if (certainty > 0.0f) return;
    }
    const float was = map.elevation_data()[slot];
    map.reset_slot(slot);
    ++stats_.cells_cleared;
    cleared_.push_back({cell, was});
  }

  VisibilityOptions options_;
  std::vector<std::uint32_t> stamp_;
  bool summed_ = true;
  std::uint32_t scan_ = 0;
  bool have_last_hit_ = false;
  Eigen::Vector2d last_hit_{0.0, 0.0};
  std::vector<ClearedCell> cleared_;
  CellBox changed_;
  VisibilityStats stats_;
};

/// Every layer the clean-up writes (reset_slot resets them all), bit for bit.
inline void expect_same_maps(const ElevationMap& a, const ElevationMap& b) {
  const std::size_t cells = static_cast<std::size_t>(a.cells_per_side()) * static_cast<std::size_t>(a.cells_per_side());
  ASSERT_EQ(a.min_cell(), b.min_cell());
  EXPECT_EQ(std::memcmp(a.elevation_data(), b.elevation_data(), cells * sizeof(float)), 0);
  EXPECT_EQ(std::memcmp(a.certainty_data(), b.certainty_data(), cells * sizeof(float)), 0);
  EXPECT_EQ(std::memcmp(a.state_data(), b.state_data(), cells), 0);
  EXPECT_EQ(std::memcmp(a.contradiction_data(), b.contradiction_data(), cells), 0);
  EXPECT_EQ(std::memcmp(a.pending_elevation_data(), b.pending_elevation_data(), cells * sizeof(float)), 0);
  EXPECT_EQ(std::memcmp(a.mean_elevation_data(), b.mean_elevation_data(), cells * sizeof(float)), 0);
  EXPECT_EQ(std::memcmp(a.mean_count_data(), b.mean_count_data(), cells * sizeof(std::uint16_t)), 0);
}

/// The clean-up's account of a scan against the reference's (the full
/// walk, or another clean-up); a pruned walk crosses no more cells.
template <typename Clearing, typename Reference>
void expect_same_account(const Clearing& clearing, const Reference& full) {
  EXPECT_EQ(clearing.stats().beams_traced, full.stats().beams_traced);
  EXPECT_EQ(clearing.stats().cells_contradicted, full.stats().cells_contradicted);
  EXPECT_EQ(clearing.stats().cells_cleared, full.stats().cells_cleared);
  EXPECT_LE(clearing.stats().cells_crossed, full.stats().cells_crossed);
  ASSERT_EQ(clearing.cleared().size(), full.cleared().size());
  for (std::size_t c = 0; c < full.cleared().size(); ++c) {
    EXPECT_EQ(clearing.cleared()[c].cell, full.cleared()[c].cell);
    EXPECT_EQ(clearing.cleared()[c].elevation_m, full.cleared()[c].elevation_m);
  }
  EXPECT_EQ(clearing.changed().min, full.changed().min);
  EXPECT_EQ(clearing.changed().max, full.changed().max);
}

}  // namespace stridemap::test
