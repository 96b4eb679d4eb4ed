#include "stridemap/core/visibility_clearing.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <string>

#include "stridemap/core/error.hpp"

namespace stridemap {
namespace {

// Enough to name what a scan cleared near the robot; beyond it only counted,
// so that recording never allocates.
constexpr std::size_t kMaxRecordedCleared = 1 << 14;

void require(bool ok, const char* field, const char* what, double value) {
  if (!ok) {
    throw InputError(std::string("visibility: ") + field + " must be " + what + ", got " + std::to_string(value));
  }
}

}  // namespace

void validate_visibility_options(const VisibilityOptions& o) {
  require(std::isfinite(o.uncertainty_factor) && o.uncertainty_factor >= 0.0, "uncertainty_factor",
          "a finite number >= 0", o.uncertainty_factor);
  require(std::isfinite(o.relief_factor) && o.relief_factor >= 0.0, "relief_factor", "a finite number >= 0",
          o.relief_factor);
  require(std::isfinite(o.certainty_decrement) && o.certainty_decrement > 0.0, "certainty_decrement",
          "a finite number > 0", o.certainty_decrement);
  require(std::isfinite(o.beam_spacing_cells) && o.beam_spacing_cells >= 0.0 && o.beam_spacing_cells <= 1000.0,
          "beam_spacing_cells", "a number from 0 to 1000", o.beam_spacing_cells);
}

VisibilityClearing::VisibilityClearing(const ElevationMap& map, const VisibilityOptions& options)
    : options_(options),
      stamp_(static_cast<std::size_t>(map.cells_per_side()) * static_cast<std::size_t>(map.cells_per_side()), 0) {
  validate_visibility_options(options_);
  cleared_.reserve(std::min(stamp_.size(), kMaxRecordedCleared));
}

void VisibilityClearing::begin_scan() {
  if (++scan_ == 0) {  // after 2^32 scans: old stamps could match again
    std::fill(stamp_.begin(), stamp_.end(), 0u);
    scan_ = 1;
  }
  ++scans_;
  have_last_hit_ = false;
  cleared_.clear();
  changed_.clear();
  stats_ = {};
}

void VisibilityClearing::trace(ElevationMap& map, const VisibilityBeam& beam) {
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

  // Only the part of the beam that cannot hold the true surface.
  const double t_stop = 1.0 - beam.range_error_m / range;
  if (!(t_stop > 0.0)) return;
  const double margin = options_.uncertainty_factor * beam.height_error_m + options_.relief_factor * cell;

  const double inverse_cell = 1.0 / cell;
  const double ox = beam.origin_m.x() * inverse_cell, oy = beam.origin_m.y() * inverse_cell;
  const double dx = d.x() * inverse_cell, dy = d.y() * inverse_cell;
  // Far outside any window the index arithmetic below would overflow.
  constexpr double kMaxIndex = 1e15;
  if (!(std::abs(ox) < kMaxIndex && std::abs(oy) < kMaxIndex && std::abs(ox + dx) < kMaxIndex &&
        std::abs(oy + dy) < kMaxIndex)) {
    return;
  }
  auto ix = static_cast<std::int64_t>(std::floor(ox)), iy = static_cast<std::int64_t>(std::floor(oy));
  const std::int64_t step_x = dx > 0 ? 1 : -1, step_y = dy > 0 ? 1 : -1;
  constexpr double kInf = std::numeric_limits<double>::infinity();
  double next_x = dx != 0.0 ? (static_cast<double>(ix + (dx > 0 ? 1 : 0)) - ox) / dx : kInf;
  double next_y = dy != 0.0 ? (static_cast<double>(iy + (dy > 0 ? 1 : 0)) - oy) / dy : kInf;
  const double delta_x = dx != 0.0 ? 1.0 / std::abs(dx) : kInf, delta_y = dy != 0.0 ? 1.0 / std::abs(dy) : kInf;

  const std::int64_t n = map.cells_per_side();
  const CellIndex corner = map.min_cell();
  const auto corner_slot = static_cast<std::int64_t>(map.slot(corner));
  const std::int64_t slot_x0 = corner_slot / n, slot_y0 = corner_slot % n;
  const double z0 = beam.origin_m.z(), dz = d.z();
  const float* elevation = map.elevation_data();
  double t_in = 0.0;
  while (true) {
    const double t_out = std::min(next_x, next_y);
    if (t_out > t_stop) break;
    const std::int64_t i = ix - corner.x, j = iy - corner.y;
    if (i >= 0 && i < n && j >= 0 && j < n) {
      ++stats_.cells_crossed;
      std::int64_t si = slot_x0 + i, sj = slot_y0 + j;
      si -= si >= n ? n : 0;
      sj -= sj >= n ? n : 0;
      const auto s = static_cast<std::size_t>(si * n + sj);
      const double z_beam_max = z0 + dz * (dz > 0 ? t_out : t_in);
      // NaN (unknown) fails the comparison: nothing to clear.
      if (elevation[s] > z_beam_max + margin) contradict(map, {ix, iy}, s);
    }
    t_in = t_out;
    if (next_x < next_y) {
      ix += step_x;
      next_x += delta_x;
    } else {
      iy += step_y;
      next_y += delta_y;
    }
  }
}

void VisibilityClearing::contradict(ElevationMap& map, CellIndex cell, std::size_t slot) {
  if (stamp_[slot] == scan_) return;
  stamp_[slot] = scan_;
  ++stats_.cells_contradicted;
  changed_.add(cell);  // the certainty, on which the foothold score depends, changes too
  const auto state = static_cast<CellState>(map.state_data()[slot]);
  if (state == CellState::measured) {
    float& certainty = map.certainty_data()[slot];
    certainty -= static_cast<float>(options_.certainty_decrement);
    if (certainty > 0.0f) return;
  }
  const float was = map.elevation_data()[slot];
  map.reset_slot(slot);
  ++stats_.cells_cleared;
  if (cleared_.size() < cleared_.capacity()) cleared_.push_back({cell, was});
}

}  // namespace stridemap
