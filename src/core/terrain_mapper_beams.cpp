// TerrainMapper's packed per-point path (core/planar_beams.hpp). Two passes
// per scan: the geometry of every valid beam (eq. 5, 6, 7 and Fig. 10, then
// the cell it falls in) as straight-line code over arrays, which the
// compiler turns into vector instructions, then the cell updates of eq. (9)
// and (10) in beam order. The arithmetic is PlanarBeamGeometry::point's and
// ElevationMap::slot_at's, operation for operation, so the maps are those of
// the per-point path bit for bit (tests/core/packed_beams_test.cpp).
// This file is built with -fno-math-errno and -fno-trapping-math
// (src/CMakeLists.txt): sqrt then needs no error branch and the selects of
// the first pass become vector blends, so that it vectorises. Neither
// changes a result; nothing reads errno or floating-point traps.
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <limits>

#include "stridemap/core/terrain_mapper.hpp"

// x86-64's baseline (SSE2) holds two doubles per vector and has no blend;
// where the CPU has AVX2 the first pass runs a copy built for it (4 lanes,
// blends), chosen once when the library loads. No FMA is enabled, so every
// operation rounds as in the baseline copy and the maps stay bit-identical.
// STRIDEMAP_NO_AVX2_COPIES (a compile definition) leaves the baseline copy
// alone, to test and count it on a CPU that has AVX2.
#if defined(__x86_64__) && defined(__GNUC__) && !defined(__clang__) && defined(__linux__) && \
    !defined(STRIDEMAP_NO_AVX2_COPIES)
#define STRIDEMAP_VECTOR_CLONES __attribute__((target_clones("avx2", "default")))
#else
#define STRIDEMAP_VECTOR_CLONES
#endif

namespace stridemap {
namespace {

// An outside point's row: beyond the largest window's rows.
constexpr double kOutsideRow = 1.0e9;
static_assert(kOutsideRow >= kMaxGridCellsPerSide && kOutsideRow < 2147483647.0, "an outside row must fit in int32");

}  // namespace

template <TerrainMapper::Turning kTurning, bool kCheckXY, bool kKeepHits>
STRIDEMAP_VECTOR_CLONES void TerrainMapper::locate_beams(const PlanarBeams& beams, const PlanarBeamGeometry& g,
                                 const MaxElevationChange& bound, const Eigen::Vector3d& origin) {
  // Everything the loop reads lives in locals, so that the compiler sees
  // that the output arrays alias none of it.
  const double fx = g.forward.x(), fy = g.forward.y(), fz = g.forward.z();
  const double lx = g.left.x(), ly = g.left.y(), lz = g.left.z();
  const double front_range = g.at_front.d_range, left_range = g.at_left.d_range;
  const double front_pitch = g.at_front.d_pitch_m_per_rad, left_pitch = g.at_left.d_pitch_m_per_rad;
  const double front_roll = g.at_front.d_roll_m_per_rad, left_roll = g.at_left.d_roll_m_per_rad;
  const double front_alpha = g.at_front.d_alpha_m_per_rad, left_alpha = g.at_left.d_alpha_m_per_rad;
  const double lever_pitch = g.lever.d_pitch_m_per_rad, lever_roll = g.lever.d_roll_m_per_rad;
  const double k_roll = options_.update.max_roll_error_rad, k_pitch = options_.update.max_pitch_error_rad;
  const double k_alpha = options_.update.max_mount_pitch_error_rad;
  const double travel = bound.travel_term_m(), turn_per_m = bound.turn_term_per_m(),
               turn_offset = bound.turn_offset_m();
  const double lateral_per_m = bound.lateral_term_per_m(), cos_yaw = bound.cos_yaw(), sin_yaw = bound.sin_yaw(),
               mount_lateral = bound.mount_lateral_m();
  const double x0 = origin.x(), y0 = origin.y(), z0 = origin.z();
  const double inverse_cell = 1.0 / map_.cell_size_m();
  const auto n = static_cast<double>(map_.cells_per_side());
  const auto lo_x = static_cast<double>(map_.min_cell().x), lo_y = static_cast<double>(map_.min_cell().y);
  const double lo_x_1 = lo_x + 1.0, lo_y_1 = lo_y + 1.0;
  constexpr double kMaxCoordinate_m = 1.0e6;  // as apply()
  constexpr double kInf = std::numeric_limits<double>::infinity();  // a NaN turning term's bound
  constexpr double kRound = 6755399441055744.0;  // 1.5 * 2^52

  const double* __restrict range = beams.range_m.data();
  const double* __restrict range_error = beams.range_error_m.data();
  const double* __restrict cos_t = beams.cos_angle.data();
  const double* __restrict sin_t = beams.sin_angle.data();
  std::int32_t* __restrict row_out = located_row_.data();
  std::int32_t* __restrict column_out = located_column_.data();
  float* __restrict h_out = located_h_m_.data();
  float* __restrict dz_out = located_dz_max_m_.data();
  double* __restrict x_out = hit_x_m_.data();
  double* __restrict y_out = hit_y_m_.data();
  double* __restrict z_out = hit_z_m_.data();
  double* __restrict error_out = hit_error_m_.data();
  const std::size_t count = beams.count;
  // With the hits kept, twelve arrays are more than GCC keeps apart by
  // restrict alone (it asks to version the loop for aliasing and gives up);
  // every one is its own vector, so no store can reach another beam's load.
#if defined(__GNUC__) && !defined(__clang__)
#pragma GCC ivdep
#endif
  for (std::size_t k = 0; k < count; ++k) {
    const double r = range[k], dr = range_error[k], ct = cos_t[k], st = sin_t[k];
    // PlanarBeamGeometry::point, written out per coordinate.
    const double ox = r * (ct * fx + st * lx), oy = r * (ct * fy + st * ly), oz = r * (ct * fz + st * lz);
    const double d_range = ct * front_range + st * left_range;
    const double d_pitch = lever_pitch + r * (ct * front_pitch + st * left_pitch);
    const double d_roll = lever_roll + r * (ct * front_roll + st * left_roll);
    const double d_alpha = r * (ct * front_alpha + st * left_alpha);
    // elevation_error_bound_m; fabs differs from its v < 0 ? -v : v only
    // in the sign of a zero term, which no sum below can see.
    const double error = std::fabs(d_range * dr) + std::fabs(d_roll) * k_roll + std::fabs(d_pitch) * k_pitch +
                         std::fabs(d_alpha) * k_alpha;
    // MaxElevationChange::at.
    double dz = travel + error;
    if constexpr (kTurning != Turning::none) {
      // A finite turn_per_m (> 0 here) times a sum >= 0 (finite or +inf:
      // the beam's terms are finite) is never NaN; only an unbounded one
      // times 0 is.
      const double turn = turn_per_m * (std::sqrt(ox * ox + oy * oy) + turn_offset);
      if constexpr (kTurning == Turning::unbounded) {
        dz += turn != turn ? kInf : turn;
      } else {
        dz += turn;
      }
      const double lateral = -sin_yaw * ox + cos_yaw * oy + mount_lateral;
      // fabs: only a zero's sign differs, and dz >= +0 here absorbs it.
      dz += lateral_per_m * std::fabs(lateral);
    }
    const double x = x0 + ox, y = y0 + oy, h = z0 + oz;
    // apply()'s range check and ElevationMap::slot_at, in doubles so that
    // the loop stays one vector type. floor() is round-to-nearest by the
    // 1.5 * 2^52 trick, less one where that rounded up: exact for cell
    // indices below 2^51, which every point within the range check has
    // (integrate() checked the window's fit in 2^30). A point is in the
    // window when its floored cell is (the corner is a whole cell, so that is
    // slot_at's cx >= lo_x && cx < lo_x + n); NaN fails every comparison.
    // The cell's row and column from the window's corner (exact integers
    // below n); update_located() turns them into the slot. Outside: a row
    // beyond every window's.
    const double cx = x * inverse_cell, cy = y * inverse_cell;
    const double rx = (cx + kRound) - kRound, ry = (cy + kRound) - kRound;
    // rx - (rx > cx) - lo as rx - (lo or lo + 1): one operation fewer, and
    // the same number wherever it can fall in the window (integers far
    // below 2^53 are exact either way; beyond, both are far outside).
    const double i = rx - (rx > cx ? lo_x_1 : lo_x), j = ry - (ry > cy ? lo_y_1 : lo_y);
    // Without kCheckXY the window lies where every cell's x and y are within
    // the range check's bound (integrate() made sure), so the cell test
    // implies theirs.
    bool inside = (std::fabs(h) < kMaxCoordinate_m) & (i >= 0.0) & (i < n) & (j >= 0.0) & (j < n);
    if constexpr (kCheckXY) inside = inside & (std::fabs(x) < kMaxCoordinate_m) & (std::fabs(y) < kMaxCoordinate_m);
    row_out[k] = static_cast<std::int32_t>(inside ? i : kOutsideRow);
    column_out[k] = static_cast<std::int32_t>(inside ? j : 0.0);
    // Such a point's h_m and Delta z_max are never read; beyond float's
    // range their conversion gives an infinity (IEEE 754; no sanitizer
    // checks a conversion between floating types), and a select here would
    // keep the loop from vectorising.
    h_out[k] = static_cast<float>(h);
    dz_out[k] = static_cast<float>(dz);
    if constexpr (kKeepHits) {
      x_out[k] = x;
      y_out[k] = y;
      z_out[k] = h;
      error_out[k] = error;
    }
  }
}

template <bool kKeepHits>
void TerrainMapper::locate_beams_for(Turning turning, bool check_xy, const PlanarBeams& beams,
                                     const PlanarBeamGeometry& geometry, const MaxElevationChange& bound,
                                     const Eigen::Vector3d& origin) {
  constexpr Turning kNone = Turning::none, kFinite = Turning::finite, kUnbounded = Turning::unbounded;
  if (check_xy) {
    if (turning == kNone) locate_beams<kNone, true, kKeepHits>(beams, geometry, bound, origin);
    if (turning == kFinite) locate_beams<kFinite, true, kKeepHits>(beams, geometry, bound, origin);
    if (turning == kUnbounded) locate_beams<kUnbounded, true, kKeepHits>(beams, geometry, bound, origin);
  } else {
    if (turning == kNone) locate_beams<kNone, false, kKeepHits>(beams, geometry, bound, origin);
    if (turning == kFinite) locate_beams<kFinite, false, kKeepHits>(beams, geometry, bound, origin);
    if (turning == kUnbounded) locate_beams<kUnbounded, false, kKeepHits>(beams, geometry, bound, origin);
  }
}

void TerrainMapper::update_located(std::size_t count, ScanStats& stats) {
  const std::int32_t n = map_.cells_per_side();
  const auto un = static_cast<std::size_t>(n);
  // Slot of a window-local row and column: the circular buffer's wrap as
  // two tables, remade only when the window's corner slot changes.
  const std::size_t corner_slot = map_.slot(map_.min_cell());
  if (row_slot_.size() != un || corner_slot != tables_corner_slot_) {
    row_slot_.resize(un);
    column_slot_.resize(un);
    const std::size_t slot_x = corner_slot / un, slot_y = corner_slot % un;
    for (std::size_t i = 0; i < un; ++i) {
      row_slot_[i] = static_cast<std::uint32_t>((i + slot_x) % un * un);
      column_slot_[i] = static_cast<std::uint32_t>((i + slot_y) % un);
    }
    tables_corner_slot_ = corner_slot;
  }
  if (row_lo_.size() != un) {  // once per window size
    row_lo_.assign(un, std::numeric_limits<std::int32_t>::max());
    row_hi_.assign(un, -1);
  }
  // Two loops, so that neither runs out of registers: the slots and the
  // changed columns per row first, then the cell updates. The first packs
  // each inside point's slot and beam index side by side, so that the cell
  // loop runs over inside points only and tests nothing.
  const std::int32_t* rows = located_row_.data();
  const std::int32_t* columns = located_column_.data();
  const std::uint32_t* row_slot = row_slot_.data();
  const std::uint32_t* column_slot = column_slot_.data();
  std::int32_t* row_lo = row_lo_.data();
  std::int32_t* row_hi = row_hi_.data();
  // Outside points come in runs at the scan's ends (beams beyond the
  // window's sides); skip those four at a time (every outside row is
  // kOutsideRow exactly), then test each point between.
  constexpr auto kOutside = static_cast<std::uint32_t>(kOutsideRow);
  constexpr std::uint64_t kOutsidePair = (std::uint64_t{kOutside} << 32) | kOutside;
  const auto four_outside = [rows](std::size_t k) {
    std::uint64_t a = 0, b = 0;
    std::memcpy(&a, rows + k, sizeof a);
    std::memcpy(&b, rows + k + 2, sizeof b);
    return ((a ^ kOutsidePair) | (b ^ kOutsidePair)) == 0;
  };
  std::size_t begin = 0, end = count;
  while (begin + 4 <= end && four_outside(begin)) begin += 4;
  while (end >= begin + 4 && four_outside(end - 4)) end -= 4;
  std::int32_t* slot_beam = located_slot_beam_.data();
  std::size_t inside = 0;
  for (std::size_t k = begin; k < end; ++k) {
    const std::int32_t i = rows[k];
    if (i >= n) continue;  // outside the window
    const std::int32_t j = columns[k];
    const auto ii = static_cast<std::size_t>(i);
    slot_beam[2 * inside] = static_cast<std::int32_t>(row_slot[ii] + column_slot[static_cast<std::size_t>(j)]);
    slot_beam[2 * inside + 1] = static_cast<std::int32_t>(k);
    ++inside;
    row_lo[ii] = std::min(row_lo[ii], j);
    row_hi[ii] = std::max(row_hi[ii], j);
  }
  if (inside > 0) {
    // The changed rows, window-local (a box in slot rows would break where
    // the circular window wraps): the first and last rows with a span,
    // found once per scan rather than tracked per point. A row without a
    // span holds (max, -1).
    std::int32_t lo_i = 0, hi_i = n - 1;
    while (row_hi[lo_i] < 0) ++lo_i;
    while (row_hi[hi_i] < 0) --hi_i;
    const CellIndex corner = map_.min_cell();
    const auto first = static_cast<std::size_t>(lo_i), rows_changed = static_cast<std::size_t>(hi_i - lo_i + 1);
    changed_.add(changed_rows_.add_spans(corner.x + lo_i, rows_changed, row_lo + first, row_hi + first, corner.y));
    std::fill(row_lo + first, row_lo + first + rows_changed, std::numeric_limits<std::int32_t>::max());
    std::fill(row_hi + first, row_hi + first + rows_changed, -1);
  }

  // Everything the loop reads lives in locals: the cell updates store
  // bytes (state, contradictions), which could alias any member.
  float* elevation = map_.elevation_data();
  float* certainty = map_.certainty_data();
  std::uint8_t* state = map_.state_data();
  float* pending = map_.pending_elevation_data();
  std::uint8_t* contradictions = map_.contradiction_data();
  float* mean = map_.mean_elevation_data();
  std::uint16_t* mean_count = map_.mean_count_data();
  const std::int32_t* slots_beams = located_slot_beam_.data();
  const float* h_m = located_h_m_.data();
  const float* dz_max_m = located_dz_max_m_.data();
  const UpdateOptions options = options_.update;
  std::size_t outcomes[4] = {0, 0, 0, 0};
  for (std::size_t q = 0; q < inside; ++q) {
    const auto s = static_cast<std::size_t>(slots_beams[2 * q]);
    const auto k = static_cast<std::size_t>(slots_beams[2 * q + 1]);
    const CellUpdate result = update_cell({elevation[s], certainty[s], state[s], pending[s], contradictions[s], mean[s],
                                           mean_count[s]},
                                          h_m[k], dz_max_m[k], options);
    ++outcomes[static_cast<std::size_t>(result)];
  }
  stats.outside_map += count - inside;
  stats.integrated += inside;
  stats.first += outcomes[static_cast<std::size_t>(CellUpdate::first)];
  stats.plausible += outcomes[static_cast<std::size_t>(CellUpdate::plausible)];
  stats.implausible += outcomes[static_cast<std::size_t>(CellUpdate::implausible)];
  stats.replaced += outcomes[static_cast<std::size_t>(CellUpdate::replaced)];
}

void TerrainMapper::integrate_far(const PlanarBeams& beams, const PlanarBeamGeometry& geometry,
                                  const MaxElevationChange& bound, const Eigen::Vector3d& origin, ScanStats& stats) {
  Eigen::Vector3d offset;
  double height_error = 0.0;
  for (std::size_t k = 0; k < beams.count; ++k) {
    geometry.point(beams.range_m[k], beams.range_error_m[k], beams.cos_angle[k], beams.sin_angle[k], options_.update,
                   offset, height_error);
    apply(origin.x() + offset.x(), origin.y() + offset.y(), origin.z() + offset.z(), bound.at(height_error, offset),
          stats);
  }
}

ScanStats TerrainMapper::integrate(const PlanarBeams& beams, const TrunkPose& pose) {
  ScanStats stats;
  stats.beams = beams.beams;
  if (!accept(pose, beams.time_s, stats)) return stats;
  // The per-scan trigonometry once: the heading's cosine and sine serve the
  // window, the sensor origin and Delta z_max's lateral term; M is kept;
  // the previous scan's origin too. The same doubles as each place made.
  const double cos_yaw = std::cos(pose.yaw_rad), sin_yaw = std::sin(pose.yaw_rad);
  follow(pose, cos_yaw, sin_yaw, stats);
  stats.invalid_range = beams.invalid_range;
  stats.invalid_beam = beams.invalid_beam;
  const PlanarBeamGeometry geometry(pose, mount_, mount_rotation_, cos_yaw, sin_yaw);
  const Eigen::Vector3d origin = sensor_origin_in_map(pose, mount_, cos_yaw, sin_yaw);
  const MaxElevationChange bound(motion_to(pose, origin), geometry.gamma_rad, mount_, options_.update, cos_yaw,
                                 sin_yaw);
  // The first pass indexes cells in 32 bits; a window beyond that (some
  // 20,000 km of 1 cm cells from the origin) takes the per-point way.
  constexpr std::int64_t kIndexLimit = std::int64_t{1} << 30;
  const CellIndex corner = map_.min_cell();
  if (std::abs(corner.x) >= kIndexLimit || std::abs(corner.y) >= kIndexLimit) {
    integrate_far(beams, geometry, bound, origin, stats);
  } else {
    if (located_row_.size() < beams.count) {  // grows once, as the beams did
      located_row_.resize(beams.range_m.size());
      located_column_.resize(beams.range_m.size());
      located_slot_beam_.resize(2 * beams.range_m.size());
      located_h_m_.resize(beams.range_m.size());
      located_dz_max_m_.resize(beams.range_m.size());
      hit_x_m_.resize(beams.range_m.size());
      hit_y_m_.resize(beams.range_m.size());
      hit_z_m_.resize(beams.range_m.size());
      hit_error_m_.resize(beams.range_m.size());
    }
    // A point the first pass finds in the window has cx = x / cell within
    // the window's corners give or take 2 (its rounding of cx is off by at
    // most 1 there); when that reach is below 1e6 m / cell, |x| < 1e6 follows
    // (rounding is monotonic: |x| >= 1e6 gives |cx| >= 1e6 / cell as
    // computed), so apply()'s x and y range checks can go. The z check stays.
    const double inverse_cell = 1.0 / map_.cell_size_m();
    const auto lo_x = static_cast<double>(corner.x), lo_y = static_cast<double>(corner.y);
    const auto n = static_cast<double>(map_.cells_per_side());
    const double reach =
        std::max(std::max(std::abs(lo_x), std::abs(lo_x + n)), std::max(std::abs(lo_y), std::abs(lo_y + n))) + 2.0;
    const bool check_xy = !(reach < 1.0e6 * inverse_cell);
    const double turn = bound.turn_term_per_m();
    const Turning turning = turn == 0.0 ? Turning::none : std::isfinite(turn) ? Turning::finite : Turning::unbounded;
    if (keep_hits_) {
      locate_beams_for<true>(turning, check_xy, beams, geometry, bound, origin);
      hits_ = {beams.beams, beams.count, beams.time_s, pose.yaw_rad, pose.pitch_rad, pose.roll_rad, origin,
               hit_x_m_.data(), hit_y_m_.data(), hit_z_m_.data(), hit_error_m_.data(), beams.range_error_m.data(),
               beams.range_m.data()};
      hits_valid_ = true;
    } else {
      locate_beams_for<false>(turning, check_xy, beams, geometry, bound, origin);
    }
    update_located(beams.count, stats);
  }
  finish(pose, beams.time_s, stats);
  previous_origin_ = origin;
  previous_origin_known_ = true;
  return stats;
}

}  // namespace stridemap
