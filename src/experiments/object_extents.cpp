#include "stridemap/experiments/object_extents.hpp"

#include <algorithm>
#include <cmath>
#include <deque>
#include <limits>

namespace stridemap {
namespace {

struct Footprint {
  double cx, cy;           // centre [m]
  double half_x, half_y;   // half extents along the object's axes [m]
  double yaw;              // axes of the object
  bool round;
};

double median(std::vector<double>& values) {
  if (values.empty()) return std::numeric_limits<double>::quiet_NaN();
  const auto mid = values.begin() + static_cast<std::ptrdiff_t>(values.size() / 2);
  std::nth_element(values.begin(), mid, values.end());
  return *mid;
}

// Offsets of a point in the object's axes.
Eigen::Vector2d in_object_axes(const Footprint& f, double x, double y) {
  const double c = std::cos(f.yaw), s = std::sin(f.yaw);
  const double dx = x - f.cx, dy = y - f.cy;
  return {c * dx + s * dy, -s * dx + c * dy};
}

bool inside(const Footprint& f, double x, double y, double margin) {
  const Eigen::Vector2d p = in_object_axes(f, x, y);
  if (f.round) return p.norm() <= f.half_x + margin;
  return std::abs(p.x()) <= f.half_x + margin && std::abs(p.y()) <= f.half_y + margin;
}

// Extent of a box along one of its axes from the region's profile: the
// rows (bins one cell wide) holding at least half as many cells as the
// fullest row are the object; a row of a few stray cells along an edge is
// not. For a max-height map the spread of the kept bins' centres is an
// unbiased estimate of the true extent.
double profile_extent(const std::vector<Eigen::Vector2d>& cells, int axis, double s) {
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
  return static_cast<double>(last - first) * s;
}

ObjectMeasurement measure_one(const MapSnapshot& m, const Footprint& f,
                              const ObjectMeasureOptions& options) {
  ObjectMeasurement out;
  const Eigen::MatrixXf& heights = m.elevation_m();
  const CellMask& states = m.state();
  const Eigen::Index n = heights.rows();
  const double s = m.cell_size_m;
  const auto centre_of = [&](Eigen::Index i, Eigen::Index j) {
    return Eigen::Vector2d((static_cast<double>(m.min_cell.x + i) + 0.5) * s,
                           (static_cast<double>(m.min_cell.y + j) + 0.5) * s);
  };
  const auto known = [&](Eigen::Index i, Eigen::Index j) {
    return static_cast<CellState>(states(i, j)) != CellState::unknown;
  };

  std::vector<double> ground, search_heights;
  for (Eigen::Index i = 0; i < n; ++i) {
    for (Eigen::Index j = 0; j < n; ++j) {
      if (!known(i, j)) continue;
      const Eigen::Vector2d c = centre_of(i, j);
      if (inside(f, c.x(), c.y(), options.search_margin_m)) {
        search_heights.push_back(heights(i, j));
      } else if (inside(f, c.x(), c.y(), options.search_margin_m + options.ground_ring_m)) {
        ground.push_back(heights(i, j));
      }
    }
  }
  if (search_heights.empty() || ground.empty()) return out;
  const double ground_m = median(ground);
  // The top is a high quantile rather than the maximum, so one spike does not
  // set the threshold.
  std::sort(search_heights.begin(), search_heights.end());
  const double top_m = search_heights[static_cast<std::size_t>(0.95 * static_cast<double>(search_heights.size() - 1))];
  const double threshold = ground_m + options.height_fraction * (top_m - ground_m);

  // Seed: the qualifying cell nearest the object's centre.
  Eigen::Index seed_i = -1, seed_j = -1;
  double best = std::numeric_limits<double>::infinity();
  const auto qualifies = [&](Eigen::Index i, Eigen::Index j) {
    if (!known(i, j) || heights(i, j) <= threshold) return false;
    const Eigen::Vector2d c = centre_of(i, j);
    return inside(f, c.x(), c.y(), options.search_margin_m);
  };
  for (Eigen::Index i = 0; i < n; ++i) {
    for (Eigen::Index j = 0; j < n; ++j) {
      if (!qualifies(i, j)) continue;
      const double d = (centre_of(i, j) - Eigen::Vector2d(f.cx, f.cy)).norm();
      if (d < best) {
        best = d;
        seed_i = i;
        seed_j = j;
      }
    }
  }
  if (seed_i < 0) return out;

  CellMask visited = CellMask::Zero(n, n);
  std::deque<std::pair<Eigen::Index, Eigen::Index>> queue{{seed_i, seed_j}};
  visited(seed_i, seed_j) = 1;
  std::vector<Eigen::Vector2d> cells;  // centres in the object's axes
  std::vector<double> tops;
  while (!queue.empty()) {
    const auto [i, j] = queue.front();
    queue.pop_front();
    const Eigen::Vector2d c = centre_of(i, j);
    cells.push_back(in_object_axes(f, c.x(), c.y()));
    if (static_cast<CellState>(states(i, j)) == CellState::measured) tops.push_back(heights(i, j));
    for (const auto& [di, dj] : {std::pair{1, 0}, {-1, 0}, {0, 1}, {0, -1}}) {
      const Eigen::Index a = i + di, b = j + dj;
      if (a < 0 || b < 0 || a >= n || b >= n || visited(a, b) || !qualifies(a, b)) continue;
      visited(a, b) = 1;
      queue.emplace_back(a, b);
    }
  }
  out.found = true;
  out.cells = cells.size();
  if (f.round) {
    // A grid of cells of side s touching a disk of radius R covers on
    // average pi R^2 + 4 R s + s^2 (the area of the disk grown by a cell);
    // solving for R uses every cell, so a stray cell moves it by s^2 only.
    const double area = static_cast<double>(cells.size()) * s * s;
    const double pi = 3.14159265358979323846;
    const double radius = (-4.0 * s + std::sqrt(16.0 * s * s - 4.0 * pi * (s * s - area))) / (2.0 * pi);
    out.measured.length_m = out.measured.width_m = 2.0 * radius;
  } else {
    out.measured.length_m = profile_extent(cells, 0, s);
    out.measured.width_m = profile_extent(cells, 1, s);
  }
  out.measured.height_m = (tops.empty() ? threshold : median(tops)) - ground_m;
  return out;
}

}  // namespace

double relative_error_pct(double measured, double truth) {
  return truth != 0.0 ? (measured - truth) / truth * 100.0 : std::numeric_limits<double>::quiet_NaN();
}

std::vector<ObjectMeasurement> measure_objects(const MapSnapshot& snapshot, const Scene& scene,
                                               const ObjectMeasureOptions& options) {
  std::vector<ObjectMeasurement> results;
  for (const BoxObject& box : scene.boxes) {
    const Footprint f{box.center_x_m, box.center_y_m, box.length_m / 2, box.width_m / 2, box.yaw_rad, false};
    ObjectMeasurement m = measure_one(snapshot, f, options);
    m.name = box.name;
    m.kind = "box";
    m.truth = {box.length_m, box.width_m, box.top_m() - scene.terrain.height_at(box.center_x_m, box.center_y_m)};
    results.push_back(std::move(m));
  }
  for (const CylinderObject& cyl : scene.cylinders) {
    const Footprint f{cyl.center_x_m, cyl.center_y_m, cyl.radius_m, cyl.radius_m, 0.0, true};
    ObjectMeasurement m = measure_one(snapshot, f, options);
    m.name = cyl.name;
    m.kind = "cylinder";
    m.truth = {2 * cyl.radius_m, 2 * cyl.radius_m,
               cyl.top_m() - scene.terrain.height_at(cyl.center_x_m, cyl.center_y_m)};
    results.push_back(std::move(m));
  }
  return results;
}

}  // namespace stridemap

