#include "stridemap/experiments/walk.hpp"

#include <cmath>
#include <numbers>
#include <string>

#include <gtest/gtest.h>

#include "stridemap/config/scene_yaml.hpp"
#include "stridemap/core/error.hpp"
#include "stridemap/experiments/cart_rail.hpp"
#include "stridemap/experiments/urg_walk_sensor.hpp"
#include "test_paths.hpp"

namespace stridemap {
namespace walk_test {
namespace {

constexpr double kPi = std::numbers::pi;

Scene rail_scene() { return load_scene_yaml(std::string(STRIDEMAP_SOURCE_DIR) + "/scenes/cart_rail_boxes.yaml"); }

WalkPath along_the_rail() {
  WalkPath path;  // the rail of the shipped scene: x = 0 to 1.2 at y = 0
  path.segments.push_back({WalkSegment::Kind::straight, 1.2, 0.0, 0.0});
  return path;
}

WalkResult walk(const Scene& scene, const WalkPath& path, const WalkOptions& options,
                const UrgWalkSensorOptions& urg = {}) {
  UrgWalkSensor sensor(scene, urg, options.mapper.update, 1);
  return run_walk(scene, path, sensor, options);
}

// With a perfect pose a walk along the rail is the rail experiment: a trunk
// gliding without gait motion gives the rail's map to the last bit, and the
// gait's bobbing, pitching and rolling (known exactly) cost under a
// millimetre of RMS error.
TEST(Walk, WithZeroPoseErrorTheWalkReproducesTheRail) {
  const Scene scene = rail_scene();
  const CartRailResult rail = run_cart_rail(scene, CartRailOptions{});

  WalkOptions options;
  options.pose_errors = PoseErrorOptions::none();
  options.mapper.follow_robot = false;  // the rail's fixed window
  options.gait.follow_terrain = false;  // the cart rides above the objects
  options.gait.bob_amplitude_m = options.gait.pitch_amplitude_rad = options.gait.roll_amplitude_rad = 0.0;
  const WalkResult glide = walk(scene, along_the_rail(), options);
  EXPECT_EQ(glide.scans, rail.scans);
  EXPECT_DOUBLE_EQ(glide.mosaic_score.rms_error_m, rail.score.rms_error_m);
  EXPECT_EQ(glide.mosaic_score.measured_cells, rail.score.measured_cells);
  EXPECT_EQ(glide.mosaic_score.artifact_cells, rail.score.artifact_cells);

  options.gait = GaitOptions{};
  options.gait.follow_terrain = false;
  const WalkResult gait = walk(scene, along_the_rail(), options);
  EXPECT_LT(gait.mosaic_score.rms_error_m, rail.score.rms_error_m + 0.001);
  EXPECT_GT(gait.mosaic_score.coverage, rail.score.coverage - 0.01);
  EXPECT_LE(gait.mosaic_score.artifact_cells, rail.score.artifact_cells + 15);
  EXPECT_LT(gait.mosaic_score.rms_error_m, 0.010);  // the rail's acceptance target
}

// The walk clears the mapper's changed rows once a scan, so the clean-up
// keeps its maxima from scan to scan; before, the rows grew past a quarter
// of the window and most scans took them from the whole map again.
TEST(Walk, TheCleanUpKeepsItsMaximaAlongTheWalk) {
  const Scene scene = rail_scene();
  WalkOptions options;
  options.pose_errors = PoseErrorOptions::none();
  options.gait.follow_terrain = false;
  UrgWalkSensorOptions urg;
  urg.visibility.enabled = true;
  const WalkResult r = walk(scene, along_the_rail(), options, urg);
  EXPECT_TRUE(r.visibility_enabled);
  EXPECT_GT(r.visibility_scans, 50u);
  EXPECT_LT(r.visibility_whole_map_scans * 4, r.visibility_scans)
      << r.visibility_whole_map_scans << " of " << r.visibility_scans;
}

TEST(Walk, TheMapFollowsTheRobotAndTurningUsesFigureTen) {
  const Scene scene = rail_scene();
  WalkPath path;
  path.segments = {{WalkSegment::Kind::straight, 0.4, 0.0, 0.0},
                   {WalkSegment::Kind::turn, 0.0, kPi / 3, 0.0},
                   {WalkSegment::Kind::turn, 0.0, -2 * kPi / 3, 0.0},
                   {WalkSegment::Kind::turn, 0.0, kPi / 3, 0.5},
                   {WalkSegment::Kind::straight, 0.3, 0.0, 0.0}};
  WalkOptions options;
  options.pose_errors = PoseErrorOptions::none();
  options.gait.follow_terrain = false;
  options.gait.turn_rate_rad_per_s = 1.0;  // 5.7 deg per scan: Fig. 10's term matters
  UrgWalkSensor sensor(scene, UrgWalkSensorOptions{}, options.mapper.update, 1);
  WalkRun run(scene, path, sensor, options);
  const CellIndex start_corner = run.mapper().map().min_cell();
  while (!run.done()) run.step();
  const CellIndex end_corner = run.mapper().map().min_cell();
  const WalkResult with_term = run.finish();
  // The 100 x 100 window moved with the robot (by the whole path's travel).
  EXPECT_GT(std::abs(end_corner.x - start_corner.x), 50);
  EXPECT_GT(with_term.scans_with_yaw_change, with_term.scans / 3);
  EXPECT_GT(with_term.mosaic_score.coverage, 0.85);

  options.mapper.update.use_turning_term = false;
  const WalkResult without_term = walk(scene, path, options);
  EXPECT_EQ(with_term.mapper_totals.integrated, without_term.mapper_totals.integrated);
  // The turn's extra travel widens Delta z_max: fewer readings rejected.
  EXPECT_LT(with_term.mapper_totals.implausible, without_term.mapper_totals.implausible);
}

TEST(Walk, PoseErrorsReachTheMapAndItsScore) {
  const Scene scene = rail_scene();
  WalkOptions perfect;
  perfect.pose_errors = PoseErrorOptions::none();
  WalkOptions noisy;
  noisy.pose_errors = PoseErrorOptions{}.scaled(4.0);
  noisy.pose_errors.reference = ReferenceElevationSource::truth;
  const WalkResult a = walk(scene, along_the_rail(), perfect);
  const WalkResult b = walk(scene, along_the_rail(), noisy);
  EXPECT_DOUBLE_EQ(a.pose_errors.pitch_rad, 0.0);
  EXPECT_NEAR(b.pose_errors.pitch_rad, std::hypot(4 * 0.2, 4 * 0.3) * kPi / 180, 0.003);
  EXPECT_GT(b.mosaic_score.rms_error_m, a.mosaic_score.rms_error_m + 0.001);
  EXPECT_EQ(count_invalid_cells(*std::make_unique<ElevationMap>(), 100.0), 0u);
}

// With the true h_ref the walk still keeps the fused layers and says how
// far they lie from the ground under the true soles: with no pose error, on
// the rail's floor, within the URG's own range error (about a millimetre
// up, docs/experiments.md); the IMU's pitch bias, which lifts the points
// ahead, lifts it by millimetres more. A walk reading eq. (10)'s layer
// keeps none.
TEST(Walk, TheFusedLayerUnderTheSolesIsMeasuredWithTheTrueHref) {
  const Scene scene = rail_scene();
  WalkOptions options;
  options.build_mosaic = false;
  options.pose_errors = PoseErrorOptions::none();
  const auto mean_under_soles = [](const WalkResult& r) {
    return r.fused_under_soles_error_sum_m / static_cast<double>(r.fused_under_soles_scans);
  };
  const WalkResult exact = walk(scene, along_the_rail(), options);
  ASSERT_GT(exact.fused_under_soles_scans, exact.scans / 2);
  EXPECT_LT(std::abs(mean_under_soles(exact)), 0.002);
  options.pose_errors.imu_pitch_bias_rad = -0.3 * kPi / 180;
  const WalkResult biased = walk(scene, along_the_rail(), options);
  EXPECT_GT(mean_under_soles(biased), mean_under_soles(exact) + 0.0015);
  options.pose_errors.reference = ReferenceElevationSource::map;
  EXPECT_EQ(walk(scene, along_the_rail(), options).fused_under_soles_scans, 0u);
}

// Eq. (10)'s highest reading lies above the floor by the range noise; a
// robot reading its h_ref from it climbs by that at every look-ahead it
// walks, even with a perfect pose. The fused layer has no such bias.
TEST(Walk, HrefFromTheFusedLayerDoesNotClimbWithTheRangeNoise) {
  const Scene scene = rail_scene();
  WalkOptions options;
  options.pose_errors = PoseErrorOptions{}.scaled(0.0);
  options.build_mosaic = false;
  options.pose_errors.reference = ReferenceElevationSource::map;
  const WalkResult highest = walk(scene, along_the_rail(), options);
  options.pose_errors.reference = ReferenceElevationSource::map_fused;
  const WalkResult fused = walk(scene, along_the_rail(), options);
  EXPECT_GT(highest.pose_errors.mean_sensor_height_m, 0.003);
  EXPECT_LT(std::abs(fused.pose_errors.mean_sensor_height_m), 0.5 * highest.pose_errors.mean_sensor_height_m);
  EXPECT_LT(fused.pose_errors.sensor_height_m, highest.pose_errors.sensor_height_m);
}

TEST(Walk, BadInputIsRejectedBeforeTheFirstScan) {
  const Scene scene = rail_scene();
  const auto error_of = [&](const WalkPath& path, const WalkOptions& options, const UrgWalkSensorOptions& urg) {
    try {
      UrgWalkSensor sensor(scene, urg, options.mapper.update, 1);
      WalkRun run(scene, path, sensor, options);
    } catch (const InputError& e) {
      return std::string(e.what());
    }
    return std::string();
  };
  WalkPath leaving = along_the_rail();
  leaving.segments.push_back({WalkSegment::Kind::straight, 5.0, 0.0, 0.0});  // the extent ends at x = 2.5
  EXPECT_NE(error_of(leaving, WalkOptions{}, {}).find("walk_path.segments[1]: the path leaves"), std::string::npos);

  UrgWalkSensorOptions below;
  below.mount.height_m = -0.05;
  EXPECT_NE(error_of(along_the_rail(), WalkOptions{}, below).find("at or below the terrain"), std::string::npos)
      << error_of(along_the_rail(), WalkOptions{}, below);
  UrgWalkSensorOptions past_vertical;
  past_vertical.mount.pitch_rad = 95.0 * kPi / 180;
  EXPECT_NE(error_of(along_the_rail(), WalkOptions{}, past_vertical).find("between -90 and 90 deg"), std::string::npos)
      << error_of(along_the_rail(), WalkOptions{}, past_vertical);
  UrgWalkSensorOptions level;
  level.mount.pitch_rad = 0.0;  // a level scan plane never meets a level floor
  EXPECT_NE(error_of(along_the_rail(), WalkOptions{}, level).find("cannot see the ground"), std::string::npos);

  WalkOptions negative;
  negative.pose_errors.imu_pitch_noise_sigma_rad = -0.001;
  EXPECT_NE(error_of(along_the_rail(), negative, {}).find("imu_pitch_noise_sigma_rad"), std::string::npos);
  WalkOptions bad_mosaic;
  bad_mosaic.mosaic_every_scans = 0;
  EXPECT_NE(error_of(along_the_rail(), bad_mosaic, {}).find("mosaic_every_scans"), std::string::npos);
}

}  // namespace
}  // namespace walk_test
}  // namespace stridemap
