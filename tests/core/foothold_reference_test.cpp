// The foothold layers' plane fits (slope, roughness, step height) against a
// plain per-cell fit written from their definition, bit for bit: the
// refresh fits several cells at once in vector lanes and reads a padded
// copy of the window, and must still give exactly the one-cell arithmetic
// (sums in footprint order, the whole footprint's inverse or a partial
// footprint's own) at the window's border, beside unknown cells and with
// the storage wrapped round by window moves.
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <limits>
#include <numbers>
#include <random>
#include <vector>

#include <Eigen/Dense>
#include <gtest/gtest.h>

#include "stridemap/core/foothold.hpp"
#include "stridemap/core/terrain_mapper.hpp"

namespace stridemap {
namespace {

struct ReferenceGeometry {
  float slope_deg, roughness_m, step_height_m;
};

// One cell's fit, operation for operation as the layers define it.
ReferenceGeometry reference_fit(const ElevationMap& map, const FootholdOptions& o, int i, int j) {
  const float nan = std::numeric_limits<float>::quiet_NaN();
  const double cell = map.cell_size_m();
  const int n = map.cells_per_side();
  const double radius = o.foot_radius_m / cell * (1.0 + 1e-9);
  const auto reach = static_cast<int>(std::floor(radius));
  std::vector<Eigen::Vector2i> footprint;
  for (int dx = -reach; dx <= reach; ++dx) {
    for (int dy = -reach; dy <= reach; ++dy) {
      if (static_cast<double>(dx * dx + dy * dy) <= radius * radius) footprint.emplace_back(dx, dy);
    }
  }
  const std::size_t m = footprint.size();
  std::size_t min_known =
      std::max<std::size_t>(3, static_cast<std::size_t>(std::ceil(o.min_known_fraction * static_cast<double>(m))));
  min_known = std::min(min_known, std::max<std::size_t>(m, 3));
  const auto known = [&](int a, int b, float& z) {
    if (a < 0 || b < 0 || a >= n || b >= n) return false;
    const std::size_t s = map.slot(map.cell_at_local(a, b));
    z = map.elevation_data()[s];
    return map.state_data()[s] != static_cast<std::uint8_t>(CellState::unknown) && std::isfinite(z);
  };
  float centre = 0.0f;
  if (!known(i, j, centre)) return {nan, nan, nan};
  const double z0 = centre;
  double sx = 0.0, sy = 0.0, sxx = 0.0, sxy = 0.0, syy = 0.0, lo = 0.0, hi = 0.0;
  double b0 = 0.0, b1 = 0.0, b2 = 0.0, sum_z2 = 0.0;
  std::size_t kept = 0;
  for (const Eigen::Vector2i& d : footprint) {
    float e = 0.0f;
    if (!known(i + d.x(), j + d.y(), e)) continue;
    const double z = e - z0;
    const double x = d.x() * cell, y = d.y() * cell;
    sx += x;
    sy += y;
    sxx += x * x;
    sxy += x * y;
    syy += y * y;
    b0 += z;
    b1 += x * z;
    b2 += y * z;
    sum_z2 += z * z;
    lo = std::min(lo, z);
    hi = std::max(hi, z);
    ++kept;
  }
  if (kept < min_known) return {nan, nan, nan};
  ReferenceGeometry g{nan, nan, static_cast<float>(hi - lo)};
  Eigen::Matrix3d inverse;
  if (kept == m) {
    Eigen::Matrix3d full = Eigen::Matrix3d::Zero();
    for (const Eigen::Vector2i& d : footprint) {
      const Eigen::Vector3d v(1.0, d.x() * cell, d.y() * cell);
      full.noalias() += v * v.transpose();
    }
    inverse = full.inverse();
  } else {
    Eigen::Matrix3d a;
    a << static_cast<double>(kept), sx, sy, sx, sxx, sxy, sy, sxy, syy;
    bool invertible = false;
    a.computeInverseWithCheck(inverse, invertible, 1e-9 * cell * cell * cell * cell);
    if (!invertible) return g;
  }
  // The plane row by row, left to right; the residuals' sum of squares
  // from the normal equations: sum z^2 - plane . b.
  const Eigen::Vector3d plane(inverse(0, 0) * b0 + inverse(0, 1) * b1 + inverse(0, 2) * b2,
                              inverse(1, 0) * b0 + inverse(1, 1) * b1 + inverse(1, 2) * b2,
                              inverse(2, 0) * b0 + inverse(2, 1) * b1 + inverse(2, 2) * b2);
  const double residual2 = std::max(0.0, sum_z2 - (plane[0] * b0 + plane[1] * b1 + plane[2] * b2));
  g.slope_deg = static_cast<float>(std::atan(std::sqrt(plane[1] * plane[1] + plane[2] * plane[2])) * 180.0 /
                                   std::numbers::pi);
  g.roughness_m = static_cast<float>(std::sqrt(residual2 / static_cast<double>(kept)));
  return g;
}

bool same_float_bits(float a, float b) { return std::memcmp(&a, &b, sizeof a) == 0; }

void walk_against_reference_fits(const FootholdOptions& o, unsigned seed) {
  MapperOptions options;
  options.grid = GridOptions{40, 0.01};
  options.reject_stale_scans = false;
  TerrainMapper mapper(options, SensorMount{});
  FootholdLayers foothold(mapper.map(), o);
  foothold.recompute_all(mapper.map());
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> unit(-1.0, 1.0);
  double x = 0.0, y = 0.0;
  std::vector<MapPoint> points;
  std::size_t compared = 0;
  for (int scan = 0; scan < 40; ++scan) {
    // Drifting both ways, so that the window's storage wraps at every offset.
    x += 0.02 * unit(rng) + 0.005;
    y += 0.02 * unit(rng) - 0.003;
    TrunkPose pose;
    pose.x_m = x;
    pose.y_m = y;
    points.clear();
    const double angle = 3.0 * unit(rng);
    for (int k = 0; k < 50; ++k) {  // a line across the window, with gaps
      if (k % 7 == 3) continue;
      const double t = 0.35 * (k / 49.0 - 0.5);
      const double px = x + 0.1 * std::cos(angle) - t * std::sin(angle);
      const double py = y + 0.1 * std::sin(angle) + t * std::cos(angle);
      const double step_m = std::fmod(std::abs(px + py), 0.1) < 0.03 ? 0.04 : 0.0;
      points.push_back({px, py, 0.03 * std::sin(11 * px) + step_m, 0.02});
    }
    mapper.integrate_points(points, pose);
    foothold.note(mapper.map(), mapper.changed_rows());
    mapper.clear_changed_cells();
    if (scan % 3 != 2) continue;
    foothold.refresh(mapper.map());
    const ElevationMap& map = mapper.map();
    for (int i = 0; i < map.cells_per_side(); ++i) {
      for (int j = 0; j < map.cells_per_side(); ++j) {
        const std::size_t s = map.slot(map.cell_at_local(i, j));
        const ReferenceGeometry r = reference_fit(map, o, i, j);
        ASSERT_TRUE(same_float_bits(map.data(foothold.slope())[s], r.slope_deg))
            << "slope, scan " << scan << " cell " << i << "," << j << " " << map.data(foothold.slope())[s] << " vs " << r.slope_deg;
        ASSERT_TRUE(same_float_bits(map.data(foothold.roughness())[s], r.roughness_m)) << "roughness, scan " << scan;
        ASSERT_TRUE(same_float_bits(map.data(foothold.step_height())[s], r.step_height_m)) << "step, scan " << scan;
        compared += std::isfinite(r.roughness_m) ? 1 : 0;
      }
    }
  }
  EXPECT_GT(compared, 1000u);  // plenty of fitted cells, not only NaN
}

TEST(FootholdReference, PlaneFitsEqualAOneCellFitBitForBit) { walk_against_reference_fits(FootholdOptions{}, 3); }

TEST(FootholdReference, PlaneFitsOfAWiderFootWithThinFootprintsEqualAOneCellFit) {
  FootholdOptions o;
  o.foot_radius_m = 0.03;       // 29 cells
  o.min_known_fraction = 0.2;   // many partial footprints
  walk_against_reference_fits(o, 4);
}

}  // namespace
}  // namespace stridemap
