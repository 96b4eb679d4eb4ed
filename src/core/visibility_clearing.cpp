#include "stridemap/core/visibility_clearing.hpp"

#include <algorithm>
#include <bit>
#include <cmath>
#include <limits>
#include <string>

#include "stridemap/core/error.hpp"
#include "stridemap/core/terrain_mapper.hpp"
#include "visibility_screen.hpp"

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
      stamp_(static_cast<std::size_t>(map.cells_per_side()) * static_cast<std::size_t>(map.cells_per_side()), 0),
      n_(map.cells_per_side()) {
  validate_visibility_options(options_);
  cleared_.reserve(std::min(stamp_.size(), kMaxRecordedCleared));
  const auto n = static_cast<std::size_t>(n_);
  floor_log2_.assign(n + 1, 0);
  for (std::size_t k = 2; k <= n; ++k) floor_log2_[k] = static_cast<std::uint8_t>(floor_log2_[k / 2] + 1);
  const std::size_t levels = static_cast<std::size_t>(floor_log2_[n]) + 1;
  row_max_.assign(levels * n, -std::numeric_limits<float>::infinity());
  column_max_.assign(levels * n, -std::numeric_limits<float>::infinity());
  slot_row_max_.assign(n, -std::numeric_limits<float>::infinity());
  slot_column_max_.assign(n, -std::numeric_limits<float>::infinity());
  tables_rows_.assign(n, 0.0f);
  tables_columns_.assign(n, 0.0f);
  retake_row_.assign(n, 0);
  retake_column_.assign(n, 0);
  column_holder_.assign(n, 0);
}

void VisibilityClearing::begin_scan(const ElevationMap& map) {
  start(map);
  seen_mapper_ = 0;  // followed no mapper: the next begin_scan(mapper) looks at the whole map
  take_maxima(map);
  build_tables();
  stats_.maxima_from_whole_map = true;
}

void VisibilityClearing::begin_scan(const TerrainMapper& mapper) {
  const ElevationMap& map = mapper.map();
  if (map.cells_per_side() != n_) start(map);  // throws
  const MapChanges changes = mapper.changes();
  // The rows hold every change since the last look when nothing uncounted
  // happened and they were not cleared of a scan not yet seen here; the
  // last scan's own clears must all be listed to be accounted for.
  const bool follow = seen_mapper_ != 0 && changes.mapper == seen_mapper_ &&
                      changes.unrecorded == seen_unrecorded_ && changes.record_from_scan <= seen_scans_ &&
                      stats_.cells_cleared == cleared_.size();
  const bool kept = follow && update_maxima(mapper);  // before start(): it reads the last scan's clears
  start(map);
  if (!kept) take_maxima(map);
  build_tables();
  stats_.maxima_from_whole_map = !kept;
  seen_mapper_ = changes.mapper;
  seen_unrecorded_ = changes.unrecorded;
  seen_scans_ = changes.scans;
}

void VisibilityClearing::start(const ElevationMap& map) {
  if (map.cells_per_side() != n_) {
    throw InputError("visibility: the map has " + std::to_string(map.cells_per_side()) +
                     " cells a side, the clean-up was made for " + std::to_string(n_));
  }
  if (++scan_ == 0) {  // after 2^32 scans: old stamps could match again
    std::fill(stamp_.begin(), stamp_.end(), 0u);
    scan_ = 1;
  }
  ++scans_;
  have_last_hit_ = false;
  cleared_.clear();
  changed_.clear();
  stats_ = {};
  // The window stays where it is for the scan: its corner and that
  // corner's slot are taken once.
  corner_ = map.min_cell();
  const auto corner_slot = static_cast<std::int64_t>(map.slot(corner_));
  slot_x0_ = corner_slot / n_;
  slot_y0_ = corner_slot % n_;
  const double cell = map.cell_size_m();
  inverse_cell_ = 1.0 / cell;
  relief_m_ = options_.relief_factor * cell;
  spacing_m2_ = spacing_m2(cell);
}


namespace {

// floor() without a call into libm, exact for |x| < 2^63 (the walk keeps
// its coordinates below 1e15 cells).
inline std::int64_t floor_index(double x) {
  const auto t = static_cast<std::int64_t>(x);
  return t - (x < static_cast<double>(t) ? 1 : 0);
}

// The walk's crossing parameters, each from its own cell boundary b (an
// integer, as a double): the same value wherever a walk starts.
inline double crossing(double b, double o, double inverse_d) { return (b - o) * inverse_d; }

// One axis of the walk: the cell index, the next boundary, and where the
// beam crosses it (inf for an axis the beam does not move along).
struct Axis {
  std::int64_t index = 0;
  std::int64_t step = 1;
  double s = 1.0;  // the step as a double
  double o = 0.0, inverse_d = 0.0;
  double boundary = 0.0;  // the next boundary's coordinate [cells]
  double next = 0.0;      // crossing(boundary)
  bool moves = false;

  /// o_index: floor(o_cells); inverse_d_cells: 1 / d_cells, any value for a 0.
  Axis(double o_cells, std::int64_t o_index, double d_cells, double inverse_d_cells)
      : index(o_index), o(o_cells), inverse_d(inverse_d_cells) {
    set_direction(d_cells);
    boundary = static_cast<double>(index + (d_cells > 0 ? 1 : 0));
    next = moves ? crossing(boundary, o, inverse_d) : std::numeric_limits<double>::infinity();
  }
  /// An axis already started, its next boundary and crossing known (its
  /// index not kept: the walk keeps its own).
  Axis(double o_cells, double d_cells, double inverse_d_cells, double next_boundary, double next_crossing)
      : o(o_cells), inverse_d(inverse_d_cells), boundary(next_boundary), next(next_crossing) {
    set_direction(d_cells);
  }
  void set_direction(double d_cells) {
    step = d_cells > 0 ? 1 : -1;
    s = d_cells > 0 ? 1.0 : -1.0;
    // A direction too small to invert never reaches a boundary in the beam.
    moves = d_cells != 0.0 && std::isfinite(inverse_d);
  }
  /// Whether the window-local index `local` (0..n-1 inside) lies beyond the
  /// window on the side this axis moves to, or outside an axis it never
  /// moves along: no later cell of the walk is then inside.
  bool left(std::int64_t local, std::int64_t n) const {
    return local >= n ? (step > 0 || !moves) : local < 0 && (step < 0 || !moves);
  }
  void advance() {
    index += step;
    boundary += s;
    next = crossing(boundary, o, inverse_d);
  }
  /// Moves past every boundary crossed at or before t (t finite, within the
  /// beam), as the full walk would have; returns the last such crossing,
  /// or -inf when there was none.
  double skip_to(double t, double d_cells) {
    constexpr double kNone = -std::numeric_limits<double>::infinity();
    if (!moves || !(next <= t)) return kNone;
    // First guess from the line, then set right with the same formula: the
    // crossings grow along the step, and the next boundary's is <= t, so
    // the boundary sought lies a step on or more, and the search back
    // stops at the next one without a bound of its own.
    const double at = o + t * d_cells;
    const double nearest = boundary + s;
    double target = static_cast<double>(step > 0 ? floor_index(at) + 1 : -floor_index(-at) - 1);
    if ((target - nearest) * s < 0.0) target = nearest;
    double before = crossing(target - s, o, inverse_d);
    while (before > t) {
      target -= s;
      before = crossing(target - s, o, inverse_d);
    }
    double after = crossing(target, o, inverse_d);
    while (after <= t) {
      before = after;
      target += s;
      after = crossing(target, o, inverse_d);
    }
    index += static_cast<std::int64_t>(target - boundary);  // one cell per boundary, in the step's direction
    boundary = target;
    next = after;
    return before;
  }
};

// Narrows the walk of a beam to [t_skip, t_last]: where a cell as high as
// `top` (the bound of the rows and columns crossed, lowered as the walk
// shrinks) can first (falling beam) or last (rising beam) lie above the
// beam by more than the margin. False when no cell can.
template <typename Bound, typename Clearance>
[[gnu::always_inline]] inline bool narrow_walk(double dz, double t_stop, double& top, const Bound& bound,
                                               const Clearance& clearance, double& t_skip, double& t_last) {
  constexpr double kNoBound = -std::numeric_limits<double>::infinity();
  if (dz < 0.0) {
    t_skip = clearance(top) / -dz;
    if (!(t_skip < t_stop)) return false;
    // What is left of the walk crosses fewer rows and columns, whose bound
    // may be lower and move the start on again (four times at most: nearly
    // every beam is settled by then, its walk ended early or left out).
    for (int round = 0; round < 4; ++round) {
      const double lower = bound(std::max(t_skip, 0.0), t_stop);
      if (!(lower > kNoBound)) return false;
      if (!(lower < top)) break;
      top = lower;
      t_skip = clearance(top) / -dz;
      if (!(t_skip < t_stop)) return false;
    }
  } else if (dz > 0.0) {
    if (!(clearance(top) < 0.0)) return false;
    t_last = -clearance(top) / dz;
    for (int round = 0; round < 4; ++round) {  // the same for the end of a rising beam's walk
      const double lower = bound(0.0, std::min(t_last, t_stop));
      if (!(lower > kNoBound)) return false;
      if (!(lower < top)) break;
      top = lower;
      if (!(clearance(top) < 0.0)) return false;
      t_last = -clearance(top) / dz;
    }
  } else {  // a level beam: above the window's bound, or above its rows' and columns'
    if (!(clearance(top) < 0.0)) return false;
    top = bound(0.0, t_stop);
    if (!(top > kNoBound) || !(clearance(top) < 0.0)) return false;
  }
  return true;
}


}  // namespace

namespace {

// A stop this many ranges past the hit (a range error below -1000 ranges)
// is no sensor's, and the walk's places along such a beam could leave what
// its cell indices hold.
constexpr double kMaxStopPastHit = 1000.0;

// A beam is traced when its range is positive and finite (its square tells
// as the range would), both its errors are finite and its stop lies at most
// kMaxStopPastHit ranges past its hit; any other leaves no trace, not even
// for the thinning.
inline bool traceable(double range2, double range_error_m, double height_error_m) {
  return range2 > 0.0 && range2 < std::numeric_limits<double>::infinity() && std::isfinite(range_error_m) &&
         std::isfinite(height_error_m) &&
         (range_error_m >= 0.0 || range_error_m * range_error_m <= kMaxStopPastHit * kMaxStopPastHit * range2);
}

// A rising beam's walk ends with the last cell ending before t_last: the
// one ending at or before the double just below it, and never past the stop.
inline double rising_walk_end(double t_stop, double t_last) {
  return std::min(t_stop, std::nextafter(t_last, -std::numeric_limits<double>::infinity()));
}

}  // namespace

// Inlined into both callers: for a fan, the loop over its beams then keeps
// the scan's constants in registers.
[[gnu::always_inline]] inline void VisibilityClearing::trace_from(ElevationMap& map, const Eigen::Vector3d& origin_m,
                                                                  const Eigen::Vector3d& hit_m, double range_error_m,
                                                                  double height_error_m) {
  // An invalid beam is left out here as a thinned one is by trace(): neither
  // changes any state. The range's square tells a valid beam as the range
  // would (norm() is its root), and most beams are settled before the root
  // is needed. The origin was found finite by the caller.
  const Eigen::Vector3d d = hit_m - origin_m;
  const double range2 = d.squaredNorm();
  if (!traceable(range2, range_error_m, height_error_m)) return;
  have_last_hit_ = true;
  last_hit_ = hit_m.head<2>();
  ++stats_.beams_traced;
  trace_valid(map, origin_m, d, range2, range_error_m, height_error_m);
}

[[gnu::always_inline]] inline void VisibilityClearing::trace_valid(ElevationMap& map, const Eigen::Vector3d& origin_m,
                                                                   const Eigen::Vector3d& d, double range2,
                                                                   double range_error_m, double height_error_m) {
  const double margin = options_.uncertainty_factor * height_error_m + relief_m_;
  const double z0 = origin_m.z(), dz = d.z();
  // The beam's height over a bound at t = 0, less the margin. The slack
  // outweighs the rounding of both this and the walk's own comparison, so
  // that no cell the full walk would contradict is skipped.
  const double slack_sum = 1.0 + std::abs(z0) + std::abs(dz) + std::abs(margin);
  const auto clearance = [&](double bound_m) {
    const double slack = 1e-9 * (slack_sum + std::abs(bound_m));
    return z0 + margin - (bound_m + slack);
  };
  // Nothing known in the window (-inf: a NaN clearance), or no cell as high
  // as its highest that the beam could pass below: a falling beam comes down
  // to it only at t >= 1, past its stop when the range error is >= 0; a
  // rising or level beam starts above it.
  double top = window_top_;
  if (dz < 0.0 ? range_error_m >= 0.0 && !(clearance(top) < -dz) : !(clearance(top) < 0.0)) return;

  // Only the part of the beam that cannot hold the true surface.
  const double t_stop = 1.0 - range_error_m / std::sqrt(range2);
  if (!(t_stop > 0.0)) return;

  const double inverse_cell = inverse_cell_;
  const double ox = origin_m.x() * inverse_cell, oy = origin_m.y() * inverse_cell;
  const double dx = d.x() * inverse_cell, dy = d.y() * inverse_cell;
  // Far outside any window the index arithmetic below would overflow.
  constexpr double kMaxIndex = 1e15;
  if (!(std::abs(ox) < kMaxIndex && std::abs(oy) < kMaxIndex && std::abs(ox + dx) < kMaxIndex &&
        std::abs(oy + dy) < kMaxIndex)) {
    return;
  }
  const std::int64_t n = n_;
  const CellIndex corner = corner_;

  // The highest known elevation of the window's rows and columns the beam
  // crosses from t0 to t1 (its cells there lie between its places at t0 and
  // t1, one more each way for rounding): an upper bound for every cell the
  // walk visits between them; -inf when none of them is in the window or
  // known. t0 <= t1, so the direction tells which place is lower.
  const auto bound = [&](double t0, double t1) {
    constexpr float kNone = -std::numeric_limits<float>::infinity();
    const double x0 = ox + dx * t0, x1 = ox + dx * t1, y0 = oy + dy * t0, y1 = oy + dy * t1;
    const std::int64_t lo_i = std::max<std::int64_t>(floor_index(dx < 0.0 ? x1 : x0) - 1 - corner.x, 0);
    const std::int64_t hi_i = std::min<std::int64_t>(floor_index(dx < 0.0 ? x0 : x1) + 1 - corner.x, n - 1);
    const std::int64_t lo_j = std::max<std::int64_t>(floor_index(dy < 0.0 ? y1 : y0) - 1 - corner.y, 0);
    const std::int64_t hi_j = std::min<std::int64_t>(floor_index(dy < 0.0 ? y0 : y1) + 1 - corner.y, n - 1);
    if (lo_i > hi_i || lo_j > hi_j) return kNone;
    return std::min(range_max(row_max_, lo_i, hi_i), range_max(column_max_, lo_j, hi_j));
  };
  double t_skip = -1.0;                                     // cells ending at or before it cannot be contradicted
  double t_last = std::numeric_limits<double>::infinity();  // nor cells ending at or after it
  if (!narrow_walk(dz, t_stop, top, bound, clearance, t_skip, t_last)) return;
  if (dz > 0.0) {
    const double t_end = rising_walk_end(t_stop, t_last);
    walk<true>(map, {ox, oy, floor_index(ox), floor_index(oy), dx, dy, 1.0 / dx, 1.0 / dy, z0, dz, margin, t_skip,
                     t_end});
  } else {
    walk<false>(map, {ox, oy, floor_index(ox), floor_index(oy), dx, dy, 1.0 / dx, 1.0 / dy, z0, dz, margin, t_skip,
                      t_stop});
  }
}

template <bool kRising>
inline void VisibilityClearing::walk(ElevationMap& map, const WalkBeam& beam) {
  const double z0 = beam.z0, dz = beam.dz, margin = beam.margin, t_skip = beam.t_skip, t_end = beam.t_end;
  Axis ax = beam.started ? Axis(beam.ox, beam.dx, beam.inverse_dx, beam.boundary_x, beam.next_x)
                          : Axis(beam.ox, beam.ix, beam.dx, beam.inverse_dx);
  Axis ay = beam.started ? Axis(beam.oy, beam.dy, beam.inverse_dy, beam.boundary_y, beam.next_y)
                          : Axis(beam.oy, beam.iy, beam.dy, beam.inverse_dy);

  const std::int64_t n = n_;
  const CellIndex corner = corner_;
  const float* elevation = map.elevation_data();
  std::size_t crossed = 0;
  // The window-local indices, and the slot row (times n) and column they
  // fall in whether inside or not, moved along with the walk.
  double t_in = beam.t_in;
  std::int64_t i = beam.i, j = beam.j, row = beam.row, column = beam.column;
  if (!beam.started) {
    if (t_skip > 0.0) t_in = std::max(0.0, std::max(ax.skip_to(t_skip, beam.dx), ay.skip_to(t_skip, beam.dy)));
    i = ax.index - corner.x;
    j = ay.index - corner.y;
    // A walk nearly always starts inside the window: no division then.
    const auto slot_of = [n](std::int64_t x) {
      return static_cast<std::uint64_t>(x) < static_cast<std::uint64_t>(2 * n)
                 ? x - (x >= n ? n : 0)
                 : static_cast<std::int64_t>(visibility::wrap_index(x, n));
    };
    row = slot_of(slot_x0_ + i) * n;
    column = slot_of(slot_y0_ + j);
  }
  // Past the window's last slot row (column) the walk goes on from its
  // first, and the other way round: one comparison for the way it moves.
  const std::int64_t row_step = ax.step * n, rows_end = n * n;
  const std::int64_t row_wrap = ax.step > 0 ? rows_end : -n, row_reset = ax.step > 0 ? 0 : rows_end - n;
  const std::int64_t column_wrap = ay.step > 0 ? n : -1, column_reset = ay.step > 0 ? 0 : n - 1;
  while (true) {
    const double t_out = std::min(ax.next, ay.next);
    if (!(t_out <= t_end)) break;
    // Both inside 0..n-1 at once, as unsigned.
    if (static_cast<std::uint64_t>(i) < static_cast<std::uint64_t>(n) &&
        static_cast<std::uint64_t>(j) < static_cast<std::uint64_t>(n)) {
      ++crossed;
      const auto s = static_cast<std::size_t>(row + column);
      // The beam's highest point over the cell: its exit rising, its entry falling.
      const double z_beam_max = z0 + dz * (kRising ? t_out : t_in);
      // NaN (unknown) fails the comparison: nothing to clear.
      if (elevation[s] > z_beam_max + margin) contradict(map, {corner.x + i, corner.y + j}, s);
    } else if (ax.left(i, n) || ay.left(j, n)) {
      break;  // out of the window for good: every cell from here lies outside
    }
    t_in = t_out;
    if (ax.next < ay.next) {
      ax.advance();
      i += ax.step;
      row += row_step;
      row = row == row_wrap ? row_reset : row;
    } else {
      ay.advance();
      j += ay.step;
      column += ay.step;
      column = column == column_wrap ? column_reset : column;
    }
  }
  stats_.cells_crossed += crossed;
}

void VisibilityClearing::trace_unthinned(ElevationMap& map, const VisibilityBeam& beam) {
  if (beam.origin_m.allFinite()) trace_from(map, beam.origin_m, beam.hit_m, beam.range_error_m, beam.height_error_m);
}

void VisibilityClearing::trace_fan(ElevationMap& map, const VisibilityFan& fan) {
  if (!fan.origin_m.allFinite()) return;  // no beam of the fan is valid
  // Locals, which the traces' stores cannot change: kept in registers.
  const Eigen::Vector3d origin_m = fan.origin_m;
  const double *x_m = fan.x_m, *y_m = fan.y_m, *z_m = fan.z_m;
  const double *range_error_m = fan.range_error_m, *height_error_m = fan.height_error_m;
  const std::size_t count = fan.count;
  // The screen's index arithmetic in doubles needs the corner well inside
  // 2^53 (the walk's own limit keeps the origin below 1e15 cells), its
  // range lengths as floats and table indices as int32 a side below 2^24.
  constexpr double kMaxCorner = 1e15;
  const bool screen = visibility::screen_available() && std::abs(static_cast<double>(corner_.x)) < kMaxCorner &&
                      std::abs(static_cast<double>(corner_.y)) < kMaxCorner && n_ < (1 << 24);
  if (!screen) {
    for (std::size_t k = 0; k < count; ++k) {
      if (thinned(x_m[k], y_m[k])) continue;
      trace_from(map, origin_m, {x_m[k], y_m[k], z_m[k]}, range_error_m[k], height_error_m[k]);
    }
    return;
  }
  visibility::ScreenScan scan;
  scan.z0 = origin_m.z();
  scan.inverse_cell = inverse_cell_;
  scan.ox = origin_m.x() * inverse_cell_;
  scan.oy = origin_m.y() * inverse_cell_;
  scan.uncertainty_factor = options_.uncertainty_factor;
  scan.relief_m = relief_m_;
  scan.one_abs_z0 = 1.0 + std::abs(scan.z0);
  scan.top = window_top_;
  scan.corner_x = static_cast<double>(corner_.x);
  scan.corner_y = static_cast<double>(corner_.y);
  scan.last_index = static_cast<double>(n_ - 1);
  scan.n = n_;
  scan.row_max = row_max_.data();
  scan.column_max = column_max_.data();
  // An origin this far out ends every beam before its walk.
  constexpr double kMaxIndex = 1e15;
  const bool origin_far = !(std::abs(scan.ox) < kMaxIndex && std::abs(scan.oy) < kMaxIndex);
  // The origin's cell, for every walk of the fan.
  const std::int64_t ix = origin_far ? 0 : floor_index(scan.ox), iy = origin_far ? 0 : floor_index(scan.oy);
  scan.origin_cell_x = static_cast<double>(ix);
  scan.origin_cell_y = static_cast<double>(iy);
  scan.slot_x0 = static_cast<double>(slot_x0_);
  scan.slot_y0 = static_cast<double>(slot_y0_);
  // On the stack (about 14 kB): nothing allocated per scan.
  visibility::ScreenBatch batch;
  // No last hit as NaN, to which no distance is below the spacing.
  constexpr double kNoHit = std::numeric_limits<double>::quiet_NaN();
  double last_x = have_last_hit_ ? last_hit_.x() : kNoHit, last_y = have_last_hit_ ? last_hit_.y() : kNoHit;
  const double spacing_m2 = spacing_m2_;
  std::size_t k = 0;
  while (k < count) {
    // The beams trace_from() would trace, in order: the thinning follows
    // the last valid beam whatever its walk does.
    std::size_t m = 0;
    while (k < count) {
      const std::size_t at = k++;
      const double x = x_m[at], y = y_m[at];
      const double ex = x - last_x, ey = y - last_y;
      if (ex * ex + ey * ey < spacing_m2) continue;
      const Eigen::Vector3d d = Eigen::Vector3d(x, y, z_m[at]) - origin_m;
      const double range2 = d.squaredNorm();
      const double range_error = range_error_m[at], height_error = height_error_m[at];
      if (!traceable(range2, range_error, height_error)) continue;
      last_x = x;
      last_y = y;
      batch.dx_m[m] = d.x();
      batch.dy_m[m] = d.y();
      batch.dz_m[m] = d.z();
      batch.range2[m] = range2;
      batch.range_error_m[m] = range_error;
      batch.height_error_m[m] = height_error;
      if (++m == visibility::kScreenBeams) break;
    }
    if (m == 0) break;
    stats_.beams_traced += m;
    if (origin_far) continue;
    for (std::size_t p = m; p % 4 != 0; ++p) {  // padding: copies of the last beam, results unused
      batch.dx_m[p] = batch.dx_m[m - 1];
      batch.dy_m[p] = batch.dy_m[m - 1];
      batch.dz_m[p] = batch.dz_m[m - 1];
      batch.range2[p] = batch.range2[m - 1];
      batch.range_error_m[p] = batch.range_error_m[m - 1];
      batch.height_error_m[p] = batch.height_error_m[m - 1];
    }
    visibility::screen(scan, batch, m);
    // A walk's arguments, its start from the screen where it found it.
    const auto walk_beam = [&](std::size_t p, double t_end) {
      WalkBeam beam{scan.ox, scan.oy, ix, iy, batch.dx_cells[p], batch.dy_cells[p], batch.inverse_dx[p],
                    batch.inverse_dy[p], scan.z0, batch.dz_m[p], batch.margin_m[p], batch.t_skip[p], t_end};
      if (batch.started[p / 4] >> (p % 4) & 1u) {
        beam.started = true;
        beam.i = static_cast<std::int64_t>(batch.start_i[p]);
        beam.j = static_cast<std::int64_t>(batch.start_j[p]);
        beam.row = static_cast<std::int64_t>(batch.start_row[p]);
        beam.column = static_cast<std::int64_t>(batch.start_column[p]);
        beam.boundary_x = batch.boundary_x[p];
        beam.boundary_y = batch.boundary_y[p];
        beam.next_x = batch.next_x[p];
        beam.next_y = batch.next_y[p];
        beam.t_in = batch.t_in[p];
      }
      return beam;
    };
    // The rest walk in the fan's order: a walk reads the cells the walks
    // before it may have cleared.
    for (std::size_t v = 0; v < m; v += 4) {
      for (unsigned rest = ~batch.settled[v / 4] & 15u; rest != 0; rest &= rest - 1) {
        const std::size_t p = v + static_cast<std::size_t>(std::countr_zero(rest));
        if (p >= m) break;
        const double dz = batch.dz_m[p];
        if (batch.left[v / 4] >> (p - v) & 1u) {
          trace_valid(map, origin_m, {batch.dx_m[p], batch.dy_m[p], dz}, batch.range2[p], batch.range_error_m[p],
                      batch.height_error_m[p]);
        } else if (dz > 0.0) {
          const double t_end = rising_walk_end(batch.t_stop[p], batch.t_last[p]);
          walk<true>(map, walk_beam(p, t_end));
        } else {
          walk<false>(map, walk_beam(p, batch.t_stop[p]));
        }
      }
    }
  }
  if (!std::isnan(last_x)) {
    have_last_hit_ = true;
    last_hit_ = {last_x, last_y};
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
  map.forget_measurement(slot);
  ++stats_.cells_cleared;
  if (cleared_.size() < cleared_.capacity()) cleared_.push_back({cell, was});
}

}  // namespace stridemap
