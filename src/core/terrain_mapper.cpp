#include "stridemap/core/terrain_mapper.hpp"

#include <algorithm>
#include <atomic>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <limits>
#include <string>

#include "stridemap/core/error.hpp"

#if defined(__x86_64__)
#include <immintrin.h>

#include "stridemap/core/detail/kept_lanes_avx2.hpp"
#endif

namespace stridemap {
namespace {

void require_finite_non_negative(double value, const char* name) {
  if (!std::isfinite(value) || value < 0.0) {
    throw InputError(std::string("mapper options: ") + name + " must be a finite number >= 0, got " +
                     std::to_string(value));
  }
}

double wrap_angle(double a) { return std::remainder(a, 2.0 * std::numbers::pi); }

}  // namespace

namespace detail {
std::uint64_t MapperIdentity::next() noexcept {
  static std::atomic<std::uint64_t> last{0};
  return ++last;
}
}  // namespace detail

ScanStats& ScanStats::operator+=(const ScanStats& o) {
  beams += o.beams;
  integrated += o.integrated;
  first += o.first;
  plausible += o.plausible;
  implausible += o.implausible;
  replaced += o.replaced;
  invalid_range += o.invalid_range;
  invalid_beam += o.invalid_beam;
  outside_map += o.outside_map;
  pose_rejected = pose_rejected || o.pose_rejected;
  time_rejected = time_rejected || o.time_rejected;
  cells_reset_by_move += o.cells_reset_by_move;
  return *this;
}

MapperTotals& MapperTotals::operator+=(const MapperTotals& o) {
  scans += o.scans;
  scans_rejected_for_pose += o.scans_rejected_for_pose;
  scans_rejected_for_time += o.scans_rejected_for_time;
  beams += o.beams;
  integrated += o.integrated;
  invalid_range += o.invalid_range;
  invalid_beam += o.invalid_beam;
  outside_map += o.outside_map;
  implausible += o.implausible;
  return *this;
}

bool pose_is_finite(const TrunkPose& p) {
  return std::isfinite(p.x_m) && std::isfinite(p.y_m) && std::isfinite(p.yaw_rad) && std::isfinite(p.pitch_rad) &&
         std::isfinite(p.roll_rad) && std::isfinite(p.reference_elevation_m) && std::isfinite(p.height_change_m) &&
         (!p.z_m || std::isfinite(*p.z_m));
}

TerrainMapper::TerrainMapper(const MapperOptions& options, const SensorMount& mount)
    : options_(options),
      mount_(mount),
      map_(options.grid),
      changed_rows_(options.grid.cells_per_side),
      mount_rotation_(mount_rotation(mount)) {
  const UpdateOptions& u = options.update;
  if (!std::isfinite(u.certainty_increment) || u.certainty_increment <= 0.0) {
    throw InputError("mapper options: certainty_increment must be a positive number, got " +
                     std::to_string(u.certainty_increment));
  }
  if (!std::isfinite(u.certainty_max) || u.certainty_max < u.certainty_increment) {
    throw InputError("mapper options: certainty_max must be finite and >= certainty_increment, got " +
                     std::to_string(u.certainty_max));
  }
  if (u.replace_after_contradictions < 1 || u.replace_after_contradictions > 255) {
    throw InputError("mapper options: replace_after_contradictions must be between 1 and 255, got " +
                     std::to_string(u.replace_after_contradictions));
  }
  require_finite_non_negative(u.max_pitch_error_rad, "max_pitch_error_rad");
  require_finite_non_negative(u.max_roll_error_rad, "max_roll_error_rad");
  require_finite_non_negative(u.max_mount_pitch_error_rad, "max_mount_pitch_error_rad");
  if (!std::isfinite(options.window_ahead_m)) {
    throw InputError("mapper options: window_ahead_m must be finite");
  }
  if (!std::isfinite(mount.height_m) || !std::isfinite(mount.pitch_rad) || !std::isfinite(mount.forward_offset_m) ||
      !std::isfinite(mount.lateral_offset_m) || !std::isfinite(mount.roll_rad) || !std::isfinite(mount.yaw_rad)) {
    throw InputError("sensor mount: every field must be finite");
  }
  if (std::abs(mount.pitch_rad) >= std::numbers::pi / 2) {
    throw InputError("sensor mount: pitch_rad must lie strictly between -90 and 90 deg, got " +
                     std::to_string(mount.pitch_rad) + " rad");
  }
}

ScanMotion TerrainMapper::motion_to(const TrunkPose& pose) const {
  if (!previous_pose_) return {};
  return motion_to(pose, sensor_origin_in_map(pose, mount_));
}

ScanMotion TerrainMapper::motion_to(const TrunkPose& pose, const Eigen::Vector3d& now) const {
  if (!previous_pose_) return {};
  const Eigen::Vector3d before =
      previous_origin_known_ ? previous_origin_ : sensor_origin_in_map(*previous_pose_, mount_);
  return {std::hypot(now.x() - before.x(), now.y() - before.y()), wrap_angle(pose.yaw_rad - previous_pose_->yaw_rad)};
}

bool TerrainMapper::accept(const TrunkPose& pose, std::optional<double> time_s, ScanStats& stats) {
  hits_valid_ = false;  // every route starts here; only the packed pass sets them again
  if (!pose_is_finite(pose)) {
    stats.pose_rejected = true;
    ++totals_.scans_rejected_for_pose;
  } else if (options_.reject_stale_scans && time_s &&
             (!std::isfinite(*time_s) || (previous_time_s_ && !(*time_s > *previous_time_s_)))) {
    stats.time_rejected = true;
    ++totals_.scans_rejected_for_time;
  } else {
    return true;
  }
  ++totals_.scans;
  totals_.beams += stats.beams;
  return false;
}

void TerrainMapper::follow(const TrunkPose& pose, double cos_yaw, double sin_yaw, ScanStats& stats) {
  if (!options_.follow_robot) return;
  const double x_m = pose.x_m + options_.window_ahead_m * cos_yaw;
  const double y_m = pose.y_m + options_.window_ahead_m * sin_yaw;
  if (!window_listener_) {
    stats.cells_reset_by_move = map_.move_to(x_m, y_m);
    return;
  }
  // The listener must see the corner before the move, so it is found here
  // as move_to() finds it; a target move_to() would refuse moves nothing.
  const double limit =
      static_cast<double>(std::numeric_limits<std::int64_t>::max() / 4) * map_.cell_size_m();
  if (!(std::abs(x_m) <= limit && std::abs(y_m) <= limit)) return;
  const CellIndex centre = map_.cell_of(x_m, y_m);
  const int half = map_.cells_per_side() / 2;
  const CellIndex new_min{centre.x - half, centre.y - half};
  const CellIndex old_min = map_.min_cell();
  if (new_min == old_min) return;
  ++unrecorded_changes_;  // the listener may write the cells that entered (tiles)
  window_listener_->window_leaving(map_, new_min);
  stats.cells_reset_by_move = map_.move_corner_to(new_min);
  window_listener_->window_entered(map_, old_min);
}

void TerrainMapper::apply(double x_m, double y_m, double h_m, double dz_max, ScanStats& stats) {
  // Far beyond any terrain a walking robot sees; also keeps the cell index
  // and the float layers free of overflow.
  constexpr double kMaxCoordinate_m = 1.0e6;
  if (!(std::abs(x_m) < kMaxCoordinate_m && std::abs(y_m) < kMaxCoordinate_m && std::abs(h_m) < kMaxCoordinate_m)) {
    ++stats.outside_map;
    return;
  }
  std::size_t s = 0;
  if (!map_.slot_at(x_m, y_m, s)) {
    ++stats.outside_map;
    return;
  }
  const CellUpdate result = update_cell({map_.elevation_data()[s], map_.certainty_data()[s], map_.state_data()[s],
                                         map_.pending_elevation_data()[s], map_.contradiction_data()[s],
                                         map_.mean_elevation_data()[s], map_.mean_count_data()[s]},
                                        static_cast<float>(h_m), static_cast<float>(dz_max), options_.update);
  ++stats.integrated;
  const CellIndex cell = map_.cell_of(x_m, y_m);
  changed_.add(cell);
  changed_rows_.add(cell);
  switch (result) {
    case CellUpdate::first: ++stats.first; break;
    case CellUpdate::plausible: ++stats.plausible; break;
    case CellUpdate::implausible: ++stats.implausible; break;
    case CellUpdate::replaced: ++stats.replaced; break;
  }
}

void TerrainMapper::finish(const TrunkPose& pose, std::optional<double> time_s, const ScanStats& stats) {
  previous_pose_ = pose;
  previous_origin_known_ = false;
  if (time_s) previous_time_s_ = *time_s;
  ++scans_;  // its cells are in changed_rows_ by now
  MapperTotals scan;
  scan.scans = 1;
  scan.beams = stats.beams;
  scan.integrated = stats.integrated;
  scan.invalid_range = stats.invalid_range;
  scan.invalid_beam = stats.invalid_beam;
  scan.outside_map = stats.outside_map;
  scan.implausible = stats.implausible;
  totals_ += scan;
}

void TerrainMapper::refresh_beam_directions(const std::vector<double>& angles) {
  // A sensor's beam angles rarely change between scans; their sines and
  // cosines are the costliest part of a point, so keep them. Compared bit
  // for bit (memcmp runs at memory speed): a -0 for a 0 is a new angle too.
  if (angles.size() == cached_angles_.size() &&
      (angles.empty() || std::memcmp(angles.data(), cached_angles_.data(), angles.size() * sizeof(double)) == 0)) {
    return;
  }
  cached_angles_.assign(angles.begin(), angles.end());
  cos_angle_.resize(angles.size());
  sin_angle_.resize(angles.size());
  for (std::size_t i = 0; i < angles.size(); ++i) {
    cos_angle_[i] = std::cos(angles[i]);
    sin_angle_[i] = std::sin(angles[i]);
  }
}

#if defined(__x86_64__) && defined(__GNUC__) && !defined(__clang__) && defined(__linux__) && \
    !defined(STRIDEMAP_NO_AVX2_COPIES)
#define STRIDEMAP_PACK_AVX2 1
namespace {
// pack()'s loop four beams at a time where the CPU has AVX2 (chosen at run
// time), as the URG model's conversion packs: the same comparisons, the
// kept lanes moved to the front by one permute per array and stored at
// `count` (the lanes beyond are overwritten by the next block or left
// beyond the packed count, as the scalar loop leaves its last rejected
// beam). Returns the beams consumed (a multiple of 4).
__attribute__((target("avx2"))) std::size_t pack_blocks_avx2(const double* range, const double* error,
                                                              const double* cos_t, const double* sin_t, std::size_t n,
                                                              double* out_range, double* out_error, double* out_cos,
                                                              double* out_sin, std::size_t& count,
                                                              std::size_t& invalid_range, std::size_t& invalid_beam) {
  const __m256d zero = _mm256_setzero_pd(), inf = _mm256_set1_pd(std::numeric_limits<double>::infinity());
  std::size_t i = 0;
  for (; i + 4 <= n; i += 4) {
    const __m256d r = _mm256_loadu_pd(range + i), dr = _mm256_loadu_pd(error + i), c = _mm256_loadu_pd(cos_t + i);
    const __m256d range_ok = _mm256_and_pd(_mm256_cmp_pd(r, zero, _CMP_GT_OQ), _mm256_cmp_pd(r, inf, _CMP_LT_OQ));
    const __m256d beam_ok = _mm256_and_pd(_mm256_cmp_pd(c, c, _CMP_EQ_OQ),
                                          _mm256_and_pd(_mm256_cmp_pd(dr, zero, _CMP_GE_OQ), _mm256_cmp_pd(dr, inf, _CMP_LT_OQ)));
    const auto range_mask = static_cast<unsigned>(_mm256_movemask_pd(range_ok));
    const auto mask = static_cast<unsigned>(_mm256_movemask_pd(_mm256_and_pd(range_ok, beam_ok)));
    invalid_range += static_cast<std::size_t>(4 - __builtin_popcount(range_mask));
    invalid_beam += static_cast<std::size_t>(__builtin_popcount(range_mask & ~mask));
    detail::store_kept_lanes(mask, r, dr, c, _mm256_loadu_pd(sin_t + i), out_range, out_error, out_cos, out_sin, count);
  }
  return i;
}
}  // namespace
#endif

void TerrainMapper::pack(const PlanarScan& scan) {
  const std::size_t n = scan.size();
  packed_.prepare(n);
  packed_.time_s = scan.time_s;
  const double* range = scan.range_m.data();
  const double* error = scan.range_error_m.data();
  double* out_range = packed_.range_m.data();
  double* out_error = packed_.range_error_m.data();
  double* out_cos = packed_.cos_angle.data();
  double* out_sin = packed_.sin_angle.data();
  constexpr double kInf = std::numeric_limits<double>::infinity();
  std::size_t count = 0, invalid_range = 0, invalid_beam = 0;
  std::size_t i = 0;
#ifdef STRIDEMAP_PACK_AVX2
  static const bool has_avx2 = __builtin_cpu_supports("avx2");
  if (has_avx2) {
    i = pack_blocks_avx2(range, error, cos_angle_.data(), sin_angle_.data(), n, out_range, out_error, out_cos, out_sin,
                         count, invalid_range, invalid_beam);
  }
#endif
  // Every beam is written and only a valid one kept: no branch to mispredict.
  // PlanarScanPoints::point's checks; a non-finite angle has a NaN cosine.
  for (; i < n; ++i) {
    const double r = range[i], dr = error[i], c = cos_angle_[i];
    const bool range_ok = (r > 0.0) & (r < kInf);
    const bool beam_ok = (c == c) & (dr >= 0.0) & (dr < kInf);
    out_range[count] = r;
    out_error[count] = dr;
    out_cos[count] = c;
    out_sin[count] = sin_angle_[i];
    count += static_cast<std::size_t>(range_ok & beam_ok);
    invalid_range += static_cast<std::size_t>(!range_ok);
    invalid_beam += static_cast<std::size_t>(range_ok & !beam_ok);
  }
  packed_.count = count;
  packed_.invalid_range = invalid_range;
  packed_.invalid_beam = invalid_beam;
}

void TerrainMapper::check_scan_lengths(const PlanarScan& scan) {
  if (scan.angle_rad.size() != scan.range_m.size() || scan.range_error_m.size() != scan.range_m.size()) {
    throw InputError("scan at t=" + std::to_string(scan.time_s) + " s: angle_rad, range_m and range_error_m have " +
                     std::to_string(scan.angle_rad.size()) + ", " + std::to_string(scan.range_m.size()) + " and " +
                     std::to_string(scan.range_error_m.size()) + " entries; they must be equal");
  }
}

ScanStats TerrainMapper::integrate(const PlanarScan& scan, const TrunkPose& pose) {
  check_scan_lengths(scan);
  refresh_beam_directions(scan.angle_rad);
  pack(scan);
  return integrate(packed_, pose);
}

ScanStats TerrainMapper::integrate_points(std::span<const MapPoint> points, const TrunkPose& pose,
                                          std::optional<double> time_s) {
  ScanStats stats;
  stats.beams = points.size();
  if (!accept(pose, time_s, stats)) return stats;
  follow(pose, stats);
  for (const MapPoint& p : points) {
    if (!std::isfinite(p.x_m) || !std::isfinite(p.y_m) || !std::isfinite(p.elevation_m)) {
      ++stats.invalid_range;
      continue;
    }
    // An infinite bound is meaningful ("anything is plausible", as after a
    // yaw jump on the scan path); only NaN is not.
    if (std::isnan(p.max_elevation_change_m)) {
      ++stats.invalid_beam;
      continue;
    }
    apply(p.x_m, p.y_m, p.elevation_m, p.max_elevation_change_m, stats);
  }
  finish(pose, time_s, stats);
  return stats;
}

}  // namespace stridemap
