#include "stridemap/preprocess/line_extraction.hpp"

#include <algorithm>
#include <cmath>
#include <cstring>
#include <limits>
#include <numbers>
#include <utility>

#include "line_kernels.hpp"
#include "option_checks.hpp"
#include "range_breaks.hpp"
#include "stridemap/preprocess/range_clustering.hpp"
#include "stridemap/preprocess/scan_checks.hpp"

namespace stridemap {
namespace {

constexpr std::size_t kNoIndex = static_cast<std::size_t>(-1);
constexpr double kNoLimit = std::numeric_limits<double>::infinity();

}  // namespace

void LineExtractionOptions::validate(const char* owner) const {
  detail::require_angle_in_range(owner, "lines.max_incidence_angle_rad", max_incidence_angle_rad, 0.0, false,
                                 90.0, false);
  detail::require_in_range(owner, "lines.break_noise_sigmas", break_noise_sigmas, 0.0, true, 1e6, true);
  detail::require_in_range(owner, "lines.split_noise_sigmas", split_noise_sigmas, 0.0, true, 1e6, true);
  detail::require_in_range(owner, "lines.min_split_distance_m", min_split_distance_m, 0.0, false, 1e6, true,
                           " m");
  detail::require_at_least(owner, "lines.min_points", min_points, 2);
  detail::require_in_range(owner, "lines.min_length_m", min_length_m, 0.0, true, 1e6, true, " m");
  sigma.validate(owner);
}

LineExtractor::LineExtractor(const LineExtractionOptions& options)
    : options_(options), bands_(options.max_incidence_angle_rad, false) {
  options_.validate("LineExtractionOptions");
}

void LineExtractor::extract(const PlanarScan& scan, std::vector<LineSegment>& segments, Keep keep,
                            const RangeBreaks* known) {
  segments.clear();
  const std::size_t n = scan.size();
  const std::vector<double>& range = scan.range_m;
  x_m_.resize(n);
  y_m_.resize(n);
  // Reserve the worst case up front so that a scan with more structure than
  // the ones before it does not allocate: pieces share at most their end
  // points, so a scan holds fewer than n pieces and n / (min_points - 1) + 1
  // segments.
  const std::size_t max_segments = n / (options_.min_points - 1) + 1;
  if (segments.capacity() < max_segments) segments.reserve(max_segments);
  if (stack_.capacity() < n + 1) stack_.reserve(n + 1);
  directions_.update(scan.angle_rad);
  if (const RangeRatioBand* band = detail::uniform_step_band(scan, directions_, bands_)) {
    // The loop below, its tests made in one pass: the same clusters in the same order.
    if (known != nullptr && detail::made_with(*known, n, *band, options_.break_noise_sigmas, options_.sigma)) {
      breaks_ = known->breaks;
    } else {
      detail::mark_range_breaks(scan, *band, options_.break_noise_sigmas, options_.sigma, breaks_);
    }
    // A cluster of two beams or more starts before a joined pair (whose
    // beams are usable); the others are single beams, below min_points.
    for (std::size_t i = 1; i < n;) {
      const void* joined = std::memchr(breaks_.data() + i, 0, n - i);
      if (joined == nullptr) break;
      const std::size_t start = static_cast<std::size_t>(static_cast<const std::uint8_t*>(joined) - breaks_.data()) - 1;
      const std::size_t end = detail::run_end(breaks_, start);
      process_cluster(scan, start, end - 1, keep, segments);
      i = end + 1;
    }
    return;
  }
  RangeRatioBandCache bands(options_.max_incidence_angle_rad, false);
  std::size_t first = kNoIndex;
  for (std::size_t i = 0; i < n; ++i) {
    if (!is_usable_range(range[i])) {
      if (first != kNoIndex) process_cluster(scan, first, i - 1, keep, segments);
      first = kNoIndex;
      continue;
    }
    if (first != kNoIndex) {
      const double tolerance =
          options_.break_noise_sigmas * options_.sigma.sigma_m(range[i - 1], scan.range_error_m[i - 1]);
      if (!ranges_on_one_surface(range[i - 1], range[i], tolerance,
                                 bands.band(scan.angle_rad[i] - scan.angle_rad[i - 1]))) {
        process_cluster(scan, first, i - 1, keep, segments);
        first = kNoIndex;
      }
    }
    if (first == kNoIndex) first = i;
  }
  if (first != kNoIndex) process_cluster(scan, first, n - 1, keep, segments);
}

// Split, then merge neighbouring pieces left to right. Only a segment that
// starts at the cluster's first beam or ends at its last can occlude, and
// whether an end can is known before any fit (occluded_beam()): with
// Keep::occluding a cluster with no such end is skipped, and one whose
// last end cannot stops after its first segment.
void LineExtractor::process_cluster(const PlanarScan& scan, std::size_t first, std::size_t last, Keep keep,
                                    std::vector<LineSegment>& segments) {
  if (last - first + 1 < options_.min_points) return;
  const std::size_t beyond_first = occluded_beam(scan, first, false);
  const std::size_t beyond_last = occluded_beam(scan, last, true);
  const bool occluding_only = keep == Keep::occluding;
  if (occluding_only && beyond_first == kNoIndex && beyond_last == kNoIndex) return;
  // Points only for the clusters split and fitted: most are skipped above.
  double max_range = 0.0;
  const double max_sigma =
      detail::cluster_points(scan.range_m.data(), scan.range_error_m.data(), directions_.cos().data(),
                             directions_.sin().data(), first, last, options_.sigma, x_m_.data(), y_m_.data(), max_range);
  const double split_distance = std::max(options_.split_noise_sigmas * max_sigma, options_.min_split_distance_m);
  // Pieces are split off one at a time as the merge asks for them: a merge
  // that stops after the first segment leaves the rest of the cluster unsplit.
  stack_.clear();
  stack_.push_back({first, last});

  LineSegment merged;
  Piece current;
  next_piece(split_distance, current);
  PointSums merged_sums{0.0, 0.0, current.first};
  add_points(merged_sums, current.last);
  Moments merged_moments = moments(current.first, current.last, merged_sums);
  // Lines are fitted only for the segments emitted: a merge needs only to
  // know that the union is still a line, and most pieces are merged.
  const auto emit = [&] {
    if (current.last - current.first + 1 < options_.min_points) return;
    // A segment that starts past `first` and ends before `last` occludes nothing.
    const bool may_occlude = (current.first == first && beyond_first != kNoIndex) ||
                             (current.last == last && beyond_last != kNoIndex);
    if (occluding_only && !may_occlude) return;
    Normal normal;
    fit(current.first, current.last, merged_moments, kNoLimit, merged, normal);
    if (merged.length_m < options_.min_length_m) return;
    merged.occludes_before = current.first == first && occludes(beyond_first, scan, merged, normal, split_distance);
    merged.occludes_after = current.last == last && occludes(beyond_last, scan, merged, normal, split_distance);
    if (!occluding_only || merged.occludes_before || merged.occludes_after) segments.push_back(merged);
  };
  // The segments after the first start past `first`: without an occluding
  // last end, none of them is wanted.
  const bool first_only = occluding_only && beyond_last == kNoIndex;
  for (Piece next; next_piece(split_distance, next);) {
    PointSums candidate_sums = merged_sums;
    const Moments candidate = grown(merged_moments, current.first, next.last, candidate_sums);
    if (within(current.first, next.last, candidate, split_distance, max_range)) {
      current.last = next.last;
      merged_sums = candidate_sums;
      merged_moments = candidate;
    } else {
      emit();
      if (first_only) return;
      current = next;
      merged_sums = {0.0, 0.0, current.first};
      add_points(merged_sums, current.last);
      merged_moments = moments(current.first, current.last, merged_sums);
    }
  }
  emit();
}

bool LineExtractor::next_piece(double split_distance_m, Piece& piece) {
  // Iterative end-point fit with an explicit stack; the right part is pushed
  // first so that pieces come out in beam order. The split point belongs to
  // both parts: it is the corner they share.
  while (!stack_.empty()) {
    piece = stack_.back();
    stack_.pop_back();
    if (piece.last - piece.first >= 2) {
      const double ax = x_m_[piece.first];
      const double ay = y_m_[piece.first];
      const double dx = x_m_[piece.last] - ax;
      const double dy = y_m_[piece.last] - ay;
      // hypot() is slow and its bits are needed only near a decision: a
      // squared length in this range puts the chord far above 1e-12, and
      // its square root within a few units in the last place of hypot().
      const double squared = dx * dx + dy * dy;
      const bool plain = squared > 1e-20 && squared < 1e300;
      const std::size_t farthest = plain || std::hypot(dx, dy) > 1e-12
                                       ? farthest_from_chord(piece, ax, ay, dx, dy, plain, split_distance_m)
                                       : farthest_from_point(piece, ax, ay, split_distance_m);
      if (farthest != kNoIndex) {
        stack_.push_back({farthest, piece.last});
        stack_.push_back({piece.first, farthest});
        continue;
      }
    }
    return true;
  }
  return false;
}

// The first interior point of `piece` at the largest distance |p x d| /
// chord from the chord, if that exceeds split_distance_m. Rounded division
// by the same chord never reverses an order, so the largest cross product
// gives the largest distance, and only a point whose cross product comes
// within rounding of it can tie: one division for the winner instead of
// one per point, the same point and distance as dividing each. With a
// `plain` chord the squares decide, without hypot's slow bits, unless the
// distance comes within 1e-9 of split_distance_m, a margin millions of
// times their rounding.
std::size_t LineExtractor::farthest_from_chord(const Piece& piece, double ax, double ay, double dx, double dy,
                                               bool plain, double split_distance_m) const {
  const detail::ChordFarthest far =
      detail::farthest_from_chord(x_m_.data(), y_m_.data(), piece.first + 1, piece.last, ax, ay, dx, dy);
  const std::size_t best = far.index;
  const double best_cross = far.cross;
  const double runner_up = far.runner_up;  // at least every other point's cross product
  if (best == kNoIndex) return kNoIndex;
  // An earlier point whose smaller cross product rounds to the same
  // distance came first in the per-point comparison; two doubles that
  // round alike differ by far less than 1e-12 of either.
  const double near_tie = best_cross * (1.0 - 1e-12);
  if (plain && best_cross < 1e150) {
    const double cross_squared = best_cross * best_cross;
    const double limit_squared = split_distance_m * split_distance_m * (dx * dx + dy * dy);
    if (limit_squared > 1e-250) {
      if (cross_squared < limit_squared * (1.0 - 2e-9)) return kNoIndex;
      if (cross_squared > limit_squared * (1.0 + 2e-9) && runner_up < near_tie) return best;
    }
  }
  const double chord = std::hypot(dx, dy);
  const double distance = best_cross / chord;
  if (!(distance > split_distance_m)) return kNoIndex;
  if (runner_up < near_tie) return best;
  for (std::size_t i = piece.first + 1; i < best; ++i) {
    const double cross = std::abs((x_m_[i] - ax) * dy - (y_m_[i] - ay) * dx);
    if (cross >= near_tie && cross / chord == distance) return i;
  }
  return best;
}

// Degenerate chord (end points coincide): the distance from the end point.
std::size_t LineExtractor::farthest_from_point(const Piece& piece, double ax, double ay,
                                               double split_distance_m) const {
  std::size_t farthest = kNoIndex;
  double farthest_distance = split_distance_m;
  for (std::size_t i = piece.first + 1; i < piece.last; ++i) {
    const double distance = std::hypot(x_m_[i] - ax, y_m_[i] - ay);
    if (distance > farthest_distance) {
      farthest_distance = distance;
      farthest = i;
    }
  }
  return farthest;
}

void LineExtractor::add_points(PointSums& sums, std::size_t last) const {
  for (std::size_t i = sums.next; i <= last; ++i) {
    sums.x += x_m_[i];
    sums.y += y_m_[i];
  }
  sums.next = last + 1;
}

LineExtractor::Moments LineExtractor::moments(std::size_t first, std::size_t last, const PointSums& sums) const {
  const double count = static_cast<double>(last - first + 1);
  Moments m;
  m.mean_x = sums.x / count;
  m.mean_y = sums.y / count;
  for (std::size_t i = first; i <= last; ++i) {
    const double dx = x_m_[i] - m.mean_x;
    const double dy = y_m_[i] - m.mean_y;
    m.sxx += dx * dx;
    m.syy += dy * dy;
    m.sxy += dx * dy;
  }
  return m;
}

// The moments of [first, new_last] from `m`, those of [first, sums.next),
// and the points after it, by the pairwise update of Chan, Golub and
// LeVeque: the second moments of the two parts plus the spread of their
// means, a sum of non-negative terms. A growing segment costs its new
// points only, where moments() over the union cost all its points at every
// merge. The new points' own moments are summed in one pass about their
// first point, which lies within the part's extent of its mean: the
// cancellation costs a few units in the last place, not digits. `sums`
// grows by the new points in beam order, as add_points() would: the means
// are the in-order sums', the bits fit() reports as mid_x_m and mid_y_m.
LineExtractor::Moments LineExtractor::grown(const Moments& m, std::size_t first, std::size_t new_last,
                                            PointSums& sums) const {
  const std::size_t from = sums.next;
  const double old_count = static_cast<double>(from - first);
  const double new_count = static_cast<double>(new_last + 1 - from);
  const double x0 = x_m_[from], y0 = y_m_[from];
  double su = 0.0, sv = 0.0, suu = 0.0, svv = 0.0, suv = 0.0;
  for (std::size_t i = from; i <= new_last; ++i) {
    sums.x += x_m_[i];
    sums.y += y_m_[i];
    const double u = x_m_[i] - x0, v = y_m_[i] - y0;
    su += u;
    sv += v;
    suu += u * u;
    svv += v * v;
    suv += u * v;
  }
  sums.next = new_last + 1;
  const double mean_u = su / new_count, mean_v = sv / new_count;
  const double dx = x0 + mean_u - m.mean_x;
  const double dy = y0 + mean_v - m.mean_y;
  const double weight = old_count * new_count / (old_count + new_count);
  Moments union_moments;
  union_moments.mean_x = sums.x / (old_count + new_count);
  union_moments.mean_y = sums.y / (old_count + new_count);
  union_moments.sxx = m.sxx + std::max(suu - su * mean_u, 0.0) + dx * dx * weight;
  union_moments.syy = m.syy + std::max(svv - sv * mean_v, 0.0) + dy * dy * weight;
  union_moments.sxy = m.sxy + (suv - su * mean_v) + dx * dy * weight;
  return union_moments;
}

// fit()'s normal has half the angle of (a, b) = (syy - sxx, -2 sxy), from
// atan2, cos and sin. The bisector of (1, 0) and (a, b) / r has it too, and
// without the trigonometry, a division or cancellation: (a + r, b), or
// (b, r - a) (the normal or its opposite, which is the same line), of length
// sqrt(2 r (r + |a|)). Residuals scaled by that length move by no more than
// about 1e-14 of the largest range; only a point within 1e-9 of it from the
// limit sends the question to fit().
bool LineExtractor::within(std::size_t first, std::size_t last, const Moments& m, double max_residual_m,
                           double max_range_m) const {
  const double a = m.syy - m.sxx;
  const double b = -2.0 * m.sxy;
  const double r = std::sqrt(a * a + b * b);
  if (r > 1e-150 && r < 1e150) {
    const double wx = a >= 0.0 ? a + r : b;
    const double wy = a >= 0.0 ? b : r - a;
    const double length = std::sqrt(2.0 * r * (r + std::abs(a)));
    const double margin = 1e-9 * max_range_m;
    switch (detail::residuals_within(x_m_.data(), y_m_.data(), first, last, wx, wy, m.mean_x * wx + m.mean_y * wy,
                                     (max_residual_m - margin) * length, (max_residual_m + margin) * length)) {
      case detail::Verdict::inside:
        return true;
      case detail::Verdict::outside:
        return false;
      case detail::Verdict::unsure:
        break;
    }
  }
  LineSegment line;
  Normal normal;
  return fit(first, last, m, max_residual_m, line, normal);
}

bool LineExtractor::fit(std::size_t first, std::size_t last, const Moments& m, double max_residual_m,
                        LineSegment& line, Normal& normal) const {
  const std::size_t count = last - first + 1;
  const double mean_x = m.mean_x, mean_y = m.mean_y, sxx = m.sxx, syy = m.syy, sxy = m.sxy;
  // Total least squares in polar form (algorithms.md 3.2 step 4).
  double alpha = 0.5 * std::atan2(-2.0 * sxy, syy - sxx);
  double rho = mean_x * std::cos(alpha) + mean_y * std::sin(alpha);
  if (rho < 0.0) {
    rho = -rho;
    alpha += std::numbers::pi;
  }
  const double nx = std::cos(alpha);
  const double ny = std::sin(alpha);
  detail::LineExtent extent;
  if (!detail::line_extent(x_m_.data(), y_m_.data(), first, last, nx, ny, rho, max_residual_m, extent)) return false;
  line.first_beam = first;
  line.last_beam = last;
  line.point_count = count;
  line.normal_angle_rad = alpha;
  line.distance_m = rho;
  line.length_m = extent.along_max_m - extent.along_min_m;
  line.max_residual_m = extent.max_residual_m;
  line.mid_x_m = mean_x;
  line.mid_y_m = mean_y;
  line.occludes_before = false;
  line.occludes_after = false;
  normal = {nx, ny};
  return true;
}

// The first valid beam past `end_beam` (within occlusion_search_beams)
// when it breaks from the end and lies farther: what an occluding end
// needs whatever the line; kNoIndex otherwise.
std::size_t LineExtractor::occluded_beam(const PlanarScan& scan, std::size_t end_beam, bool forward) const {
  const std::size_t n = scan.size();
  const double end_range = scan.range_m[end_beam];
  for (std::size_t step = 1; step <= options_.occlusion_search_beams; ++step) {
    if (forward ? end_beam + step >= n : step > end_beam) return kNoIndex;
    const std::size_t j = forward ? end_beam + step : end_beam - step;
    const double beyond = scan.range_m[j];
    if (!is_usable_range(beyond)) continue;
    // Nearer is no occlusion whatever the band: its cosines only for a farther beam.
    if (beyond <= end_range) return kNoIndex;
    const double tolerance =
        options_.break_noise_sigmas * options_.sigma.sigma_m(end_range, scan.range_error_m[end_beam]);
    if (ranges_on_one_surface(end_range, beyond, tolerance, bands_.band(scan.angle_rad[j] - scan.angle_rad[end_beam])))
      return kNoIndex;
    return j;
  }
  return kNoIndex;
}

// The beam past the end (occluded_beam()) must also lie off the segment's
// line; `normal` is the cos and sin of its normal_angle_rad, from fit().
bool LineExtractor::occludes(std::size_t beyond_beam, const PlanarScan& scan, const LineSegment& line,
                             const Normal& normal, double split_distance_m) const {
  if (beyond_beam == kNoIndex) return false;
  const std::size_t j = beyond_beam;
  const double off_line =
      std::abs(scan.range_m[j] * (directions_.cos()[j] * normal.x + directions_.sin()[j] * normal.y) - line.distance_m);
  return off_line > split_distance_m;
}

}  // namespace stridemap
