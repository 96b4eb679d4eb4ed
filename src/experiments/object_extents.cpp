#include "stridemap/experiments/object_extents.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <deque>
#include <limits>
#include <numbers>
#include <string>

#include "stridemap/core/error.hpp"

namespace stridemap {
namespace {

// What the truth may say: where the object is (its region's seed) and, for
// a box, which of its axes is the length.
struct Identity {
  double cx, cy;
  double yaw;
  bool round;
  double half_length_m = 0.0, half_width_m = 0.0;
};

// The fit's four edges against the truth's, outwards positive, named from
// the heading. The fit's offsets are measured from the truth's centre
// along its own axes, which lie within a few degrees of the truth's but may
// point the other way.
std::array<double, 4> edge_errors(const BoxEdgeFit& fit, const Identity& id, double heading_rad) {
  const bool flipped = std::abs(std::remainder(fit.yaw_rad - id.yaw, 2.0 * std::numbers::pi)) > std::numbers::pi / 2;
  // Outward position of each truth side (+u, -u, +v, -v) as the fit puts it.
  const double plus_u = flipped ? -fit.edges_m[0] : fit.edges_m[1];
  const double minus_u = flipped ? fit.edges_m[1] : -fit.edges_m[0];
  const double plus_v = flipped ? -fit.edges_m[2] : fit.edges_m[3];
  const double minus_v = flipped ? fit.edges_m[3] : -fit.edges_m[2];
  struct Side {
    double error_m;
    Eigen::Vector2d normal;
  };
  const Eigen::Vector2d u(std::cos(id.yaw), std::sin(id.yaw)), v(-u.y(), u.x());
  const std::array<Side, 4> sides{Side{plus_u - id.half_length_m, u}, Side{minus_u - id.half_length_m, -u},
                                  Side{plus_v - id.half_width_m, v}, Side{minus_v - id.half_width_m, -v}};
  const Eigen::Vector2d ahead(std::cos(heading_rad), std::sin(heading_rad)), left(-ahead.y(), ahead.x());
  const auto pick = [&](const Eigen::Vector2d& direction) {
    const Side* best = &sides[0];
    for (const Side& s : sides)
      if (s.normal.dot(direction) > best->normal.dot(direction)) best = &s;
    return best->error_m;
  };
  return {pick(-ahead), pick(ahead), pick(left), pick(-left)};
}

double median(std::vector<double>& values) {
  if (values.empty()) return std::numeric_limits<double>::quiet_NaN();
  const auto mid = values.begin() + static_cast<std::ptrdiff_t>(values.size() / 2);
  std::nth_element(values.begin(), mid, values.end());
  return *mid;
}

std::vector<Eigen::Vector2d> turned(const std::vector<Eigen::Vector2d>& points, double yaw) {
  const double c = std::cos(yaw), s = std::sin(yaw);
  std::vector<Eigen::Vector2d> out;
  out.reserve(points.size());
  for (const Eigen::Vector2d& p : points) out.emplace_back(c * p.x() + s * p.y(), -s * p.x() + c * p.y());
  return out;
}

// The yaw of the smallest rectangle around the cell centres, in [0, 90)
// deg; a box's cells fill its own rectangle best, at any size ratio (a
// square's principal axes, by contrast, are undefined).
double min_area_yaw(const std::vector<Eigen::Vector2d>& points) {
  double best_yaw = 0.0, best_area = std::numeric_limits<double>::infinity();
  for (int k = 0; k < 180; ++k) {
    const double yaw = k * 0.5 * std::numbers::pi / 180.0;
    const double c = std::cos(yaw), s = std::sin(yaw);
    Eigen::Vector2d lo = Eigen::Vector2d::Constant(std::numeric_limits<double>::infinity()), hi = -lo;
    for (const Eigen::Vector2d& p : points) {
      const Eigen::Vector2d q(c * p.x() + s * p.y(), -s * p.x() + c * p.y());
      lo = lo.cwiseMin(q);
      hi = hi.cwiseMax(q);
    }
    const double area = (hi - lo).prod();
    if (area < best_area - 1e-12) {
      best_area = area;
      best_yaw = yaw;
    }
  }
  return best_yaw;
}

// The span along one axis of the rows (bins one cell wide) holding at
// least half as many cells as the fullest, as the first and last row's
// centres: a row of a few stray cells along an edge is not the object.
std::pair<double, double> trimmed_span(const std::vector<Eigen::Vector2d>& cells, int axis, double s) {
  double lo = std::numeric_limits<double>::infinity();
  for (const Eigen::Vector2d& c : cells) lo = std::min(lo, c[axis]);
  std::vector<int> counts;
  for (const Eigen::Vector2d& c : cells) {
    const auto bin = static_cast<std::size_t>(std::lround((c[axis] - lo) / s));
    if (bin >= counts.size()) counts.resize(bin + 1, 0);
    ++counts[bin];
  }
  const int fullest = *std::max_element(counts.begin(), counts.end());
  std::size_t first = counts.size(), last = 0;
  for (std::size_t b = 0; b < counts.size(); ++b) {
    if (2 * counts[b] < fullest) continue;
    first = std::min(first, b);
    last = std::max(last, b);
  }
  return {lo + static_cast<double>(first) * s, lo + static_cast<double>(last) * s};
}

double trimmed_extent(const std::vector<Eigen::Vector2d>& cells, int axis, double s) {
  const auto [lo, hi] = trimmed_span(cells, axis, s);
  return hi - lo;
}

double untrimmed_extent(const std::vector<Eigen::Vector2d>& cells, int axis) {
  double lo = std::numeric_limits<double>::infinity(), hi = -lo;
  for (const Eigen::Vector2d& c : cells) {
    lo = std::min(lo, c[axis]);
    hi = std::max(hi, c[axis]);
  }
  return hi - lo;
}

// A rectangle of length L covered by cells of side s: the covering cells'
// centres span L + s on average, and a uniform spread over a span of n
// cells has variance ((n s)^2 - s^2) / 12, hence L = sqrt(12 var + s^2) - s.
double moment_extent(const std::vector<Eigen::Vector2d>& cells, int axis, double s) {
  double mean = 0.0;
  for (const Eigen::Vector2d& c : cells) mean += c[axis];
  mean /= static_cast<double>(cells.size());
  double var = 0.0;
  for (const Eigen::Vector2d& c : cells) var += (c[axis] - mean) * (c[axis] - mean);
  var /= static_cast<double>(cells.size());
  return std::max(0.0, std::sqrt(12.0 * var + s * s) - s);
}

using CellIndex = std::pair<Eigen::Index, Eigen::Index>;

struct Flood {
  CellMask mask;
  std::vector<CellIndex> order;  ///< as visited: the sums over the cells keep their order
};

// The cells 4-connected to `seed` that `admit` lets in.
template <typename Admit>
Flood flood_from(Eigen::Index n, CellIndex seed, const Admit& admit) {
  Flood flood{CellMask::Zero(n, n), {}};
  std::deque<CellIndex> queue{seed};
  flood.mask(seed.first, seed.second) = 1;
  while (!queue.empty()) {
    const auto [i, j] = queue.front();
    queue.pop_front();
    flood.order.emplace_back(i, j);
    for (const auto& [di, dj] : {std::pair{1, 0}, {-1, 0}, {0, 1}, {0, -1}}) {
      const Eigen::Index a = i + di, b = j + dj;
      if (a < 0 || b < 0 || a >= n || b >= n || flood.mask(a, b) || !admit(a, b)) continue;
      flood.mask(a, b) = 1;
      queue.emplace_back(a, b);
    }
  }
  return flood;
}

// The readings that set the border cells of `mask` (a measured cell with a
// neighbour outside), relative to `centre`, for the sub-cell edges.
struct BorderReadings {
  std::vector<Eigen::Vector2d> points;
  std::vector<Eigen::Vector2d> cells;  ///< the centre of the cell each point set
  std::vector<double> heights_m;       ///< the elevation each point set
  /// Each point moved along its beam to the top's level; empty when the
  /// sensor's height is not known (ObjectMeasureOptions::sensor_height_m).
  std::vector<Eigen::Vector2d> on_level;
  /// The same move along the track too (ObjectMeasureOptions::sensor_pitch_rad);
  /// empty when the pitch is not known.
  std::vector<Eigen::Vector2d> on_beam_level;
};

BorderReadings border_readings(const MapSnapshot& m, const CellMask& mask, const Eigen::Vector2d& centre) {
  BorderReadings border;
  const ExportedLayer* top_x = m.find("top_point_x");
  const ExportedLayer* top_y = m.find("top_point_y");
  if (!top_x || !top_y || top_x->spec.type != LayerType::f32 || top_y->spec.type != LayerType::f32) return border;
  const Eigen::Index n = mask.rows();
  for (Eigen::Index i = 0; i < n; ++i) {
    for (Eigen::Index j = 0; j < n; ++j) {
      if (!mask(i, j) || static_cast<CellState>(m.state()(i, j)) != CellState::measured) continue;
      bool inside = true;
      for (Eigen::Index a = i - 1; a <= i + 1 && inside; ++a)
        for (Eigen::Index b = j - 1; b <= j + 1; ++b)
          if (a < 0 || b < 0 || a >= n || b >= n || !mask(a, b)) {
            inside = false;
            break;
          }
      const Eigen::Vector2d p(top_x->f32(i, j), top_y->f32(i, j));
      if (!inside && p.allFinite()) {
        border.points.push_back(p - centre);
        border.cells.push_back(m.cell_center(i, j) - centre);
        border.heights_m.push_back(m.elevation_m()(i, j));
      }
    }
  }
  return border;
}

// Each reading moved across the track along its beam to `level_m`
// (ObjectMeasureOptions::sensor_height_m); `path_point_m` is on the track,
// in the readings' frame. With `pitch_rad` known (else NaN), the same
// readings moved along the track as well, by cot(pitch) per unit of drop.
void to_top_level(BorderReadings& border, const Eigen::Vector2d& path_point_m, double heading_rad,
                  double sensor_height_m, double pitch_rad, double level_m) {
  const Eigen::Vector2d ahead(std::cos(heading_rad), std::sin(heading_rad)), across(-ahead.y(), ahead.x());
  const double drop_to_level = sensor_height_m - level_m;
  const bool along_known = std::isfinite(pitch_rad);
  border.on_level = border.points;
  for (std::size_t k = 0; k < border.points.size(); ++k) {
    const double drop = sensor_height_m - border.heights_m[k];
    // A reading level with or above the sensor has no usable beam.
    if (!(drop > 0.0) || !(drop_to_level > 0.0)) continue;
    const double run = across.dot(border.points[k] - path_point_m);
    border.on_level[k] += across * (run * (drop_to_level / drop - 1.0));
  }
  if (!along_known) return;
  border.on_beam_level = border.on_level;
  for (std::size_t k = 0; k < border.points.size(); ++k) {
    const double drop = sensor_height_m - border.heights_m[k];
    if (!(drop > 0.0) || !(drop_to_level > 0.0)) continue;
    border.on_beam_level[k] += ahead * ((drop_to_level - drop) / std::tan(pitch_rad));
  }
}

// The ground the height is measured from: the median of a ring of known
// cells around the region (not the region's own neighbourhood median,
// which other objects may raise); `fallback` when the ring is empty.
double ring_ground(const MapSnapshot& m, const CellMask& region, double ring_m, double fallback) {
  const Eigen::MatrixXf& heights = m.elevation_m();
  const Eigen::Index n = heights.rows();
  const auto ring_cells = static_cast<Eigen::Index>(std::ceil(ring_m / m.cell_size_m));
  std::vector<double> ring;
  for (Eigen::Index i = 0; i < n; ++i) {
    for (Eigen::Index j = 0; j < n; ++j) {
      if (region(i, j) || static_cast<CellState>(m.state()(i, j)) == CellState::unknown) continue;
      bool near = false;
      for (Eigen::Index a = std::max<Eigen::Index>(0, i - ring_cells); a <= std::min(n - 1, i + ring_cells) && !near; ++a)
        for (Eigen::Index b = std::max<Eigen::Index>(0, j - ring_cells); b <= std::min(n - 1, j + ring_cells); ++b)
          if (region(a, b)) {
            near = true;
            break;
          }
      if (near) ring.push_back(heights(i, j));
    }
  }
  return ring.empty() ? fallback : median(ring);
}

// A box's length and width from its cells (relative to the truth's centre)
// by every estimate, and the one `options.extent` picks as `measured`.
// ObjectMeasureOptions::unlit_far_side_step_m. A far side turned to the
// travel direction meets the frames at many points, the last of them near
// its far corner, and stays as read; one running less than a step along
// the travel direction ends, in the map, at the last frame's stripe, short
// by the part of the step beyond it.
void place_unlit_far_side(BoxEdgeFit& fit, const ObjectMeasureOptions& options) {
  const double step_m = options.unlit_far_side_step_m;
  if (!fit.ok || !(step_m > 0.0)) return;
  const Eigen::Vector2d u(std::cos(fit.yaw_rad), std::sin(fit.yaw_rad)), v(-u.y(), u.x());
  const std::array<Eigen::Vector2d, 4> outward{-u, u, -v, v};  // of edges_m's sides
  const Eigen::Vector2d ahead(std::cos(options.travel_heading_rad), std::sin(options.travel_heading_rad));
  std::size_t far = 0;
  for (std::size_t k = 1; k < outward.size(); ++k) {
    if (outward[k].dot(ahead) > outward[far].dot(ahead)) far = k;
  }
  const double cos_turn = outward[far].dot(ahead);
  const double side_length_m = far < 2 ? fit.width_m : fit.length_m;
  const double along_travel_m = side_length_m * std::sqrt(std::max(0.0, 1.0 - cos_turn * cos_turn));
  const double out_m = 0.5 * std::max(0.0, step_m - along_travel_m) * cos_turn;
  fit.edges_m[far] += far % 2 == 0 ? -out_m : out_m;
  fit.length_m = fit.edges_m[1] - fit.edges_m[0];
  fit.width_m = fit.edges_m[3] - fit.edges_m[2];
}

void measure_box(ObjectMeasurement& out, const std::vector<Eigen::Vector2d>& cells, const BorderReadings& top_border,
                 const BorderReadings& region_border, double s, double height, const Identity& id,
                 const ObjectMeasureOptions& options) {
  // The measured axes, the first one turned to the nearer of the truth's
  // length axis (truth names the dimensions, it does not place them).
  double yaw = min_area_yaw(cells);
  const auto gap = [](double a, double b) { return std::abs(std::remainder(a - b, std::numbers::pi)); };
  if (gap(yaw + std::numbers::pi / 2, id.yaw) < gap(yaw, id.yaw)) yaw += std::numbers::pi / 2;
  out.measured_yaw_rad = std::remainder(yaw, std::numbers::pi);
  const std::vector<Eigen::Vector2d> axes = turned(cells, yaw);
  out.measured_trimmed = {trimmed_extent(axes, 0, s), trimmed_extent(axes, 1, s), height};
  out.measured_untrimmed = {untrimmed_extent(axes, 0), untrimmed_extent(axes, 1), height};
  const ObjectDimensions moments{moment_extent(axes, 0, s), moment_extent(axes, 1, s), height};
  // The sides the edge readings are sorted to: the trimmed rows' outer
  // cell faces, in the turned frame.
  const auto [u_lo, u_hi] = trimmed_span(axes, 0, s);
  const auto [v_lo, v_hi] = trimmed_span(axes, 1, s);
  const BoxFrame frame{yaw, u_lo - s / 2, u_hi + s / 2, v_lo - s / 2, v_hi + s / 2};
  BoxEdgeOptions edge_options = options.edges;
  edge_options.view_path_point_m = options.travel_point_m - Eigen::Vector2d(id.cx, id.cy);
  constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();
  out.edges_trimmed = out.edges_untrimmed = {kNaN, kNaN, height};
  // The top's border first; where a side of it holds too few readings
  // (a top broken up by noise), the whole region's border.
  const BorderReadings* border = &top_border;
  BoxEdgeFit trimmed = fit_box_edges(border->points, frame, s, true, edge_options, border->cells, border->on_level,
                                     border->on_beam_level);
  if (!trimmed.ok) {
    border = &region_border;
    trimmed = fit_box_edges(border->points, frame, s, true, edge_options, border->cells, border->on_level,
                            border->on_beam_level);
  }
  place_unlit_far_side(trimmed, options);
  BoxEdgeFit untrimmed = fit_box_edges(border->points, frame, s, false, edge_options, border->cells,
                                       border->on_level, border->on_beam_level);
  place_unlit_far_side(untrimmed, options);
  if (trimmed.ok) {
    out.edges_trimmed = {trimmed.length_m, trimmed.width_m, height};
    out.edge_errors_m = edge_errors(trimmed, id, options.travel_heading_rad);
    out.measured_yaw_rad = std::remainder(trimmed.yaw_rad, std::numbers::pi);
  }
  if (untrimmed.ok) out.edges_untrimmed = {untrimmed.length_m, untrimmed.width_m, height};
  switch (options.extent) {
    case ExtentEstimate::edges:
      out.measured = trimmed.ok ? out.edges_trimmed : untrimmed.ok ? out.edges_untrimmed : moments;
      break;
    case ExtentEstimate::moments: out.measured = moments; break;
    case ExtentEstimate::trimmed: out.measured = out.measured_trimmed; break;
    case ExtentEstimate::untrimmed: out.measured = out.measured_untrimmed; break;
  }
}

ObjectMeasurement measure_one(const MapSnapshot& m, const Identity& id, const ObjectMeasureOptions& options) {
  ObjectMeasurement out;
  const Eigen::MatrixXf& heights = m.elevation_m();
  const CellMask& states = m.state();
  const Eigen::Index n = heights.rows();
  const double s = m.cell_size_m;
  const auto known = [&](Eigen::Index i, Eigen::Index j) {
    return static_cast<CellState>(states(i, j)) != CellState::unknown;
  };
  const Eigen::Vector2d centre(id.cx, id.cy);
  const auto distance = [&](Eigen::Index i, Eigen::Index j) { return (m.cell_center(i, j) - centre).norm(); };

  // First guesses from the neighbourhood: the ground is most of it, the top
  // is what stands at the centre.
  std::vector<double> around, at_centre;
  for (Eigen::Index i = 0; i < n; ++i) {
    for (Eigen::Index j = 0; j < n; ++j) {
      if (!known(i, j)) continue;
      const double d = distance(i, j);
      if (d <= options.neighbourhood_m) around.push_back(heights(i, j));
      if (d <= 1.5 * s) at_centre.push_back(heights(i, j));
    }
  }
  if (around.empty() || at_centre.empty()) return out;
  const double ground_guess = median(around);
  const double top_m = median(at_centre);
  if (!(top_m > ground_guess)) return out;
  const double threshold = ground_guess + options.height_fraction * (top_m - ground_guess);
  const auto qualifies = [&](Eigen::Index i, Eigen::Index j) {
    const bool admitted = options.region_measured_only
                              ? static_cast<CellState>(states(i, j)) == CellState::measured
                              : known(i, j);
    return admitted && heights(i, j) > threshold && distance(i, j) <= options.neighbourhood_m;
  };

  Eigen::Index seed_i = -1, seed_j = -1;
  double best = 2.5 * s;
  for (Eigen::Index i = 0; i < n; ++i) {
    for (Eigen::Index j = 0; j < n; ++j) {
      if (!qualifies(i, j) || distance(i, j) > best) continue;
      best = distance(i, j);
      seed_i = i;
      seed_j = j;
    }
  }
  if (seed_i < 0) return out;

  const Flood region = flood_from(n, {seed_i, seed_j}, qualifies);
  std::vector<Eigen::Vector2d> cells;
  std::vector<double> tops;
  for (const auto& [i, j] : region.order) {
    cells.push_back(m.cell_center(i, j) - centre);
    if (static_cast<CellState>(states(i, j)) == CellState::measured) tops.push_back(heights(i, j));
  }
  // The box's top: the region's cells within a band below its median top,
  // grown from the seed. Mixed pixels at an edge leave a ramp of readings
  // between the top and the floor behind it, which rises above half the
  // height for some way beyond the edge; a box's top is flat, so the ramp
  // leaves the band within a few millimetres.
  std::vector<double> top_values = tops;
  const double top_level = top_values.empty() ? threshold : median(top_values);
  // A dark or far top is noisier than the band: widen it to the top's own
  // spread (2.5 robust standard deviations), never below the threshold.
  std::vector<double> deviations;
  for (const double t : tops) deviations.push_back(std::abs(t - top_level));
  const double spread = deviations.empty() ? 0.0 : 2.5 * 1.4826 * median(deviations);
  const double band = std::min(std::max(options.edge_band_m, spread), top_level - threshold);
  const Flood top = flood_from(n, {seed_i, seed_j}, [&](Eigen::Index a, Eigen::Index b) {
    return region.mask(a, b) && heights(a, b) >= top_level - band;
  });
  const double ground_m = ring_ground(m, region.mask, options.ground_ring_m, ground_guess);

  out.found = true;
  out.cells = cells.size();
  const double height = (tops.empty() ? threshold : median(tops)) - ground_m;
  if (id.round) {
    // A grid of cells of side s touching a disk of radius R covers on
    // average pi R^2 + 4 R s + s^2 (the area of the disk grown by a cell);
    // solving for R uses every cell, so a stray cell moves it by s^2 only.
    const double area = static_cast<double>(cells.size()) * s * s;
    const double pi = std::numbers::pi;
    const double radius = (-4.0 * s + std::sqrt(16.0 * s * s - 4.0 * pi * (s * s - area))) / (2.0 * pi);
    out.measured = out.measured_trimmed = out.measured_untrimmed = out.edges_trimmed = out.edges_untrimmed =
        {2.0 * radius, 2.0 * radius, height};
    return out;
  }
  BorderReadings top_border = border_readings(m, top.mask, centre);
  if (std::isfinite(options.sensor_height_m) && options.travel_point_m.allFinite()) {
    const double robust_sd = deviations.empty() ? 0.0 : 1.4826 * median(deviations);
    to_top_level(top_border, options.travel_point_m - centre, options.travel_heading_rad, options.sensor_height_m,
                 options.sensor_pitch_rad, top_level - options.level_below_top_sds * robust_sd);
  }
  measure_box(out, cells, top_border, border_readings(m, region.mask, centre), s, height, id, options);
  return out;
}

}  // namespace

const char* to_string(EdgeSide side) {
  switch (side) {
    case EdgeSide::near: return "near";
    case EdgeSide::far: return "far";
    case EdgeSide::left: return "left";
    case EdgeSide::right: return "right";
  }
  return "?";
}

double relative_error_pct(double measured, double truth) {
  return truth != 0.0 ? (measured - truth) / truth * 100.0 : std::numeric_limits<double>::quiet_NaN();
}

void validate(const ObjectMeasureOptions& options) {
  const double pitch = options.sensor_pitch_rad;
  if (!std::isnan(pitch) && !(pitch > 0.0 && pitch < std::numbers::pi / 2)) {
    throw InputError("object measurement: sensor_pitch_rad must be NaN (unknown) or in (0, pi/2), got " +
                     std::to_string(pitch));
  }
  if (!(std::isfinite(options.level_below_top_sds) && options.level_below_top_sds >= 0.0)) {
    throw InputError("object measurement: level_below_top_sds must be finite and >= 0, got " +
                     std::to_string(options.level_below_top_sds));
  }
  const double step = options.unlit_far_side_step_m;
  if (!std::isnan(step) && !(step > 0.0 && step < 1.0)) {
    throw InputError("object measurement: unlit_far_side_step_m must be NaN (sides as read) or in (0, 1) m, got " +
                     std::to_string(step));
  }
}

std::vector<ObjectMeasurement> measure_objects(const MapSnapshot& snapshot, const Scene& scene,
                                               const ObjectMeasureOptions& options) {
  validate(options);
  std::vector<ObjectMeasurement> results;
  for (const BoxObject& box : scene.boxes) {
    ObjectMeasurement m = measure_one(
        snapshot, {box.center_x_m, box.center_y_m, box.yaw_rad, false, box.length_m / 2, box.width_m / 2}, options);
    m.name = box.name;
    m.kind = "box";
    m.truth = {box.length_m, box.width_m, box.top_m() - scene.terrain.height_at(box.center_x_m, box.center_y_m)};
    results.push_back(std::move(m));
  }
  for (const CylinderObject& cyl : scene.cylinders) {
    ObjectMeasurement m = measure_one(snapshot, {cyl.center_x_m, cyl.center_y_m, 0.0, true}, options);
    m.name = cyl.name;
    m.kind = "cylinder";
    m.truth = {2 * cyl.radius_m, 2 * cyl.radius_m,
               cyl.top_m() - scene.terrain.height_at(cyl.center_x_m, cyl.center_y_m)};
    results.push_back(std::move(m));
  }
  return results;
}

}  // namespace stridemap
