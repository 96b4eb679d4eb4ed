#include "stridemap/experiments/structured_light_walk_sensor.hpp"

#include <algorithm>
#include <cmath>
#include <string>

#include <gtest/gtest.h>

#include "stridemap/config/scene_yaml.hpp"
#include "stridemap/core/error.hpp"
#include "stridemap/experiments/attitude_calibration.hpp"
#include "stridemap/experiments/mount_analysis.hpp"
#include "stridemap/experiments/rocky_walk.hpp"
#include "test_paths.hpp"

namespace stridemap {
namespace structured_light_walk_test {
namespace {

constexpr double kDeg = 3.14159265358979323846 / 180.0;

TEST(StructuredLightWalk, FloorTraceIsTheSimulatorsStripeOnAFlatFloor) {
  const StructuredLightWalkSensor sensor(Scene{}, StructuredLightWalkSensorOptions{}, UpdateOptions{}, 1);
  TrunkPose pose;
  pose.x_m = 0.3;
  pose.yaw_rad = 0.4;
  pose.pitch_rad = 0.02;
  pose.reference_elevation_m = 0.01;
  std::vector<Eigen::Vector2d> trace;
  sensor.floor_trace(pose, 0.01, 4.0, trace);
  const std::vector<Eigen::Vector2d> truth = stripe_floor_points(StructuredLightParameters{}, pose, 0.01);
  ASSERT_EQ(trace.size(), truth.size());
  std::size_t seen = 0;
  for (std::size_t i = 0; i < trace.size(); ++i) {
    ASSERT_EQ(trace[i].allFinite(), truth[i].allFinite()) << "column " << i;
    if (!trace[i].allFinite()) continue;
    ++seen;
    EXPECT_NEAR((trace[i] - truth[i]).norm(), 0.0, 1e-6) << "column " << i;
  }
  EXPECT_GT(seen, 600u);
}

TEST(StructuredLightWalk, MapsTheMockUpPreciselyWithAPerfectPose) {
  const Scene scene = load_scene_yaml(std::string(STRIDEMAP_SOURCE_DIR) + "/scenes/rocky_mockup.yaml");
  RockyWalkOptions options;
  options.walk.pose_errors = PoseErrorOptions::none();
  options.walk.mapper.grid = {200, 0.005};
  options.walk.map_filter = MapFilter::none;
  options.pose_error_scales = {};
  const WalkSensorFactory factory = [](const Scene& s, const UpdateOptions& u) -> std::unique_ptr<WalkSensor> {
    return std::make_unique<StructuredLightWalkSensor>(s, StructuredLightWalkSensorOptions{}, u, 1);
  };
  const RockyWalkResult r = run_rocky_walk(scene, *scene.walk_path, factory, options);
  EXPECT_EQ(r.sensor, "structured-light");
  EXPECT_GT(r.main.scans, 1000u);  // 25 frames a second
  EXPECT_LT(r.main.mosaic_score.rms_error_m, 0.003);
  EXPECT_GT(r.main.mosaic_score.coverage, 0.5);
}

// Structured light sees the calibration floor at one distance per stance,
// so each stance's leg-height noise passes into the pitch found: the four
// default stances (two of which see nothing, the trunk 4 cm up) scatter by
// tenths of a degree over seeds, the nine wide ones by hundredths.
TEST(StructuredLightWalk, WideStancesCalibrateThePitchWhereTheDefaultsCannot) {
  const Scene floor = flat_calibration_floor(0.35);
  PoseErrorOptions unbiased;
  unbiased.imu_pitch_bias_rad = unbiased.imu_roll_bias_rad = 0.0;
  const auto worst_pitch = [&](const AttitudeCalibrationOptions& stances) {
    double worst = 0.0;
    for (const std::uint64_t seed : {1u, 2u, 3u, 4u}) {
      StructuredLightWalkSensor sensor(floor, StructuredLightWalkSensorOptions{}, UpdateOptions{}, seed);
      MapperOptions mapper;
      mapper.grid = {200, 0.005};
      const AttitudeCalibration c =
          calibrate_attitude_on_flat_floor(sensor, unbiased, GaitOptions{}, mapper, seed, stances);
      EXPECT_NEAR(c.roll_bias_rad, 0.0, 0.03 * kDeg);
      worst = std::max(worst, std::abs(c.pitch_bias_rad));
    }
    return worst;
  };
  EXPECT_LT(worst_pitch(AttitudeCalibrationOptions::wide_stances()), 0.1 * kDeg);
  EXPECT_GT(worst_pitch(AttitudeCalibrationOptions{}), 0.15 * kDeg);
}

// Section 3.3: a smaller beta or a downward tilt both reduce the occlusions
// and the uncertainty of the base configuration, and both narrow the
// stripe on the ground (Fig. 5).
TEST(StructuredLightWalk, FigureFiveMountsRankAsSectionThreeThreeSays) {
  MountAnalysisOptions o;
  o.fields = 1;
  o.cell_size_m = 0.005;
  o.corridor_half_width_m = 0.15;
  o.score.min_stripe_width_m = 0.3;
  o.score.min_look_ahead_m = 0.15;
  o.sweep_heights_m = {0.174};
  o.sweep_pitches_rad = {10.0 * kDeg};
  o.field.max_x_m = 1.6;  // a shorter field keeps the test quick
  const MountSensorFactory factory = [](const Scene& s, const NamedMount& m, const UpdateOptions& u) -> std::unique_ptr<WalkSensor> {
    StructuredLightWalkSensorOptions sl;
    sl.parameters.mount = m.mount;
    if (m.sheet_angle_rad) sl.parameters.sheet_angle_rad = *m.sheet_angle_rad;
    return std::make_unique<StructuredLightWalkSensor>(s, sl, u, 1);
  };
  const MountAnalysisResult r = run_mount_analysis(paper_structured_light_mounts(), factory, nullptr, o);
  ASSERT_EQ(r.named.size(), 3u);
  const MountMetrics &base = r.named[0], &beta = r.named[1], &tilt = r.named[2];
  EXPECT_FALSE(base.favourable_range_share);
  EXPECT_GT(base.unobserved_fraction, beta.unobserved_fraction);
  EXPECT_GT(base.unobserved_fraction, tilt.unobserved_fraction);
  EXPECT_GT(base.mean_height_uncertainty_m, beta.mean_height_uncertainty_m);
  EXPECT_GT(base.mean_height_uncertainty_m, tilt.mean_height_uncertainty_m);
  EXPECT_GT(base.stripe_width_m, beta.stripe_width_m);
  EXPECT_GT(base.stripe_width_m, tilt.stripe_width_m);

  // A sheet that never reaches the ground in the image is refused by name.
  try {
    run_mount_analysis({{"blind", SensorMount{0.174, 0.0, 0.0, 0.0}, 40.0 * kDeg}}, factory, nullptr, o);
    FAIL() << "a blind structured-light mount was accepted";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("cannot see the ground"), std::string::npos) << e.what();
  }
}

}  // namespace
}  // namespace structured_light_walk_test
}  // namespace stridemap
