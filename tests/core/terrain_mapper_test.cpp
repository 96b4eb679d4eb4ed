#include "stridemap/core/terrain_mapper.hpp"

#include <cmath>
#include <limits>
#include <numbers>

#include <gtest/gtest.h>

#include "stridemap/core/error.hpp"

namespace stridemap {
namespace terrain_mapper_test {
namespace {

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();
constexpr double kInf = std::numeric_limits<double>::infinity();

// Ranges at which the beams of a pitched sensor meet flat ground at z = 0.
PlanarScan flat_ground_scan(const SensorMount& mount, int beams) {
  PlanarScan scan;
  scan.resize(static_cast<std::size_t>(beams));
  for (int i = 0; i < beams; ++i) {
    const double t = -0.8 + 1.6 * i / (beams - 1);
    // z of the unit beam is -cos(t) sin(alpha); the range reaches z = -d_z.
    scan.angle_rad[static_cast<std::size_t>(i)] = t;
    scan.range_m[static_cast<std::size_t>(i)] = mount.height_m / (std::cos(t) * std::sin(mount.pitch_rad));
    scan.range_error_m[static_cast<std::size_t>(i)] = 0.01;
  }
  return scan;
}

bool all_layers_finite_where_known(const ElevationMap& map) {
  for (int i = 0; i < map.cells_per_side(); ++i) {
    for (int j = 0; j < map.cells_per_side(); ++j) {
      const CellIndex c = map.cell_at_local(i, j);
      if (!std::isfinite(map.certainty(c))) return false;
      if (map.state(c) != CellState::unknown && !std::isfinite(map.elevation(c))) return false;
    }
  }
  return true;
}

MapperOptions fixed_window() {
  MapperOptions options;
  options.follow_robot = false;
  options.grid = {200, 0.01};
  return options;
}

TEST(TerrainMapper, FlatGroundGivesZeroElevation) {
  SensorMount mount;
  TerrainMapper mapper(fixed_window(), mount);
  const ScanStats stats = mapper.integrate(flat_ground_scan(mount, 200), TrunkPose{});
  EXPECT_EQ(stats.beams, 200u);
  EXPECT_EQ(stats.integrated + stats.outside_map, 200u);
  EXPECT_GT(stats.integrated, 100u);
  const CellIndex ahead = mapper.map().cell_of(mount.height_m / std::tan(mount.pitch_rad), 0.0);
  EXPECT_EQ(mapper.map().state(ahead), CellState::measured);
  EXPECT_NEAR(mapper.map().elevation(ahead), 0.0, 1e-6);
}

TEST(TerrainMapper, BadSamplesAreRejectedOneByOneAndCounted) {
  SensorMount mount;
  TerrainMapper mapper(fixed_window(), mount);
  PlanarScan scan = flat_ground_scan(mount, 50);
  scan.range_m[3] = kNaN;
  scan.range_m[4] = kInf;
  scan.range_m[5] = -0.2;
  scan.range_m[6] = 0.0;
  scan.angle_rad[7] = kNaN;
  scan.range_error_m[8] = kNaN;
  scan.range_error_m[9] = -0.01;
  scan.range_m[10] = 1e300;  // finite, but far outside any map
  const ScanStats stats = mapper.integrate(scan, TrunkPose{});
  EXPECT_EQ(stats.invalid_range, 4u);
  EXPECT_EQ(stats.invalid_beam, 3u);
  EXPECT_GE(stats.outside_map, 1u);
  EXPECT_EQ(stats.integrated + stats.outside_map + stats.invalid_range + stats.invalid_beam, 50u);
  EXPECT_TRUE(all_layers_finite_where_known(mapper.map()));
  EXPECT_EQ(mapper.totals().invalid_range, 4u);
}

TEST(TerrainMapper, NonFinitePoseRejectsTheWholeScan) {
  SensorMount mount;
  TerrainMapper mapper(fixed_window(), mount);
  const PlanarScan scan = flat_ground_scan(mount, 50);
  for (int field = 0; field < 7; ++field) {
    TrunkPose pose;
    double* fields[] = {&pose.x_m, &pose.y_m, &pose.yaw_rad, &pose.pitch_rad, &pose.roll_rad,
                        &pose.reference_elevation_m, &pose.height_change_m};
    *fields[field] = field % 2 ? kNaN : kInf;
    const ScanStats stats = mapper.integrate(scan, pose);
    EXPECT_TRUE(stats.pose_rejected) << field;
    EXPECT_EQ(stats.integrated, 0u);
  }
  EXPECT_EQ(mapper.totals().scans_rejected_for_pose, 7u);
  EXPECT_TRUE(all_layers_finite_where_known(mapper.map()));
  for (int i = 0; i < 200; ++i)
    for (int j = 0; j < 200; ++j) ASSERT_EQ(mapper.map().state(mapper.map().cell_at_local(i, j)), CellState::unknown);
  // A rejected pose does not become the "previous" pose of the next scan.
  EXPECT_EQ(mapper.motion_to(TrunkPose{}).horizontal_travel_m, 0.0);
}

TEST(TerrainMapper, OutOfOrderDuplicateAndNonFiniteTimesRejectTheScan) {
  SensorMount mount;
  TerrainMapper mapper(fixed_window(), mount);
  PlanarScan scan = flat_ground_scan(mount, 50);
  scan.time_s = 1.0;
  ASSERT_FALSE(mapper.integrate(scan, TrunkPose{}).time_rejected);
  const std::size_t integrated = mapper.totals().integrated;
  const float certainty = mapper.map().certainty(mapper.map().cell_of(0.37, 0.0));
  ASSERT_GT(certainty, 0.0f);
  for (double stale : {1.0, 0.5, -3.0, kNaN, kInf, -kInf}) {
    scan.time_s = stale;
    TrunkPose moved;
    moved.x_m = 0.05;
    const ScanStats stats = mapper.integrate(scan, moved);
    EXPECT_TRUE(stats.time_rejected) << stale;
    EXPECT_FALSE(stats.pose_rejected);
    EXPECT_EQ(stats.integrated, 0u);
    // A rejected scan neither raises a certainty nor becomes the previous pose.
    EXPECT_EQ(mapper.motion_to(TrunkPose{}).horizontal_travel_m, 0.0);
  }
  EXPECT_EQ(mapper.totals().scans, 7u);
  EXPECT_EQ(mapper.totals().scans_rejected_for_time, 6u);
  EXPECT_EQ(mapper.totals().integrated, integrated);
  EXPECT_EQ(mapper.map().certainty(mapper.map().cell_of(0.37, 0.0)), certainty);
  EXPECT_EQ(mapper.last_scan_time_s(), 1.0);
  scan.time_s = 1.1;
  EXPECT_FALSE(mapper.integrate(scan, TrunkPose{}).time_rejected);
  EXPECT_EQ(mapper.last_scan_time_s(), 1.1);

  // The points path checks only when it is given a time, on the same clock.
  const MapPoint point{0.1, 0.0, 0.0, 0.01};
  EXPECT_FALSE(mapper.integrate_points({&point, 1}, TrunkPose{}).time_rejected);
  EXPECT_TRUE(mapper.integrate_points({&point, 1}, TrunkPose{}, 1.1).time_rejected);
  EXPECT_FALSE(mapper.integrate_points({&point, 1}, TrunkPose{}, 1.2).time_rejected);
}

TEST(TerrainMapper, StaleScanCheckCanBeTurnedOff) {
  SensorMount mount;
  MapperOptions options = fixed_window();
  options.reject_stale_scans = false;
  TerrainMapper mapper(options, mount);
  const PlanarScan scan = flat_ground_scan(mount, 50);  // every time_s 0
  for (int k = 0; k < 3; ++k) EXPECT_FALSE(mapper.integrate(scan, TrunkPose{}).time_rejected);
  EXPECT_EQ(mapper.totals().scans_rejected_for_time, 0u);
}

TEST(TerrainMapper, MismatchedScanVectorsAreAnError) {
  SensorMount mount;
  TerrainMapper mapper(fixed_window(), mount);
  PlanarScan scan = flat_ground_scan(mount, 10);
  scan.angle_rad.pop_back();
  try {
    mapper.integrate(scan, TrunkPose{});
    FAIL();
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("angle_rad"), std::string::npos);
  }
}

TEST(TerrainMapper, MotionFeedsTheBoundAndTheWindowFollows) {
  SensorMount mount;
  MapperOptions options;
  options.grid = {100, 0.01};
  TerrainMapper mapper(options, mount);
  TrunkPose pose;
  mapper.integrate(flat_ground_scan(mount, 20), pose);
  pose.x_m = 0.01;
  pose.yaw_rad = 0.05;
  const ScanMotion motion = mapper.motion_to(pose);
  EXPECT_NEAR(motion.horizontal_travel_m, 0.01, 1e-12);
  EXPECT_NEAR(motion.yaw_change_rad, 0.05, 1e-12);
  pose.x_m = 2.0;
  PlanarScan later = flat_ground_scan(mount, 20);
  later.time_s = 0.1;
  const ScanStats stats = mapper.integrate(later, pose);
  EXPECT_EQ(stats.cells_reset_by_move, 100u * 100u);
  EXPECT_TRUE(mapper.map().contains(mapper.map().cell_of(2.0, 0.0)));
}

TEST(TerrainMapper, PointsPathAppliesTheirOwnBound) {
  TerrainMapper mapper(fixed_window(), SensorMount{});
  const MapPoint points[] = {{0.3, 0.0, 0.10, 0.01}, {0.3, 0.0, 0.105, 0.01}, {0.3, 0.0, 0.5, 0.01},
                             {kNaN, 0.0, 0.1, 0.01}, {0.3, 0.0, 0.1, kNaN}, {0.3, 0.0, 0.0, kInf}};
  const ScanStats stats = mapper.integrate_points(points, TrunkPose{});
  EXPECT_EQ(stats.first, 1u);
  EXPECT_EQ(stats.plausible, 2u);  // the infinite bound accepts anything
  EXPECT_EQ(stats.implausible, 1u);
  EXPECT_EQ(stats.invalid_range, 1u);
  EXPECT_EQ(stats.invalid_beam, 1u);
  const CellIndex c = mapper.map().cell_of(0.3, 0.0);
  EXPECT_FLOAT_EQ(mapper.map().elevation(c), 0.5f);
  EXPECT_FLOAT_EQ(mapper.map().certainty(c), 9.0f);
}

TEST(TerrainMapper, RejectsBadOptionsAndMounts) {
  MapperOptions options;
  options.update.certainty_increment = 0.0;
  EXPECT_THROW(TerrainMapper(options, SensorMount{}), InputError);
  options = {};
  options.update.max_pitch_error_rad = -1.0;
  EXPECT_THROW(TerrainMapper(options, SensorMount{}), InputError);
  SensorMount mount;
  mount.pitch_rad = std::numbers::pi;
  EXPECT_THROW(TerrainMapper(MapperOptions{}, mount), InputError);
  mount = {};
  mount.height_m = kNaN;
  EXPECT_THROW(TerrainMapper(MapperOptions{}, mount), InputError);
}

}  // namespace
}  // namespace terrain_mapper_test
}  // namespace stridemap
