#include "stridemap/experiments/box_edges.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <utility>

#include <Eigen/Eigenvalues>

namespace stridemap {
namespace {

struct Reading {
  // In the box frame, the v sides' readings turned by -90 deg, so that all
  // four sides share one normal: (u, v) for the u sides, (v, -u) for the v sides.
  Eigen::Vector2d q;
  int side;
  std::size_t index;  // into the caller's readings
  bool active = true;
  double residual = 0.0;
};

// The parameters t at which p + t * direction enters and leaves the square
// of side `size` around `centre` (p inside it).
std::pair<double, double> chord(const Eigen::Vector2d& p, const Eigen::Vector2d& direction, const Eigen::Vector2d& centre,
                                double size) {
  double lo = -std::numeric_limits<double>::infinity(), hi = std::numeric_limits<double>::infinity();
  for (int axis = 0; axis < 2; ++axis) {
    if (std::abs(direction[axis]) < 1e-12) continue;
    const double a = (centre[axis] - size / 2 - p[axis]) / direction[axis];
    const double b = (centre[axis] + size / 2 - p[axis]) / direction[axis];
    lo = std::max(lo, std::min(a, b));
    hi = std::min(hi, std::max(a, b));
  }
  // A reading rounded onto its cell's face still lies on its own chord.
  return {std::min(lo, 0.0), std::max(hi, 0.0)};
}

// The edge offset from the readings' offsets and their chords' covered
// parts, each reading uniform on [a, min(e, b)] of its own chord. The edge
// is at least the outermost reading m; a chord reaching past m is cut by
// the edge, and the outermost of n readings uniform on a part of length L
// falls short of its end by L / (n + 1) on average, so
// e = m + (m - mean a) / n is unbiased (the classic estimate of a uniform's
// end, a + (m - a)(n + 1)/n). Chords that end inside m lie wholly on the top
// and say nothing of the edge. NaN without readings.
double stripe_edge(const std::vector<std::array<double, 3>>& parts) {
  if (parts.empty()) return std::numeric_limits<double>::quiet_NaN();
  double outermost = -std::numeric_limits<double>::infinity();
  for (const auto& part : parts) outermost = std::max(outermost, part[0]);
  double inner_sum = 0.0;
  int cut = 0;
  for (const auto& [offset, a, b] : parts) {
    if (b < outermost) continue;
    inner_sum += a;
    ++cut;
  }
  return outermost + (outermost - inner_sum / cut) / cut;
}

double quantile(std::vector<double>& values, double q) {
  std::sort(values.begin(), values.end());
  const double position = std::clamp(q, 0.0, 1.0) * static_cast<double>(values.size() - 1);
  const auto lo = static_cast<std::size_t>(std::floor(position));
  const std::size_t hi = std::min(lo + 1, values.size() - 1);
  return values[lo] + (values[hi] - values[lo]) * (position - static_cast<double>(lo));
}

}  // namespace

BoxEdgeFit fit_box_edges(const std::vector<Eigen::Vector2d>& readings, const BoxFrame& frame, double cell_size_m,
                         bool trim, const BoxEdgeOptions& options, const std::vector<Eigen::Vector2d>& reading_cells,
                         const std::vector<Eigen::Vector2d>& level_readings,
                         const std::vector<Eigen::Vector2d>& beam_level_readings) {
  BoxEdgeFit fit;
  const double c = std::cos(frame.yaw_rad), s = std::sin(frame.yaw_rad);
  const auto shared_normal_frame = [&](const Eigen::Vector2d& p, int side) {
    const double u = c * p.x() + s * p.y(), v = -s * p.x() + c * p.y();
    return side < 2 ? Eigen::Vector2d(u, v) : Eigen::Vector2d(v, -u);
  };
  std::vector<Reading> sorted;
  sorted.reserve(readings.size());
  for (std::size_t index = 0; index < readings.size(); ++index) {
    const Eigen::Vector2d& p = readings[index];
    const double u = c * p.x() + s * p.y(), v = -s * p.x() + c * p.y();
    std::array<double, 4> distance{std::abs(u - frame.u_min_m), std::abs(frame.u_max_m - u),
                                   std::abs(v - frame.v_min_m), std::abs(frame.v_max_m - v)};
    std::array<int, 4> order{0, 1, 2, 3};
    std::sort(order.begin(), order.end(), [&](int a, int b) { return distance[a] < distance[b]; });
    if (distance[order[1]] < options.corner_cells * cell_size_m) continue;
    const int side = order[0];
    sorted.push_back({shared_normal_frame(p, side), side, index});
  }
  // A short side may hold its readings only near its corners: use them
  // rather than give up.
  std::array<std::size_t, 4> per_side{};
  for (const Reading& r : sorted) ++per_side[r.side];
  if (*std::min_element(per_side.begin(), per_side.end()) < 2 && options.corner_cells > 0.0) {
    BoxEdgeOptions no_corners = options;
    no_corners.corner_cells = 0.0;
    return fit_box_edges(readings, frame, cell_size_m, trim, no_corners, reading_cells, level_readings,
                         beam_level_readings);
  }

  Eigen::Vector2d normal(1.0, 0.0);
  std::array<Eigen::Vector2d, 4> centroid{};
  const int rounds = trim ? std::max(1, options.trim_rounds + 1) : 1;
  for (int round = 0; round < rounds; ++round) {
    std::array<std::size_t, 4> count{};
    centroid.fill(Eigen::Vector2d::Zero());
    for (const Reading& r : sorted) {
      if (!r.active) continue;
      centroid[r.side] += r.q;
      ++count[r.side];
    }
    fit.points = count;
    if (*std::min_element(count.begin(), count.end()) < 2) return fit;
    for (int k = 0; k < 4; ++k) centroid[k] /= static_cast<double>(count[k]);
    Eigen::Matrix2d scatter = Eigen::Matrix2d::Zero();
    for (const Reading& r : sorted) {
      if (!r.active) continue;
      const Eigen::Vector2d d = r.q - centroid[r.side];
      scatter += d * d.transpose();
    }
    const Eigen::SelfAdjointEigenSolver<Eigen::Matrix2d> solver(scatter);
    normal = solver.eigenvectors().col(0);  // eigenvalues ascend: the smallest spread
    if (normal.x() < 0.0) normal = -normal;
    std::vector<double> spread;
    for (Reading& r : sorted) {
      r.residual = normal.dot(r.q - centroid[r.side]);
      if (r.active) spread.push_back(std::abs(r.residual));
    }
    if (round + 1 == rounds) break;
    const double band = std::max(options.trim_sigmas * 1.4826 * quantile(spread, 0.5), options.min_trim_m);
    std::array<std::size_t, 4> kept{};
    for (Reading& r : sorted) {
      r.active = std::abs(r.residual) <= band;
      kept[r.side] += r.active ? 1 : 0;
    }
    // Trimming never empties a side: a side it would leave with fewer than
    // two readings keeps them all.
    for (Reading& r : sorted) r.active = r.active || kept[r.side] < 2;
  }

  fit.yaw_rad = frame.yaw_rad + std::atan2(normal.y(), normal.x());
  // Each side's edge: its line moved out to the quantile of its readings
  // (a lower one on a face the sensor saw).
  const Eigen::Vector2d u_axis(std::cos(fit.yaw_rad), std::sin(fit.yaw_rad)), v_axis(-u_axis.y(), u_axis.x());
  const Eigen::Vector2d view(std::cos(options.view_heading_rad), std::sin(options.view_heading_rad));
  const Eigen::Vector2d stripe_direction(-view.y(), view.x());
  const bool cells_known = reading_cells.size() == readings.size();
  const bool levels_known = level_readings.size() == readings.size();
  const bool beam_levels_known = beam_level_readings.size() == readings.size();
  std::array<double, 4> edge{};
  for (int k = 0; k < 4; ++k) {
    const double outward = (k == 1 || k == 3) ? 1.0 : -1.0;
    const Eigen::Vector2d outward_normal = outward * (k < 2 ? u_axis : v_axis);
    fit.facing[k] = std::isfinite(options.view_heading_rad) && outward_normal.dot(view) < -options.facing_cos;
    const bool along_view = std::isfinite(options.view_heading_rad) && std::abs(outward_normal.dot(view)) <= options.facing_cos;
    // How far the side drifts across the grid over its readings' length: a
    // side that drifts a cell or more crosses its cells at every phase, so
    // some border cells hold only a sliver of top, their readings lie at the
    // edge and the quantile reaches it.
    // The side's middle tells which way its face looks from the path.
    const Eigen::Vector2d along = k < 2 ? v_axis : u_axis;
    double first = std::numeric_limits<double>::infinity(), last = -first;
    Eigen::Vector2d on_side = Eigen::Vector2d::Zero();
    int side_count = 0;
    for (const Reading& r : sorted) {
      if (!r.active || r.side != k) continue;
      first = std::min(first, along.dot(readings[r.index]));
      last = std::max(last, along.dot(readings[r.index]));
      on_side += readings[r.index];
      ++side_count;
    }
    const double drift = (last - first) * std::min(std::abs(along.x()), std::abs(along.y()));
    const bool on_grid = drift < cell_size_m;
    const bool face_hidden = options.view_path_point_m.allFinite() && side_count > 0 &&
                             outward_normal.dot(options.view_path_point_m - on_side / side_count) < 0.0;
    std::vector<double> offsets;
    std::vector<std::array<double, 3>> parts;  // offset, then the chord's inner and outer end, outwards
    const double slope = outward_normal.dot(stripe_direction);
    const bool by_stripes = options.stripe_chords && cells_known && along_view && on_grid && face_hidden;
    // A side along the view: its readings' across-track place is where
    // their beams meet the top, not where range noise left them. The line
    // and the trimming keep the readings as found, so the other sides and
    // the orientation stay as they were.
    const bool on_level = levels_known && along_view;
    // A side facing away: its readings lie on the last scans over the top,
    // spread along their beams; back at the top's level, on those scans.
    const bool away = std::isfinite(options.view_heading_rad) && outward_normal.dot(view) > options.facing_cos;
    const bool on_beam_level = beam_levels_known && away;
    for (const Reading& r : sorted) {
      if (r.side != k) continue;
      const Eigen::Vector2d& at = on_level        ? level_readings[r.index]
                                  : on_beam_level ? beam_level_readings[r.index]
                                                  : readings[r.index];
      const double offset = on_level || on_beam_level ? outward * normal.dot(shared_normal_frame(at, k) - centroid[k])
                                                      : outward * r.residual;
      if (r.active) offsets.push_back(offset);
      // Every reading: trimming takes the line's spread for noise, but on
      // such a side the readings spread over the covered parts of their
      // cells, and the outermost, the ones the estimate rests on, go first.
      if (!by_stripes) continue;
      const auto [t_lo, t_hi] = chord(at, stripe_direction, reading_cells[r.index], cell_size_m);
      parts.push_back({offset, offset + std::min(t_lo * slope, t_hi * slope), offset + std::max(t_lo * slope, t_hi * slope)});
    }
    const double stripe = stripe_edge(parts);
    fit.stripe[k] = std::isfinite(stripe);
    edge[k] = normal.dot(centroid[k]) +
              outward * (fit.stripe[k] ? stripe
                                       : quantile(offsets, fit.facing[k] ? options.facing_edge_quantile : options.edge_quantile));
  }
  fit.ok = true;
  fit.length_m = edge[1] - edge[0];
  fit.width_m = edge[3] - edge[2];
  fit.edges_m = edge;
  return fit;
}

}  // namespace stridemap
