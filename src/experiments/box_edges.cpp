#include "stridemap/experiments/box_edges.hpp"

#include <algorithm>
#include <cmath>

#include <Eigen/Eigenvalues>

namespace stridemap {
namespace {

struct Reading {
  // In the box frame, the v sides' readings turned by -90 deg, so that all
  // four sides share one normal: (u, v) for the u sides, (v, -u) for the v sides.
  Eigen::Vector2d q;
  int side;
  bool active = true;
  double residual = 0.0;
};

double quantile(std::vector<double>& values, double q) {
  std::sort(values.begin(), values.end());
  const double position = std::clamp(q, 0.0, 1.0) * static_cast<double>(values.size() - 1);
  const auto lo = static_cast<std::size_t>(std::floor(position));
  const std::size_t hi = std::min(lo + 1, values.size() - 1);
  return values[lo] + (values[hi] - values[lo]) * (position - static_cast<double>(lo));
}

}  // namespace

BoxEdgeFit fit_box_edges(const std::vector<Eigen::Vector2d>& readings, const BoxFrame& frame, double cell_size_m,
                         bool trim, const BoxEdgeOptions& options) {
  BoxEdgeFit fit;
  const double c = std::cos(frame.yaw_rad), s = std::sin(frame.yaw_rad);
  std::vector<Reading> sorted;
  sorted.reserve(readings.size());
  for (const Eigen::Vector2d& p : readings) {
    const double u = c * p.x() + s * p.y(), v = -s * p.x() + c * p.y();
    std::array<double, 4> distance{std::abs(u - frame.u_min_m), std::abs(frame.u_max_m - u),
                                   std::abs(v - frame.v_min_m), std::abs(frame.v_max_m - v)};
    std::array<int, 4> order{0, 1, 2, 3};
    std::sort(order.begin(), order.end(), [&](int a, int b) { return distance[a] < distance[b]; });
    if (distance[order[1]] < options.corner_cells * cell_size_m) continue;
    const int side = order[0];
    sorted.push_back({side < 2 ? Eigen::Vector2d(u, v) : Eigen::Vector2d(v, -u), side});
  }
  // A short side may hold its readings only near its corners: use them
  // rather than give up.
  std::array<std::size_t, 4> per_side{};
  for (const Reading& r : sorted) ++per_side[r.side];
  if (*std::min_element(per_side.begin(), per_side.end()) < 2 && options.corner_cells > 0.0) {
    BoxEdgeOptions no_corners = options;
    no_corners.corner_cells = 0.0;
    return fit_box_edges(readings, frame, cell_size_m, trim, no_corners);
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
  std::array<double, 4> edge{};
  for (int k = 0; k < 4; ++k) {
    const double outward = (k == 1 || k == 3) ? 1.0 : -1.0;
    const Eigen::Vector2d outward_normal = outward * (k < 2 ? u_axis : v_axis);
    fit.facing[k] = std::isfinite(options.view_heading_rad) && outward_normal.dot(view) < -options.facing_cos;
    std::vector<double> offsets;
    for (const Reading& r : sorted) {
      if (r.active && r.side == k) offsets.push_back(outward * r.residual);
    }
    edge[k] = normal.dot(centroid[k]) +
              outward * quantile(offsets, fit.facing[k] ? options.facing_edge_quantile : options.edge_quantile);
  }
  fit.ok = true;
  fit.length_m = edge[1] - edge[0];
  fit.width_m = edge[3] - edge[2];
  fit.edges_m = edge;
  return fit;
}

}  // namespace stridemap
