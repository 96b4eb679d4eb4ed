// LineExtractor against split-and-merge written plainly from its definition
// (algorithms.md section 3): a pair-by-pair break loop, a
// division per point for the distance from the chord, every fit from
// scratch, Keep::occluding as Keep::all with the rest left out. Scans with
// the kinds of structure that make the fast paths work: noisy floors with
// boxes and mixed pixels, rocky ground (curved faces split into many pieces
// and merged back), beams unevenly spaced.
#include <gtest/gtest.h>

#include <cmath>
#include <cstring>
#include <limits>
#include <numbers>
#include <random>
#include <vector>

#include "stridemap/preprocess/line_extraction.hpp"
#include "test_scans.hpp"

namespace stridemap {
namespace {

constexpr std::size_t kNone = static_cast<std::size_t>(-1);

class ReferenceLines {
 public:
  explicit ReferenceLines(const LineExtractionOptions& o) : o_(o) {}

  std::vector<LineSegment> extract(const PlanarScan& scan) {
    scan_ = &scan;
    const std::size_t n = scan.size();
    x_.assign(n, 0.0);
    y_.assign(n, 0.0);
    for (std::size_t i = 0; i < n; ++i) {
      x_[i] = scan.range_m[i] * std::cos(scan.angle_rad[i]);
      y_[i] = scan.range_m[i] * std::sin(scan.angle_rad[i]);
    }
    out_.clear();
    RangeRatioBandCache bands(o_.max_incidence_angle_rad, false);
    std::size_t first = kNone;
    for (std::size_t i = 0; i < n; ++i) {
      const double r = scan.range_m[i];
      if (!is_usable_range(r)) {
        if (first != kNone) cluster(first, i - 1);
        first = kNone;
        continue;
      }
      if (first != kNone &&
          !ranges_on_one_surface(scan.range_m[i - 1], r, o_.break_noise_sigmas * sigma(i - 1),
                                 bands.band(scan.angle_rad[i] - scan.angle_rad[i - 1]))) {
        cluster(first, i - 1);
        first = kNone;
      }
      if (first == kNone) first = i;
    }
    if (first != kNone) cluster(first, n - 1);
    return out_;
  }

 private:
  double sigma(std::size_t i) const { return o_.sigma.sigma_m(scan_->range_m[i], scan_->range_error_m[i]); }

  void cluster(std::size_t first, std::size_t last) {
    if (last - first + 1 < o_.min_points) return;
    double max_sigma = 0.0;
    for (std::size_t i = first; i <= last; ++i) max_sigma = std::max(max_sigma, sigma(i));
    split_ = std::max(o_.split_noise_sigmas * max_sigma, o_.min_split_distance_m);
    pieces_.clear();
    split(first, last);
    LineSegment merged = fit(pieces_[0].first, pieces_[0].second);
    std::size_t current_first = pieces_[0].first;
    for (std::size_t p = 1; p < pieces_.size(); ++p) {
      const LineSegment candidate = fit(current_first, pieces_[p].second);
      if (candidate.max_residual_m <= split_) {
        merged = candidate;
      } else {
        emit(merged, first, last);
        current_first = pieces_[p].first;
        merged = fit(pieces_[p].first, pieces_[p].second);
      }
    }
    emit(merged, first, last);
  }

  void split(std::size_t first, std::size_t last) {
    std::size_t farthest = kNone;
    if (last - first >= 2) {
      const double ax = x_[first], ay = y_[first];
      const double dx = x_[last] - ax, dy = y_[last] - ay;
      const double chord = std::hypot(dx, dy);
      double farthest_distance = chord > 1e-12 ? -1.0 : split_;
      for (std::size_t i = first + 1; i < last; ++i) {
        const double distance = chord > 1e-12 ? std::abs((x_[i] - ax) * dy - (y_[i] - ay) * dx) / chord
                                              : std::hypot(x_[i] - ax, y_[i] - ay);
        if (distance > farthest_distance) {
          farthest_distance = distance;
          farthest = i;
        }
      }
      if (chord > 1e-12 && !(farthest_distance > split_)) farthest = kNone;
    }
    if (farthest == kNone) {
      pieces_.push_back({first, last});
      return;
    }
    split(first, farthest);
    split(farthest, last);
  }

  LineSegment fit(std::size_t first, std::size_t last) const {
    const double count = static_cast<double>(last - first + 1);
    double mx = 0.0, my = 0.0;
    for (std::size_t i = first; i <= last; ++i) mx += x_[i], my += y_[i];
    mx /= count;
    my /= count;
    double sxx = 0.0, syy = 0.0, sxy = 0.0;
    for (std::size_t i = first; i <= last; ++i) {
      sxx += (x_[i] - mx) * (x_[i] - mx);
      syy += (y_[i] - my) * (y_[i] - my);
      sxy += (x_[i] - mx) * (y_[i] - my);
    }
    double alpha = 0.5 * std::atan2(-2.0 * sxy, syy - sxx);
    double rho = mx * std::cos(alpha) + my * std::sin(alpha);
    if (rho < 0.0) rho = -rho, alpha += std::numbers::pi;
    LineSegment line;
    double low = std::numeric_limits<double>::infinity(), high = -low;
    for (std::size_t i = first; i <= last; ++i) {
      line.max_residual_m =
          std::max(line.max_residual_m, std::abs(x_[i] * std::cos(alpha) + y_[i] * std::sin(alpha) - rho));
      const double along = -x_[i] * std::sin(alpha) + y_[i] * std::cos(alpha);
      low = std::min(low, along);
      high = std::max(high, along);
    }
    line.first_beam = first;
    line.last_beam = last;
    line.point_count = last - first + 1;
    line.normal_angle_rad = alpha;
    line.distance_m = rho;
    line.length_m = high - low;
    line.mid_x_m = mx;
    line.mid_y_m = my;
    return line;
  }

  void emit(LineSegment line, std::size_t first, std::size_t last) {
    if (line.point_count < o_.min_points || line.length_m < o_.min_length_m) return;
    line.occludes_before = line.first_beam == first && occludes(first, false, line);
    line.occludes_after = line.last_beam == last && occludes(last, true, line);
    out_.push_back(line);
  }

  bool occludes(std::size_t end, bool forward, const LineSegment& line) const {
    const PlanarScan& s = *scan_;
    for (std::size_t step = 1; step <= o_.occlusion_search_beams; ++step) {
      if (forward ? end + step >= s.size() : step > end) return false;
      const std::size_t j = forward ? end + step : end - step;
      if (!is_usable_range(s.range_m[j])) continue;
      if (s.range_m[j] <= s.range_m[end]) return false;
      const RangeRatioBand band =
          range_ratio_band(std::abs(s.angle_rad[j] - s.angle_rad[end]), o_.max_incidence_angle_rad, false);
      if (ranges_on_one_surface(s.range_m[end], s.range_m[j], o_.break_noise_sigmas * sigma(end), band)) return false;
      const double along_normal = std::cos(s.angle_rad[j]) * std::cos(line.normal_angle_rad) +
                                  std::sin(s.angle_rad[j]) * std::sin(line.normal_angle_rad);
      return std::abs(s.range_m[j] * along_normal - line.distance_m) > split_;
    }
    return false;
  }

  LineExtractionOptions o_;
  const PlanarScan* scan_ = nullptr;
  std::vector<double> x_, y_;
  std::vector<std::pair<std::size_t, std::size_t>> pieces_;
  std::vector<LineSegment> out_;
  double split_ = 0.0;
};

// Ground seen by the tilted scanner (x about constant), with rocks: bumps
// towards the sensor, some with steep fronts, and boxes; noise, dropouts,
// mixed pixels, unusable values and beams without a Delta r of their own.
PlanarScan rocky_scan(std::uint64_t seed, bool even_steps) {
  std::mt19937_64 engine(seed);
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  std::normal_distribution<double> noise(0.0, 0.001 + 0.004 * unit(engine));
  PlanarScan scan = test::centred_scan(683);
  if (!even_steps) {
    for (std::size_t i = 1; i < scan.size(); ++i) {
      scan.angle_rad[i] = scan.angle_rad[i - 1] + test::urg_step_rad * (0.5 + unit(engine));
    }
  }
  struct Rock {
    double y, half_width, height, sharpness;
  };
  std::vector<Rock> rocks;
  for (int k = static_cast<int>(12 * unit(engine)); k > 0; --k) {
    rocks.push_back({-0.6 + 1.2 * unit(engine), 0.02 + 0.15 * unit(engine), 0.02 + 0.2 * unit(engine),
                     1.0 + 6.0 * unit(engine)});
  }
  const double ground = 0.3 + 0.4 * unit(engine), slope = 0.3 * (unit(engine) - 0.5);
  const double mixed = 0.05 * unit(engine);
  for (std::size_t i = 0; i < scan.size(); ++i) {
    const double t = scan.angle_rad[i];
    // Fixed-point iterations for the hit on x = profile(y), y = x tan t.
    double x = ground;
    for (int it = 0; it < 4; ++it) {
      const double y = x * std::tan(t);
      double profile = ground + slope * y;
      for (const Rock& rock : rocks) {
        const double u = (y - rock.y) / rock.half_width;
        if (std::abs(u) < 1.0) profile -= rock.height * std::pow(1.0 - u * u, 1.0 / rock.sharpness);
      }
      x = std::max(profile, 0.05);
    }
    scan.range_m[i] = x / std::cos(t) + noise(engine);
    const double u = unit(engine);
    if (u < 0.03) scan.range_m[i] = test::nan;
    else if (u < 0.035) scan.range_m[i] = u < 0.033 ? -1.0 : std::numeric_limits<double>::infinity();
    else if (u < 0.035 + mixed) scan.range_m[i] *= 0.8 + 0.4 * unit(engine);
    if (unit(engine) < 0.02) scan.range_error_m[i] = unit(engine) < 0.5 ? test::nan : 0.0;
    else scan.range_error_m[i] = scan.range_m[i] < 1.0 ? 0.010 : 0.01 * scan.range_m[i];
  }
  // Now and then every point twice: ties for the farthest from a chord.
  if (seed % 6 == 5) {
    for (std::size_t i = 1; i < scan.size(); i += 2) {
      scan.angle_rad[i] = scan.angle_rad[i - 1];
      scan.range_m[i] = scan.range_m[i - 1];
      scan.range_error_m[i] = scan.range_error_m[i - 1];
    }
  }
  // Now and then a run of repeated points: chords of no length.
  if (unit(engine) < 0.3) {
    const std::size_t at = static_cast<std::size_t>(600 * unit(engine));
    for (std::size_t i = at; i < at + 20; ++i) scan.range_m[i] = 1e-13, scan.angle_rad[i] = scan.angle_rad[at];
  }
  return scan;
}

// The extractor grows a segment's second moments merge by merge where the
// definition sums them afresh, so the fitted line's numbers may differ in
// their last bits: those agree within kFitTolerance (radians or metres);
// which beams form a segment, its centroid (the same sums in the same
// order) and its occlusion flags agree exactly.
constexpr double kFitTolerance = 1e-12;

bool same_segment(const LineSegment& a, const LineSegment& b) {
  const auto bits = [](double v) {
    std::uint64_t u;
    std::memcpy(&u, &v, sizeof u);
    return u;
  };
  const auto close = [](double u, double v) { return std::abs(u - v) <= kFitTolerance; };
  return a.first_beam == b.first_beam && a.last_beam == b.last_beam && a.point_count == b.point_count &&
         close(a.normal_angle_rad, b.normal_angle_rad) && close(a.distance_m, b.distance_m) &&
         close(a.length_m, b.length_m) && close(a.max_residual_m, b.max_residual_m) &&
         bits(a.mid_x_m) == bits(b.mid_x_m) && bits(a.mid_y_m) == bits(b.mid_y_m) &&
         a.occludes_before == b.occludes_before && a.occludes_after == b.occludes_after;
}

void expect_same(const LineExtractionOptions& options, const PlanarScan& scan, std::size_t& segment_count) {
  ReferenceLines reference(options);
  const std::vector<LineSegment> expected = reference.extract(scan);
  LineExtractor extractor(options);
  std::vector<LineSegment> all, occluding;
  extractor.extract(scan, all);
  extractor.extract(scan, occluding, LineExtractor::Keep::occluding);
  ASSERT_EQ(all.size(), expected.size());
  std::vector<LineSegment> expected_occluding;
  for (std::size_t s = 0; s < all.size(); ++s) {
    ASSERT_TRUE(same_segment(all[s], expected[s])) << "segment " << s << " beams " << expected[s].first_beam << ".."
                                                << expected[s].last_beam;
    if (expected[s].occludes_before || expected[s].occludes_after) expected_occluding.push_back(expected[s]);
  }
  ASSERT_EQ(occluding.size(), expected_occluding.size());
  for (std::size_t s = 0; s < occluding.size(); ++s) ASSERT_TRUE(same_segment(occluding[s], expected_occluding[s]));
  segment_count += all.size();
}

TEST(LineExtractionReference, MatchesSplitAndMergeAsDefined) {
  std::size_t segments = 0;
  for (std::uint64_t seed = 1; seed <= 300; ++seed) {
    LineExtractionOptions options;
    if (seed % 5 == 0) options.min_points = 3;
    if (seed % 7 == 0) options.sigma.always_use_urg_spec = true;
    if (seed % 11 == 0) options.min_split_distance_m = 0.0005;
    SCOPED_TRACE(seed);
    expect_same(options, rocky_scan(seed, seed % 4 != 0), segments);
    if (HasFatalFailure()) return;
  }
  EXPECT_GT(segments, 3000u);  // the scans gave the extractor plenty to do
}

// A line bent at its middle beam by `bend_rad`: one segment for a slight
// bend (split at the corner, merged back), two beyond the bend at which
// the union's largest residual reaches the split distance.
PlanarScan bent_line(double bend_rad) {
  PlanarScan scan = test::centred_scan(201);
  test::put_on_line_x(scan, 0, 100, 0.5);
  const double corner_y = 0.5 * std::tan(scan.angle_rad[100]);
  const double distance = 0.5 * std::cos(bend_rad) + corner_y * std::sin(bend_rad);
  for (std::size_t i = 101; i < scan.size(); ++i) scan.range_m[i] = distance / std::cos(scan.angle_rad[i] - bend_rad);
  return scan;
}

// The largest bend at which `count_segments` still sees one segment, by
// bisection: there the union's largest residual lies within rounding of the
// limit, which no margin can settle.
template <typename CountSegments>
double last_merged_bend(CountSegments count_segments) {
  double merged = 0.0, split = 0.5;
  EXPECT_EQ(count_segments(bent_line(merged)), 1u);
  EXPECT_EQ(count_segments(bent_line(split)), 2u);
  while (true) {
    const double middle = 0.5 * (merged + split);
    if (middle <= merged || middle >= split) break;
    (count_segments(bent_line(middle)) == 1 ? merged : split) = middle;
  }
  return merged;
}

TEST(LineExtractionReference, DecidesTheMergeAtTheSameBend) {
  const LineExtractionOptions options;
  ReferenceLines reference(options);
  LineExtractor extractor(options);
  std::vector<LineSegment> segments;
  const double defined = last_merged_bend([&](const PlanarScan& scan) { return reference.extract(scan).size(); });
  const double fast = last_merged_bend([&](const PlanarScan& scan) {
    extractor.extract(scan, segments);
    return segments.size();
  });
  // The moments' rounding moves the flip by a few units in the last place
  // of the residual; a bend of 1e-12 rad moves the residual far more.
  EXPECT_NEAR(fast, defined, 1e-12);
  std::size_t count = 0;
  for (double bend : {defined - 1e-9, defined + 1e-9}) {
    SCOPED_TRACE(bend);
    expect_same(options, bent_line(bend), count);
  }
  EXPECT_EQ(count, 1u + 2u);
}

}  // namespace
}  // namespace stridemap
