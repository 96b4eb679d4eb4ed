#include "stridemap/preprocess/scan_sequence.hpp"

#include <algorithm>
#include <cmath>
#include <cstring>
#include <string>
#include <utility>

#include "option_checks.hpp"
#include "scan_copy.hpp"
#include "stridemap/core/error.hpp"
#include "vector_clones.hpp"

namespace stridemap {
namespace {

constexpr const char* filter_name = "scan-sequence filter";

struct Spread {
  std::size_t points = 0;
  double spread_m = 0.0;      // eq. 12: population standard deviation
  double mean_sigma_m = 0.0;  // mean sigma_r of the points
};

/// Eq. 12 over the valid beams [first, last] of `scan`, on the coordinate
/// along the unit vector (axis_x, axis_y) of the scan plane.
Spread spread_along(const PlanarScan& scan, const BeamDirections& directions, std::size_t first, std::size_t last,
                    double axis_x, double axis_y, const RangeSigmaModel& sigma) {
  Spread result;
  const std::vector<double>& cosines = directions.cos();
  const std::vector<double>& sines = directions.sin();
  double sum = 0.0;
  for (std::size_t i = first; i <= last; ++i) {
    const double r = scan.range_m[i];
    if (!is_usable_range(r)) continue;
    sum += r * (cosines[i] * axis_x + sines[i] * axis_y);
    result.mean_sigma_m += sigma.sigma_m(r, scan.range_error_m[i]);
    ++result.points;
  }
  if (result.points == 0) return result;
  const double count = static_cast<double>(result.points);
  const double mean = sum / count;
  double squares = 0.0;
  for (std::size_t i = first; i <= last; ++i) {
    const double r = scan.range_m[i];
    if (!is_usable_range(r)) continue;
    const double deviation = r * (cosines[i] * axis_x + sines[i] * axis_y) - mean;
    squares += deviation * deviation;
  }
  result.spread_m = std::sqrt(squares / count);
  result.mean_sigma_m /= count;
  return result;
}

// jump[i] = 1 where beam i's ranges in scans k-1 and k+1 differ by more
// than min_jump_m (|a - b| is max - min exactly; NaN never jumps): the
// between-scans test's first condition for every beam in one pass.
STRIDEMAP_PREPROCESS_CLONES void mark_jumps(const double* before, const double* after, std::size_t n,
                                            double min_jump_m, std::uint8_t* jump) {
  for (std::size_t i = 0; i < n; ++i) jump[i] = static_cast<std::uint8_t>(std::abs(after[i] - before[i]) > min_jump_m);
}

}  // namespace

void BetweenScansOptions::validate(const char* owner) const {
  const std::string field = std::string(owner) + ".between_scans";
  detail::require_in_range(field.c_str(), "min_jump_m", min_jump_m, 0.0, false, 100.0, true, " m");
  detail::require_in_range(field.c_str(), "margin_sigmas", margin_sigmas, 0.0, true, 1e6, true);
}

void ScanSequenceOptions::validate() const {
  const char* owner = "ScanSequenceOptions";
  lines.validate(owner);
  detail::require_angle_in_range(owner, "max_edge_tilt_rad", max_edge_tilt_rad, 0.0, true, 90.0, true);
  detail::require_in_range(owner, "spread_ratio", spread_ratio, 0.0, true, 1e6, true);
  detail::require_in_range(owner, "spread_floor_sigmas", spread_floor_sigmas, 0.0, true, 1e6, true);
  detail::require_at_least(owner, "min_sector_points", min_sector_points, 2);
  between_scans.validate(owner);
  if (spread_axis != SpreadAxis::edge_normal && spread_axis != SpreadAxis::sensor_forward &&
      spread_axis != SpreadAxis::line_of_sight) {
    throw InputError(std::string(owner) + ": spread_axis: not one of edge_normal, sensor_forward, line_of_sight");
  }
}

ScanSequenceFilter::ScanSequenceFilter(const ScanSequenceOptions& options)
    : options_(options), lines_((options.validate(), options.lines)) {}

bool ScanSequenceFilter::push(const PlanarScan& next_scan, PlanarScan& out) {
  return push(next_scan, out, scratch_removed_);
}

bool ScanSequenceFilter::flush(PlanarScan& out) { return flush(out, scratch_removed_); }

void ScanSequenceFilter::check_length(const PlanarScan& next_scan) const {
  if (has_held_ && next_scan.size() != held_.size()) {
    throw InputError(std::string(filter_name) + ": scan " + std::to_string(scans_in_stream_) + " of the stream has " +
                     std::to_string(next_scan.size()) + " beams, but the scans before it have " +
                     std::to_string(held_.size()) +
                     "; all scans of one stream must have the same beam count (flush() or reset() starts a "
                     "new stream)");
  }
}

bool ScanSequenceFilter::push(const PlanarScan& next_scan, PlanarScan& out, std::vector<std::uint8_t>& removed) {
  const std::size_t index = scans_in_stream_;
  check_scan_shape(next_scan, filter_name, index);
  check_length(next_scan);
  detail::copy_scan(next_scan, incoming_);
  incoming_breaks_.valid = false;
  const std::size_t incoming_invalid =
      prepare_scan_for_filter(incoming_, normalize_mask_, filter_name, index).invalid_input;
  return take_incoming(incoming_invalid, out, removed);
}

bool ScanSequenceFilter::push_prepared(PlanarScan& next_scan, std::size_t invalid_input, PlanarScan& out,
                                       std::vector<std::uint8_t>& removed, const RangeBreaks* breaks) {
  check_length(next_scan);
  std::swap(incoming_, next_scan);
  if (breaks != nullptr && breaks->valid) {
    incoming_breaks_ = *breaks;  // into the buffer it had: no allocation once grown
  } else {
    incoming_breaks_.valid = false;
  }
  return take_incoming(invalid_input, out, removed);
}

bool ScanSequenceFilter::take_incoming(std::size_t incoming_invalid, PlanarScan& out,
                                       std::vector<std::uint8_t>& removed) {
  ++scans_in_stream_;
  if (!has_held_) {
    std::swap(held_, incoming_);
    std::swap(held_breaks_, incoming_breaks_);
    held_invalid_input_ = incoming_invalid;
    has_held_ = true;
    return false;
  }
  judge_held_scan(removed);
  emit_held_scan(out);
  // The judged scan, mixed points removed, is the k-1 of the next decision.
  std::swap(previous_, held_);
  std::swap(previous_breaks_, held_breaks_);
  has_previous_ = true;
  std::swap(held_, incoming_);
  std::swap(held_breaks_, incoming_breaks_);
  held_invalid_input_ = incoming_invalid;
  return true;
}

bool ScanSequenceFilter::flush(PlanarScan& out, std::vector<std::uint8_t>& removed) {
  sectors_.clear();
  if (!has_held_) {
    reset();
    return false;
  }
  // No scan k+1: nothing to compare with, so the scan is returned as it is.
  removed.assign(held_.size(), 0);
  removed_count_ = 0;
  between_removed_.assign(held_.size(), 0);
  emit_held_scan(out);
  reset();
  return true;
}

void ScanSequenceFilter::reset() {
  has_previous_ = false;
  has_held_ = false;
  scans_in_stream_ = 0;
  held_invalid_input_ = 0;
}

void ScanSequenceFilter::judge_held_scan(std::vector<std::uint8_t>& removed) {
  const std::size_t n = held_.size();
  removed.assign(n, 0);
  between_removed_.assign(n, 0);
  sectors_.clear();
  removed_count_ = 0;
  if (!has_previous_ || n == 0) return;
  if (options_.spread_test) judge_spread(removed);
  if (options_.between_scans.enabled) judge_between_scans(removed);
  if (removed_count_ == 0) return;
  apply_removal_mask(held_, removed);
  if (!held_breaks_.valid) return;
  // The pairs of each beam removed break, as the clustering test would find
  // (breaks[0] is 1 already). Plain pointers, so that the loop vectorises.
  std::uint8_t* breaks = held_breaks_.breaks.data();
  const std::uint8_t* gone = removed.data();
  for (std::size_t i = 1; i < n; ++i) breaks[i] = static_cast<std::uint8_t>(breaks[i] | gone[i] | gone[i - 1]);
}

void ScanSequenceFilter::judge_between_scans(std::vector<std::uint8_t>& removed) {
  // Scan k-1 as returned (its own mixed beams already NaN) and scan k+1 as
  // pushed: the beam index is the same direction in the sensor frame.
  const BetweenScansOptions& o = options_.between_scans;
  const RangeSigmaModel& sigma = options_.lines.sigma;
  const std::size_t n = held_.size();
  jumps_.resize(n);
  mark_jumps(previous_.range_m.data(), incoming_.range_m.data(), n, o.min_jump_m, jumps_.data());
  // Only the beams that jump: the rest fail the test below anyway.
  const std::uint8_t* jumps = jumps_.data();
  const std::uint8_t* end = jumps + n;
  for (const std::uint8_t* p = jumps; p < end; ++p) {
    p = static_cast<const std::uint8_t*>(std::memchr(p, 1, static_cast<std::size_t>(end - p)));
    if (p == nullptr) break;
    const std::size_t i = static_cast<std::size_t>(p - jumps);
    const double r = held_.range_m[i], before = previous_.range_m[i], after = incoming_.range_m[i];
    if (removed[i] || !is_usable_range(r) || !is_usable_range(before) || !is_usable_range(after)) continue;
    const double near = std::min(before, after), far = std::max(before, after);
    if (far - near <= o.min_jump_m) continue;
    const double margin = o.margin_sigmas * sigma.sigma_m(r, held_.range_error_m[i]);
    if (r > near + margin && r < far - margin) {
      removed[i] = between_removed_[i] = 1;
      ++removed_count_;
    }
  }
}

void ScanSequenceFilter::judge_spread(std::vector<std::uint8_t>& removed) {
  const std::size_t n = held_.size();
  // Only occluding segments are judged when an occluding end is required.
  lines_.extract(previous_, segments_,
                 options_.require_occluding_end ? LineExtractor::Keep::occluding : LineExtractor::Keep::all,
                 &previous_breaks_);
  if (sectors_.capacity() < segments_.capacity()) sectors_.reserve(segments_.capacity());
  bool directions_current = false;  // brought up to date for the first spread only
  const BeamDirections& directions_previous = lines_.directions();
  const double max_cos_to_beam = std::sin(options_.max_edge_tilt_rad);
  const RangeSigmaModel& sigma = options_.lines.sigma;
  for (const LineSegment& segment : segments_) {
    if (options_.require_occluding_end && !segment.occludes_before && !segment.occludes_after) continue;
    // Line direction is the normal turned by 90 deg; an edge across the scan is
    // nearly perpendicular to the beams that see it.
    const double along_x = -std::sin(segment.normal_angle_rad);
    const double along_y = std::cos(segment.normal_angle_rad);
    const auto crosses_beam = [&](std::size_t beam) {
      return std::abs(along_x * directions_previous.cos()[beam] + along_y * directions_previous.sin()[beam]) <=
             max_cos_to_beam;
    };
    if (!crosses_beam(segment.first_beam) || !crosses_beam(segment.last_beam)) continue;
    double axis_x = 1.0, axis_y = 0.0;  // SpreadAxis::sensor_forward
    if (options_.spread_axis == SpreadAxis::edge_normal) {
      axis_x = std::cos(segment.normal_angle_rad);
      axis_y = std::sin(segment.normal_angle_rad);
    } else if (options_.spread_axis == SpreadAxis::line_of_sight) {
      const double centroid_range = std::hypot(segment.mid_x_m, segment.mid_y_m);
      if (centroid_range <= 0.0) continue;
      axis_x = segment.mid_x_m / centroid_range;
      axis_y = segment.mid_y_m / centroid_range;
    }

    ScanSequenceSector sector;
    const auto widen = [&](std::size_t margin, std::size_t& first, std::size_t& last) {
      first = segment.first_beam >= margin ? segment.first_beam - margin : 0;
      last = std::min(n - 1, segment.last_beam + margin);
    };
    widen(options_.sector_margin_beams, sector.first_beam, sector.last_beam);
    widen(options_.spread_margin_beams, sector.spread_first_beam, sector.spread_last_beam);
    if (!directions_current) {
      directions_k_.update(held_.angle_rad);
      directions_next_.update(incoming_.angle_rad);
      directions_current = true;
    }
    const Spread now = spread_along(held_, directions_k_, sector.spread_first_beam, sector.spread_last_beam,
                                    axis_x, axis_y, sigma);
    const Spread next = spread_along(incoming_, directions_next_, sector.spread_first_beam,
                                     sector.spread_last_beam, axis_x, axis_y, sigma);
    sector.points_k = now.points;
    sector.points_next = next.points;
    sector.spread_k_m = now.spread_m;
    sector.spread_next_m = next.spread_m;
    sector.threshold_m =
        options_.spread_ratio * next.spread_m + options_.spread_floor_sigmas * next.mean_sigma_m;
    sector.removed = now.points >= options_.min_sector_points &&
                     next.points >= options_.min_sector_points && now.spread_m > sector.threshold_m;
    if (sector.removed) {
      for (std::size_t i = sector.first_beam; i <= sector.last_beam; ++i) {
        if (removed[i] == 0 && is_usable_range(held_.range_m[i])) {
          removed[i] = 1;
          ++removed_count_;
        }
      }
    }
    sectors_.push_back(sector);
  }
}

void ScanSequenceFilter::emit_held_scan(PlanarScan& out) {
  detail::copy_scan(held_, out);
  ScanFilterStats& stats = last_stats_;
  stats.beams = held_.size();
  stats.invalid_input = held_invalid_input_;
  stats.removed = removed_count_;  // the beams marked in `removed`, each once
}

}  // namespace stridemap
