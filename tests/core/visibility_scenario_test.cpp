// The visibility clean-up (core/visibility_clearing.hpp) as the pipeline runs
// it, against its rule with nothing left out (tests/core/visibility_full_walk.hpp):
// a walking, turning and tilting URG over a floor with a box that hides the
// floor behind it, a box that moves across the stripe, one taken away and
// walked back over, and a foot that steps through the stripe. Four hundred
// scans through two mappers, the clean-up kept up to date from the changed
// rows (and from the whole map after a write through map()), the reference
// walking every cell of every beam: every layer after every scan, and every
// scan's account, must be the same bit for bit.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>
#include <random>
#include <utility>
#include <vector>

#include "core/visibility_full_walk.hpp"
#include "stridemap/core/terrain_mapper.hpp"
#include "stridemap/core/visibility_clearing.hpp"

namespace stridemap {
namespace {

struct SceneBox {
  Eigen::Vector3d lo_m, hi_m;
};

// Range along unit direction u from o to the first of the floor (z = 0) and
// the boxes; NaN beyond 4 m.
double scene_range_m(const Eigen::Vector3d& o, const Eigen::Vector3d& u, const std::vector<SceneBox>& boxes) {
  double best = u.z() < 0.0 ? -o.z() / u.z() : std::numeric_limits<double>::infinity();
  for (const SceneBox& b : boxes) {
    double t0 = 0.0, t1 = best;
    for (int a = 0; a < 3; ++a) {
      if (u[a] == 0.0) {
        if (o[a] < b.lo_m[a] || o[a] > b.hi_m[a]) t0 = t1 + 1.0;
        continue;
      }
      double near = (b.lo_m[a] - o[a]) / u[a], far = (b.hi_m[a] - o[a]) / u[a];
      if (near > far) std::swap(near, far);
      t0 = std::max(t0, near);
      t1 = std::min(t1, far);
    }
    if (t0 <= t1) best = std::min(best, t0);
  }
  return best < 4.0 ? best : std::numeric_limits<double>::quiet_NaN();
}

// The scene at scan k of a robot at x_m: what stands where.
std::vector<SceneBox> scene_at(int k, double x_m) {
  std::vector<SceneBox> boxes;
  boxes.push_back({{0.60, -0.10, 0.0}, {0.70, 0.0, 0.08}});  // hides the floor behind it
  const double y = -0.40 + 0.004 * (k % 200);                // crosses the stripe sideways
  boxes.push_back({{x_m + 0.32, y, 0.0}, {x_m + 0.40, y + 0.08, 0.05}});
  if (k < 100) boxes.push_back({{0.45, 0.05, 0.0}, {0.55, 0.15, 0.06}});  // taken away, walked back over
  if ((k / 15) % 2 == 0) boxes.push_back({{x_m + 0.33, 0.10, 0.0}, {x_m + 0.35, 0.12, 0.15}});  // a foot
  return boxes;
}

void run_scenario(const VisibilityOptions& options, std::size_t& contradicted, std::size_t& cleared,
                  std::size_t& whole_map_scans) {
  const bool failed_before = ::testing::Test::HasFailure();
  MapperOptions mapper_options;
  mapper_options.window_ahead_m = 0.3;
  const SensorMount mount;
  TerrainMapper mapper(mapper_options, mount), reference(mapper_options, mount);
  VisibilityClearing clearing(std::as_const(mapper).map(), options);
  test::FullWalk full(std::as_const(reference).map(), options, false);

  PlanarScan scan;
  scan.resize(682);
  std::vector<double> cos_angle(scan.size()), sin_angle(scan.size());
  for (std::size_t i = 0; i < scan.size(); ++i) {
    scan.angle_rad[i] = (static_cast<double>(i) + 44.0 - 384.0) * 2.0 * M_PI / 1024.0;
    cos_angle[i] = std::cos(scan.angle_rad[i]);
    sin_angle[i] = std::sin(scan.angle_rad[i]);
  }
  std::mt19937_64 rng(7);
  std::normal_distribution<double> tilt(0.0, 0.02);
  std::uniform_real_distribution<double> noise(-0.002, 0.002);
  TrunkPose pose;
  for (int k = 0; k < 400; ++k) {
    SCOPED_TRACE("scan " + std::to_string(k));
    pose.x_m += k < 200 ? 0.003 : -0.003;  // there and back
    pose.yaw_rad = 0.3 * std::sin(0.02 * k);
    pose.pitch_rad = tilt(rng);
    pose.roll_rad = tilt(rng);
    scan.time_s += 0.1;
    const PlanarBeamGeometry geometry(pose, mount);
    const Eigen::Vector3d origin = sensor_origin_in_map(pose, mount);
    const std::vector<SceneBox> boxes = scene_at(k, pose.x_m);
    for (std::size_t i = 0; i < scan.size(); ++i) {
      const double r = scene_range_m(origin, geometry.offset(1.0, cos_angle[i], sin_angle[i]), boxes);
      scan.range_m[i] = r + noise(rng);
      scan.range_error_m[i] = 0.01;
    }
    mapper.integrate(scan, pose);
    reference.integrate(scan, pose);
    // A write through map() now and then: the clean-up must see the whole map.
    if (k % 97 == 96) {
      (void)mapper.map();
      (void)reference.map();
    }
    clearing.begin_scan(std::as_const(mapper));
    full.begin_scan();
    ElevationMap& map = mapper.map_without_raising();
    ElevationMap& reference_map = reference.map_without_raising();
    VisibilityBeam beam;
    beam.origin_m = origin;
    for (std::size_t i = 0; i < scan.size(); ++i) {
      const double r = scan.range_m[i];
      if (!(r > 0.0)) continue;
      beam.hit_m = origin + geometry.offset(r, cos_angle[i], sin_angle[i]);
      beam.range_error_m = scan.range_error_m[i];
      beam.height_error_m = geometry.height_error(r, beam.range_error_m, cos_angle[i], sin_angle[i],
                                                  mapper_options.update);
      clearing.trace(map, beam);
      full.trace(reference_map, beam);
    }
    test::expect_same_maps(map, reference_map);
    test::expect_same_account(clearing, full);
    mapper.note_changed_cells(clearing.changed());
    reference.note_changed_cells(full.changed());
    mapper.clear_changed_cells();
    reference.clear_changed_cells();
    contradicted += full.stats().cells_contradicted;
    cleared += full.stats().cells_cleared;
    whole_map_scans += clearing.stats().maxima_from_whole_map ? 1 : 0;
    if (::testing::Test::HasFailure() && !failed_before) return;  // the first scan that differs
  }
}

TEST(VisibilityScenario, FourHundredScansOfMovingAndHiddenObjectsAsTheFullWalk) {
  VisibilityOptions defaults;
  VisibilityOptions every_beam;  // every beam traced, no relief: more cells contradicted
  every_beam.beam_spacing_cells = 0.0;
  every_beam.relief_factor = 0.0;
  for (const VisibilityOptions& options : {defaults, every_beam}) {
    std::size_t contradicted = 0, cleared = 0, whole_map_scans = 0;
    run_scenario(options, contradicted, cleared, whole_map_scans);
    // Meaningful only when cells were cleared and the maxima were mostly
    // kept up to date from the changed rows.
    EXPECT_GT(cleared, 100u);
    EXPECT_LT(whole_map_scans, 200u);
    std::printf("contradicted %zu, cleared %zu, maxima from the whole map in %zu scans\n", contradicted, cleared,
                whole_map_scans);
  }
}

}  // namespace
}  // namespace stridemap
