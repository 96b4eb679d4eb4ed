#include "stridemap/sim/structured_light_simulator.hpp"

#include <cmath>
#include <limits>
#include <numbers>

#include <Eigen/LU>
#include <gtest/gtest.h>

#include "stridemap/core/error.hpp"
#include "stridemap/core/sensor_transform.hpp"
#include "stridemap/sensors/structured_light_report.hpp"

namespace stridemap {
namespace structured_light_simulator_test {
namespace {

constexpr double kDeg = std::numbers::pi / 180.0;

Scene floor_scene() {
  Scene scene;
  scene.terrain.reflectance = 0.5;
  return scene;
}

BoxObject box(double x_min, double x_max, double y_min, double y_max, double height) {
  BoxObject b;
  b.name = "box";
  b.center_x_m = 0.5 * (x_min + x_max);
  b.center_y_m = 0.5 * (y_min + y_max);
  b.length_m = x_max - x_min;
  b.width_m = y_max - y_min;
  b.height_m = height;
  b.reflectance = 0.8;
  return b;
}

TEST(StructuredLightSimulator, FlatFloorStripeIsTheReportedRowInEveryColumn) {
  const StructuredLightParameters ragno;  // the defaults are Ragno's
  StructuredLightSimulator sim(floor_scene(), ragno);
  StructuredLightFrameTruth frame;
  sim.simulate(TrunkPose{}, frame);
  const GroundStripeReport report = ground_stripe_report(sim.model());
  ASSERT_EQ(frame.columns.size(), 640u);
  EXPECT_EQ(frame.visible, 640u);
  ASSERT_EQ(frame.stripe.size(), 640u);
  for (std::size_t i = 0; i < frame.columns.size(); ++i) {
    const StripeColumnTruth& c = frame.columns[i];
    ASSERT_EQ(c.label, StripeColumnLabel::visible) << i;
    EXPECT_DOUBLE_EQ(c.u_px, i + 0.5);
    EXPECT_NEAR(c.v_px, report.stripe_row_px, 1e-9) << i;
    EXPECT_NEAR(c.point_m.z(), 0.0, 1e-12);
    EXPECT_EQ(c.object_index, -1);
    EXPECT_NEAR(c.camera_point_m.z(), report.stripe_depth_m, 1e-9);
    EXPECT_NEAR(sim.model().distance_from_sheet_m(c.camera_point_m), 0.0, 1e-12);
    EXPECT_GT(c.cos_incidence, 0.0);
    EXPECT_GT(c.cos_view, 0.0);
    EXPECT_DOUBLE_EQ(frame.stripe[i].v_px, c.v_px);  // no row noise by default
  }
  // The middle column looks straight ahead: the stripe's nearest point.
  EXPECT_NEAR(frame.columns[320].point_m.x(), report.nearest_distance_m, 1e-9);
}

TEST(StructuredLightSimulator, TruthBackProjectsToTheLitPointThroughTheMapper) {
  Scene scene = floor_scene();
  scene.boxes.push_back(box(0.20, 0.30, -0.05, 0.08, 0.04));
  StructuredLightParameters p;
  StructuredLightSimulator sim(scene, p);
  StructuredLightFrameTruth frame;
  TrunkPose pose;
  pose.x_m = 0.02;
  pose.y_m = -0.01;
  pose.yaw_rad = 3 * kDeg;
  pose.pitch_rad = 2 * kDeg;
  pose.roll_rad = -1.5 * kDeg;
  sim.simulate(pose, frame);
  ASSERT_GT(frame.visible, 600u);
  std::size_t on_box = 0;
  for (const StripeColumnTruth& c : frame.columns) {
    if (c.label != StripeColumnLabel::visible) continue;
    Eigen::Vector3d camera_point;
    ASSERT_EQ(sim.model().back_project(c.u_px, c.v_px, camera_point), StripePointStatus::valid);
    const Eigen::Vector3d in_map = sensor_point_to_map(camera_to_sensor_frame(camera_point), pose, p.mount);
    EXPECT_LT((in_map - c.point_m).norm(), 1e-9);
    on_box += c.object_index == 0;
  }
  EXPECT_GT(on_box, 50u);
}

TEST(StructuredLightSimulator, GroundBehindAWallIsNotLit) {
  // A wall 0.15 m ahead, taller than the sheet there: every column lights
  // the wall's front face, none the ground behind it (emitter occlusion).
  Scene scene = floor_scene();
  scene.boxes.push_back(box(0.15, 0.25, -1.0, 1.0, 0.30));
  StructuredLightSimulator sim(scene, StructuredLightParameters{});
  StructuredLightFrameTruth frame;
  sim.simulate(TrunkPose{}, frame);
  EXPECT_EQ(frame.visible, 640u);
  for (const StripeColumnTruth& c : frame.columns) {
    EXPECT_EQ(c.object_index, 0);
    EXPECT_NEAR(c.point_m.x(), 0.15, 1e-9);
    EXPECT_GT(c.point_m.z(), 0.0);
  }
}

TEST(StructuredLightSimulator, LowBarrierHidesTheLitGroundFromTheCamera) {
  // Between camera and stripe the camera ray to the ground stripe runs below
  // the emitter ray: a bar 8 cm high at x = 0.15 m blocks the camera's view
  // but not the sheet, so the ground stays lit and unseen.
  Scene scene = floor_scene();
  scene.boxes.push_back(box(0.150, 0.155, -0.03, 0.03, 0.08));
  StructuredLightSimulator sim(scene, StructuredLightParameters{});
  StructuredLightFrameTruth frame;
  sim.simulate(TrunkPose{}, frame);
  const StripeColumnTruth& centre = frame.columns[320];
  EXPECT_EQ(centre.label, StripeColumnLabel::hidden_from_camera);
  EXPECT_EQ(centre.object_index, -1);  // lit: the ground, not the bar
  EXPECT_GT(frame.hidden_from_camera, 20u);
  EXPECT_EQ(frame.columns[0].label, StripeColumnLabel::visible);  // the bar is narrow
  EXPECT_EQ(frame.visible + frame.hidden_from_camera, 640u);
  EXPECT_EQ(frame.stripe.size(), frame.visible);
}

TEST(StructuredLightSimulator, LabelsFanRangeAndImageLimits) {
  StructuredLightSimOptions narrow;
  narrow.fan_half_angle_rad = 10 * kDeg;
  StructuredLightSimulator fan(floor_scene(), StructuredLightParameters{}, narrow);
  StructuredLightFrameTruth frame;
  fan.simulate(TrunkPose{}, frame);
  EXPECT_EQ(frame.columns[0].label, StripeColumnLabel::outside_fan);
  EXPECT_EQ(frame.columns[320].label, StripeColumnLabel::visible);
  EXPECT_EQ(frame.visible + frame.outside_fan, 640u);

  StructuredLightSimOptions short_range;
  short_range.max_range_m = 0.1;
  StructuredLightSimulator near(floor_scene(), StructuredLightParameters{}, short_range);
  near.simulate(TrunkPose{}, frame);
  EXPECT_EQ(frame.no_surface, 640u);
  EXPECT_TRUE(frame.stripe.empty());

  // Nose up by 5 deg: the flat-ground stripe falls below the image.
  StructuredLightSimulator sim(floor_scene(), StructuredLightParameters{});
  TrunkPose nose_up;
  nose_up.pitch_rad = -5 * kDeg;
  sim.simulate(nose_up, frame);
  EXPECT_EQ(frame.outside_image, 640u);
  EXPECT_GT(frame.columns[320].v_px, 480.0);
}

TEST(StructuredLightSimulator, RowNoiseIsSeededPerFrameAndHasItsSigma) {
  StructuredLightSimOptions noisy;
  noisy.row_noise_sigma_px = 0.7;
  StructuredLightSimulator a(floor_scene(), StructuredLightParameters{}, noisy, 42);
  StructuredLightSimulator b(floor_scene(), StructuredLightParameters{}, noisy, 42);
  StructuredLightFrameTruth fa, fb, second;
  a.simulate(TrunkPose{}, fa);
  b.simulate(TrunkPose{}, fb);
  a.simulate(TrunkPose{}, second);
  double sum = 0.0, sum_sq = 0.0, diff = 0.0;
  for (std::size_t i = 0; i < fa.stripe.size(); ++i) {
    EXPECT_EQ(fa.stripe[i].v_px, fb.stripe[i].v_px);
    const double e = fa.stripe[i].v_px - fa.columns[i].v_px;
    sum += e;
    sum_sq += e * e;
    diff += std::abs(second.stripe[i].v_px - fa.stripe[i].v_px);
  }
  const double n = static_cast<double>(fa.stripe.size());
  EXPECT_NEAR(sum / n, 0.0, 0.1);
  EXPECT_NEAR(std::sqrt(sum_sq / n), 0.7, 0.07);
  EXPECT_GT(diff, 0.0);  // the next frame draws new noise
  a.reset(42);
  a.simulate(TrunkPose{}, second);
  EXPECT_EQ(second.stripe[7].v_px, fa.stripe[7].v_px);
}

TEST(StructuredLightSimulator, SensorPoseMatchesTheModelsSheet) {
  StructuredLightSimulator sim(floor_scene(), StructuredLightParameters{});
  TrunkPose pose;
  pose.x_m = 0.3;
  pose.yaw_rad = 20 * kDeg;
  pose.roll_rad = 4 * kDeg;
  const StructuredLightSensorPose s = sim.sensor_pose(pose);
  EXPECT_NEAR(s.camera_axes_in_map.determinant(), -1.0, 1e-12);
  EXPECT_NEAR(s.sheet_distance_m(s.emitter_origin_m), 0.0, 1e-12);
  EXPECT_NEAR((s.emitter_origin_m - s.camera_origin_m).norm(), 0.12, 1e-12);
  const Eigen::Vector3d probe(0.5, 0.1, -0.02);
  EXPECT_NEAR(s.sheet_distance_m(probe), sim.model().distance_from_sheet_m(s.to_camera(probe)), 1e-12);
}

TEST(StructuredLightSimulator, RejectsBadPosesAndOptions) {
  StructuredLightSimulator sim(floor_scene(), StructuredLightParameters{});
  StructuredLightFrameTruth frame;
  TrunkPose bad;
  bad.roll_rad = std::numeric_limits<double>::quiet_NaN();
  EXPECT_THROW(sim.simulate(bad, frame), InputError);

  StructuredLightSimOptions options;
  options.fan_half_angle_rad = 95 * kDeg;
  try {
    StructuredLightSimulator s(floor_scene(), StructuredLightParameters{}, options);
    FAIL() << "no error";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("fan_half_angle_rad"), std::string::npos) << e.what();
  }
  options = {};
  options.row_noise_sigma_px = -1.0;
  EXPECT_THROW(StructuredLightSimulator(floor_scene(), StructuredLightParameters{}, options), InputError);
  StructuredLightParameters p;
  p.baseline_m = 0.0;
  EXPECT_THROW(StructuredLightSimulator(floor_scene(), p), InputError);
}

}  // namespace
}  // namespace structured_light_simulator_test
}  // namespace stridemap
