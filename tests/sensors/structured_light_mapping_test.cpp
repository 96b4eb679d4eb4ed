// Structured-light points in the map frame: elevation partials against
// finite differences, eq. (8) with each term once, the sheet's inclination,
// a pose round trip and the mapper taking the points.
#include <gtest/gtest.h>

#include <cmath>
#include <numbers>
#include <vector>

#include "stridemap/core/sensor_transform.hpp"
#include "stridemap/core/terrain_mapper.hpp"
#include "stridemap/sensors/structured_light_mapping.hpp"

namespace stridemap {
namespace structured_light_mapping_test {
namespace {

constexpr double kDeg = std::numbers::pi / 180.0;

// Elevation of the point seen at (u, v), relative to the camera, computed
// through core's transform.
double elevation_via_core(const StructuredLightParameters& parameters, double u, double v, const TrunkPose& pose) {
  Eigen::Vector3d camera;
  EXPECT_EQ(StructuredLightModel(parameters).back_project(u, v, camera), StripePointStatus::valid);
  return (sensor_to_map_rotation(pose, parameters.mount) * camera_to_sensor_frame(camera)).z();
}

void expect_partials_match_finite_differences(const StructuredLightParameters& base) {
  TrunkPose pose;
  pose.pitch_rad = 3.0 * kDeg;
  pose.roll_rad = -4.0 * kDeg;
  pose.yaw_rad = 0.7;
  const StructuredLightModel model(base);
  for (const auto& pixel : {std::pair{100.0, 400.0}, {320.0, 240.0}, {600.0, 30.0}}) {
    // Plain copies: clang 14 cannot capture structured bindings in lambdas.
    const double u = pixel.first, v = pixel.second;
    CameraPointPartials camera;
    ASSERT_EQ(model.back_project(u, v, camera), StripePointStatus::valid);
    const StructuredLightElevationPartials d =
        structured_light_elevation_partials(camera, pose.pitch_rad, pose.roll_rad, base.mount);
    EXPECT_NEAR(d.z_m, elevation_via_core(base, u, v, pose), 1e-15);

    const auto difference = [&](auto&& move, double h) {
      StructuredLightParameters p_plus = base, p_minus = base;
      TrunkPose pose_plus = pose, pose_minus = pose;
      double v_plus = v, v_minus = v;
      move(p_plus, pose_plus, v_plus, h);
      move(p_minus, pose_minus, v_minus, -h);
      return (elevation_via_core(p_plus, u, v_plus, pose_plus) - elevation_via_core(p_minus, u, v_minus, pose_minus)) /
             (2.0 * h);
    };
    const double h = 1e-6;
    const auto check = [&](double analytic, double numeric, const char* name) {
      EXPECT_NEAR(analytic, numeric, 1e-6 * (1.0 + std::abs(numeric))) << name << " at (" << u << ", " << v << ")";
    };
    check(d.d_baseline, difference([](auto& p, auto&, auto&, double s) { p.baseline_m += s; }, h), "dz/db");
    check(d.d_sheet_angle_m_per_rad, difference([](auto& p, auto&, auto&, double s) { p.sheet_angle_rad += s; }, h),
          "dz/dbeta");
    check(d.d_half_fov_vertical_m_per_rad,
          difference([](auto& p, auto&, auto&, double s) { p.half_fov_vertical_rad += s; }, h), "dz/dtau_c");
    check(d.d_row_m_per_px, difference([](auto&, auto&, auto& row, double s) { row += s; }, 1e-3), "dz/dv");
    check(d.d_pitch_m_per_rad, difference([](auto&, auto& t, auto&, double s) { t.pitch_rad += s; }, h), "dz/dpitch");
    check(d.d_roll_m_per_rad, difference([](auto&, auto& t, auto&, double s) { t.roll_rad += s; }, h), "dz/droll");
    check(d.d_alpha_m_per_rad, difference([](auto& p, auto&, auto&, double s) { p.mount.pitch_rad += s; }, h),
          "dz/dalpha");
  }
}

TEST(StructuredLightMapping, ElevationPartialsMatchFiniteDifferences) {
  expect_partials_match_finite_differences(StructuredLightParameters{});  // Ragno
}

TEST(StructuredLightMapping, ElevationPartialsMatchFiniteDifferencesWithMountRollAndYaw) {
  StructuredLightParameters turned;
  turned.mount.roll_rad = 5.0 * kDeg;
  turned.mount.yaw_rad = 10.0 * kDeg;
  expect_partials_match_finite_differences(turned);
}

TEST(StructuredLightMapping, EquationEightCountsEachTermOnce) {
  StructuredLightElevationPartials d;
  d.d_baseline = 0.5;
  d.d_sheet_angle_m_per_rad = -0.2;
  d.d_half_fov_vertical_m_per_rad = 0.3;
  d.d_row_m_per_px = -0.001;
  d.d_pitch_m_per_rad = 0.25;
  d.d_roll_m_per_rad = -0.05;
  d.d_alpha_m_per_rad = 0.22;
  StructuredLightParameters p;
  UpdateOptions o;
  p.baseline_error_m = 0.002;
  p.sheet_angle_error_rad = p.half_fov_vertical_error_rad = p.row_error_px = 0.0;
  o.max_pitch_error_rad = o.max_roll_error_rad = o.max_mount_pitch_error_rad = 0.0;
  // Only Delta b: the b term once (the paper prints it twice).
  EXPECT_DOUBLE_EQ(structured_light_elevation_error_bound_m(d, p, o), 0.5 * 0.002);

  p.sheet_angle_error_rad = 0.01;
  p.half_fov_vertical_error_rad = 0.003;
  p.row_error_px = 0.5;
  o.max_pitch_error_rad = 0.02;
  o.max_roll_error_rad = 0.03;
  o.max_mount_pitch_error_rad = 0.0175;
  const double expected_errors = 0.5 * 0.002 + 0.2 * 0.01 + 0.3 * 0.003 + 0.001 * 0.5 + 0.25 * 0.02 + 0.05 * 0.03 +
                                 0.22 * 0.0175;
  EXPECT_NEAR(structured_light_elevation_error_bound_m(d, p, o), expected_errors, 1e-15);
  EXPECT_NEAR(structured_light_max_elevation_change(d, p, -0.01, 55.0 * kDeg, o),
              0.01 * std::tan(55.0 * kDeg) + expected_errors, 1e-15);
}

TEST(StructuredLightMapping, SheetInclination) {
  // No roll: the sheet is 90 deg - beta steeper than the optical axis.
  EXPECT_NEAR(sheet_inclination_rad(45.0 * kDeg, 0.0, 0.0, 10.0 * kDeg), 55.0 * kDeg, 1e-12);
  EXPECT_NEAR(sheet_inclination_rad(70.0 * kDeg, 2.0 * kDeg, 0.0, 10.0 * kDeg), 32.0 * kDeg, 1e-12);
  // beta = 90 deg: the sheet is the sensor's x-y plane, like the laser's.
  EXPECT_NEAR(sheet_inclination_rad(90.0 * kDeg, 3.0 * kDeg, -7.0 * kDeg, 20.0 * kDeg),
              scan_plane_inclination_rad(3.0 * kDeg, -7.0 * kDeg, 20.0 * kDeg), 1e-12);
}

// A ground point on the laser sheet at lateral map offset `lateral_m` from
// the camera's line of sight, found by solving the (affine) sheet equation
// along the robot's heading.
Eigen::Vector3d ground_point_on_sheet(const StructuredLightModel& model, const TrunkPose& pose, double lateral_m) {
  const SensorMount& mount = model.parameters().mount;
  const Eigen::Matrix3d rotation = sensor_to_map_rotation(pose, mount);
  const Eigen::Vector3d origin = sensor_origin_in_map(pose, mount);
  const Eigen::Vector3d heading(std::cos(pose.yaw_rad), std::sin(pose.yaw_rad), 0.0);
  const Eigen::Vector3d side(-std::sin(pose.yaw_rad), std::cos(pose.yaw_rad), 0.0);
  const auto sheet_distance = [&](double ahead) {
    Eigen::Vector3d world = origin + ahead * heading + lateral_m * side;
    world.z() = pose.reference_elevation_m;
    const Eigen::Vector3d s = rotation.transpose() * (world - origin);
    return model.distance_from_sheet_m({s.y(), -s.z(), s.x()});
  };
  const double at0 = sheet_distance(0.0), at1 = sheet_distance(1.0);
  const double ahead = at0 / (at0 - at1);
  Eigen::Vector3d world = origin + ahead * heading + lateral_m * side;
  world.z() = pose.reference_elevation_m;
  return world;
}

TEST(StructuredLightMapping, PixelsOfGroundPointsComeBackToThem) {
  const StructuredLightModel model;  // Ragno
  TrunkPose pose;
  pose.x_m = 1.0;
  pose.y_m = 2.0;
  pose.yaw_rad = 0.5;
  // Ragno's stripe sits near the image's bottom edge: nose down keeps it in.
  pose.pitch_rad = 4.0 * kDeg;
  pose.roll_rad = -3.0 * kDeg;
  pose.reference_elevation_m = 0.05;
  pose.height_change_m = 0.01;
  const SensorMount& mount = model.parameters().mount;
  const Eigen::Matrix3d rotation = sensor_to_map_rotation(pose, mount);
  const Eigen::Vector3d origin = sensor_origin_in_map(pose, mount);

  std::vector<Eigen::Vector3d> truth;
  std::vector<StripePixel> pixels;
  for (double lateral = -0.12; lateral <= 0.12; lateral += 0.01) {
    const Eigen::Vector3d world = ground_point_on_sheet(model, pose, lateral);
    const Eigen::Vector3d s = rotation.transpose() * (world - origin);
    const auto pixel = model.project({s.y(), -s.z(), s.x()});
    ASSERT_TRUE(pixel && model.in_image(pixel->x(), pixel->y())) << "lateral " << lateral;
    truth.push_back(world);
    pixels.push_back({pixel->x(), pixel->y()});
  }
  std::vector<MapPoint> points;
  const StripeConversionStats stats = stripe_to_map_points(model, pixels, pose, {}, {}, points);
  ASSERT_EQ(stats.converted, truth.size());
  ASSERT_EQ(points.size(), truth.size());
  for (std::size_t i = 0; i < truth.size(); ++i) {
    EXPECT_NEAR(points[i].x_m, truth[i].x(), 1e-12);
    EXPECT_NEAR(points[i].y_m, truth[i].y(), 1e-12);
    EXPECT_NEAR(points[i].elevation_m, 0.05, 1e-12);
    EXPECT_GT(points[i].max_elevation_change_m, 0.0);
  }
}

TEST(StructuredLightMapping, BadPixelsAreCountedAndPoseGlitchesRejected) {
  const StructuredLightModel model;
  const std::vector<StripePixel> pixels = {
      {320.0, 475.0}, {std::nan(""), 10.0}, {700.0, 10.0}, {320.0, -1.0}, {0.0, 0.0}};
  std::vector<MapPoint> points;
  points.reserve(16);
  const MapPoint* storage = points.data();
  StripeConversionStats stats = stripe_to_map_points(model, pixels, {}, {}, {}, points);
  EXPECT_EQ(stats.pixels, 5u);
  EXPECT_EQ(stats.converted, 2u);
  EXPECT_EQ(stats.not_finite, 1u);
  EXPECT_EQ(stats.outside_image, 2u);
  for (const MapPoint& p : points) {
    EXPECT_TRUE(std::isfinite(p.x_m) && std::isfinite(p.y_m) && std::isfinite(p.elevation_m) &&
                std::isfinite(p.max_elevation_change_m));
  }
  // The buffer is reused, not reallocated.
  stats = stripe_to_map_points(model, pixels, {}, {}, {}, points);
  EXPECT_EQ(points.data(), storage);

  // A sheet that vanishes inside the image: rows below see nothing.
  StructuredLightParameters steep;
  steep.sheet_angle_rad = 80.0 * kDeg;
  stats = stripe_to_map_points(StructuredLightModel(steep), std::vector<StripePixel>{{320.0, 470.0}}, {}, {}, {},
                               points);
  EXPECT_EQ(stats.no_intersection, 1u);
  EXPECT_TRUE(points.empty());

  TrunkPose broken;
  broken.roll_rad = std::nan("");
  stats = stripe_to_map_points(model, pixels, broken, {}, {}, points);
  EXPECT_TRUE(stats.pose_rejected);
  EXPECT_TRUE(points.empty());
}

TEST(StructuredLightMapping, TravelAndTurningWidenTheBound) {
  const StructuredLightModel model;
  const std::vector<StripePixel> pixels = {{100.0, 470.0}};
  std::vector<MapPoint> still, moved, turned, glitch;
  UpdateOptions options;
  stripe_to_map_points(model, pixels, {}, {}, options, still);
  stripe_to_map_points(model, pixels, {}, {0.004, 0.0}, options, moved);
  ASSERT_EQ(still.size(), 1u);
  ASSERT_EQ(moved.size(), 1u);
  // d tan(gamma) with the sheet's gamma = 10 + 90 - 45 deg.
  EXPECT_NEAR(moved[0].max_elevation_change_m - still[0].max_elevation_change_m, 0.004 * std::tan(55.0 * kDeg),
              1e-12);
  const double yaw = 0.05;
  stripe_to_map_points(model, pixels, {}, {0.0, yaw}, options, turned);
  const double distance = std::hypot(turned[0].x_m, turned[0].y_m);  // sensor at the origin, no offsets
  // Fig. 10's term, plus the point's sideways distance from the heading
  // swept along it by the turn (|y| |sin theta| tan gamma; docs/mapping.md).
  EXPECT_NEAR(turned[0].max_elevation_change_m - still[0].max_elevation_change_m,
              std::tan(55.0 * kDeg) * turning_travel_m(distance, 0.0, yaw) +
                  std::abs(turned[0].y_m) * std::abs(std::sin(yaw)) * std::tan(55.0 * kDeg),
              1e-12);
  // A quarter turn between frames is a glitch: anything is plausible, but
  // the bound stays finite so that the mapper still takes the point.
  stripe_to_map_points(model, pixels, {}, {0.0, 2.0}, options, glitch);
  ASSERT_EQ(glitch.size(), 1u);
  EXPECT_TRUE(std::isfinite(glitch[0].max_elevation_change_m));
  EXPECT_GE(glitch[0].max_elevation_change_m, 1.0e5);
}

TEST(StructuredLightMapping, MapperBuildsFlatGroundFromStripes) {
  const StructuredLightModel model;  // Ragno, 174 mm above the ground
  MapperOptions options;
  options.grid.cell_size_m = 0.005;  // the paper's Ragno map
  options.grid.cells_per_side = 100;
  options.window_ahead_m = 0.2;
  TerrainMapper mapper(options, model.parameters().mount);
  std::vector<StripePixel> pixels;
  std::vector<MapPoint> points;
  std::size_t integrated = 0, implausible = 0;
  for (int frame = 0; frame < 30; ++frame) {
    TrunkPose pose;
    pose.x_m = 0.005 * frame;
    // Level trunk on flat ground: the stripe is the same image row in every frame.
    pixels.clear();
    for (int u = 0; u < 640; ++u) pixels.push_back({u + 0.5, 475.2});
    const StripeConversionStats converted =
        stripe_to_map_points(model, pixels, pose, mapper.motion_to(pose), options.update, points);
    ASSERT_EQ(converted.converted, 640u);
    const ScanStats stats = mapper.integrate_points(points, pose);
    integrated += stats.integrated;
    implausible += stats.implausible;
  }
  EXPECT_GT(integrated, 1000u);
  EXPECT_EQ(implausible, 0u);
  const ElevationMap& map = mapper.map();
  const CellIndex cell = map.cell_of(0.14 + 0.226, 0.0);  // ground under the stripe of frame 28
  ASSERT_TRUE(map.contains(cell));
  const std::size_t slot = map.slot(cell);
  EXPECT_NEAR(map.elevation_data()[slot], 0.0, 0.002);
}

}  // namespace
}  // namespace structured_light_mapping_test
}  // namespace stridemap
