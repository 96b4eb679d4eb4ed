// Section 3.3: the Ragno configuration on flat ground, the paper's 29.4 cm,
// and geometries that cannot see the ground.
#include <gtest/gtest.h>

#include <cmath>
#include <numbers>
#include <string>

#include "stridemap/core/error.hpp"
#include "stridemap/core/sensor_transform.hpp"
#include "stridemap/sensors/structured_light_report.hpp"

namespace stridemap {
namespace structured_light_report_test {
namespace {

constexpr double kDeg = std::numbers::pi / 180.0;

// The ground point seen at (u, v), relative to the ground under the camera
// (level trunk), through core's transform.
Eigen::Vector3d on_level_trunk(const StructuredLightModel& model, double u, double v) {
  Eigen::Vector3d camera;
  EXPECT_EQ(model.back_project(u, v, camera), StripePointStatus::valid);
  const SensorMount& mount = model.parameters().mount;
  return sensor_point_to_map(camera_to_sensor_frame(camera), TrunkPose{}, mount);
}

TEST(StructuredLightReport, RagnoOnFlatGround) {
  const StructuredLightModel model;  // defaults: tau_c 28.14, gamma_c 38.8 deg, b 120 mm, beta 45, alpha 10, 174 mm
  const GroundStripeReport r = ground_stripe_report(model);
  // z_c = (h + b cos a) / (sin a + cot(beta) cos a) = 0.292177 / 1.158456.
  EXPECT_NEAR(r.stripe_depth_m, 0.252212, 1e-6);
  // Ahead: X = z_c cos a - y_c sin a with y_c = z_c - b; ends at
  // x_c = +-z_c tan(gamma_c).
  EXPECT_NEAR(r.nearest_distance_m, 0.225422, 1e-6);
  EXPECT_NEAR(r.nearest_slant_range_m, 0.284765, 1e-6);
  EXPECT_NEAR(r.stripe_width_m, 0.405568, 1e-6);
  EXPECT_NEAR(r.farthest_distance_m, 0.303210, 1e-6);
  EXPECT_NEAR(r.stripe_row_px, 475.2, 0.1);
  // Independent of the closed form: the stripe row seen through eq. (1) and
  // core's transform lies on the ground, across the whole image width.
  for (const double u : {0.0, 160.0, 320.0, 640.0}) {
    const Eigen::Vector3d p = on_level_trunk(model, u, r.stripe_row_px);
    EXPECT_NEAR(p.z(), 0.0, 1e-12) << "u=" << u;
    EXPECT_NEAR(p.x(), r.nearest_distance_m, 1e-12);
  }
  EXPECT_NEAR(on_level_trunk(model, 0.0, r.stripe_row_px).y(), 0.5 * r.stripe_width_m, 1e-12);
  // Rows below the horizon look down: the horizon row's ray is level.
  EXPECT_NEAR(r.horizon_row_px, 240.0 * (1.0 - std::tan(10.0 * kDeg) / std::tan(28.14 * kDeg)), 1e-9);
  // The sheet's visible ends: tall obstacles near, a small step down far.
  EXPECT_NEAR(r.near_end.height_above_ground_m, 0.2016, 1e-4);
  EXPECT_NEAR(r.near_end.forward_m, 0.0843, 1e-4);
  ASSERT_TRUE(r.far_end.has_value());
  EXPECT_NEAR(r.far_end->height_above_ground_m, -0.0067, 1e-4);
  EXPECT_GT(r.sensor_error_bound_m, 0.0);
  EXPECT_NEAR(r.elevation_per_row_m_per_px, std::abs(r.centre_partials.d_row_m_per_px), 0.0);
  // The stripe sits near the image's bottom edge: a little nose-up pitch
  // loses it; the pitch limits are where it reaches the edge.
  EXPECT_LT(r.min_trunk_pitch_rad, 0.0);
  EXPECT_GT(r.min_trunk_pitch_rad, -3.0 * kDeg);
  EXPECT_FALSE(r.min_pitch_is_search_limit);
  const auto at_min = ground_stripe_location(model, 10.0 * kDeg + r.min_trunk_pitch_rad);
  ASSERT_TRUE(at_min.has_value());
  EXPECT_NEAR(at_min->row_px, 480.0, 1e-6);
  EXPECT_GT(r.max_trunk_pitch_rad, 0.0);
}

TEST(StructuredLightReport, ThePapersRangeIsTheUntiltedSheet) {
  // The paper: "the camera is located 17.4 cm above the ground, which
  // results in the maximum measured range of 29.4 cm". With the whole
  // sensor tilted by alpha = 10 deg (eq. 5 applies alpha to eq. 1's points)
  // the stripe lies 22.5 cm ahead (28.5 cm slant, z_c = 25.2 cm). 29.4 cm is
  // (h + b) tan(beta): where the sheet meets the ground when the emitter is
  // NOT tilted with the camera (or alpha is left out). The stripe's ends,
  // 30.3 cm away, are not it either.
  StructuredLightParameters untilted;
  untilted.mount.pitch_rad = 0.0;
  const StructuredLightModel model(untilted);
  const auto location = ground_stripe_location(model, 0.0);
  ASSERT_TRUE(location.has_value());
  EXPECT_NEAR(location->depth_m, 0.294, 1e-12);  // level camera: z_c is the ground distance
  EXPECT_NEAR((0.174 + 0.120) * std::tan(45.0 * kDeg), 0.294, 1e-12);
  // Untilted, that stripe is below the image: tilting is what makes the
  // ground visible at all.
  EXPECT_GT(location->row_px, 480.0);
  const GroundStripeReport tilted = ground_stripe_report(StructuredLightModel{});
  EXPECT_NEAR(tilted.nearest_distance_m, 0.2254, 1e-4);
  EXPECT_NEAR(tilted.nearest_slant_range_m, 0.2848, 1e-4);
  EXPECT_NEAR(tilted.farthest_distance_m, 0.3032, 1e-4);
}

std::string ground_error(const StructuredLightParameters& p) {
  try {
    ground_stripe_report(StructuredLightModel(p));
  } catch (const InputError& e) {
    return e.what();
  }
  return "(accepted)";
}

TEST(StructuredLightReport, GeometriesThatCannotSeeTheGround) {
  StructuredLightParameters p;
  p.mount.pitch_rad = 0.0;  // Ragno untilted: stripe below the image
  std::string message = ground_error(p);
  EXPECT_NE(message.find("this geometry cannot see the ground"), std::string::npos) << message;
  EXPECT_NE(message.find("below the image (rows 0 to 480)"), std::string::npos) << message;
  EXPECT_NE(message.find("tilt the sensor further down"), std::string::npos) << message;

  p = {};
  p.sheet_angle_rad = 80.0 * kDeg;
  p.mount.pitch_rad = -15.0 * kDeg;  // sheet 5 deg above the horizontal
  message = ground_error(p);
  EXPECT_NE(message.find("the laser sheet does not descend ahead of the camera (it lies -5.00 deg below"),
            std::string::npos)
      << message;

  p = {};
  p.mount.pitch_rad = 70.0 * kDeg;
  p.sheet_angle_rad = 80.0 * kDeg;
  p.half_fov_vertical_rad = 10.0 * kDeg;
  message = ground_error(p);
  EXPECT_NE(message.find("above the image"), std::string::npos) << message;
}

TEST(StructuredLightReport, SheetInViewOfFig3) {
  StructuredLightParameters p;
  p.baseline_m = 0.1;
  p.sheet_angle_rad = 70.0 * kDeg;
  p.half_fov_vertical_rad = 19.1 * kDeg;
  p.half_fov_horizontal_rad = 24.8 * kDeg;
  const StructuredLightModel model(p);
  const SheetInView view = sheet_in_view(model);
  EXPECT_NEAR(view.axis_crossing_depth_m, 0.274748, 1e-6);
  EXPECT_NEAR(view.top_row.depth_m, 0.140795, 1e-6);
  EXPECT_NEAR(view.top_row.lateral_field_m, 2.0 * 0.0650565, 1e-6);
  ASSERT_TRUE(view.bottom_row.has_value());
  EXPECT_NEAR(view.bottom_row->depth_m, 5.65317, 1e-5);
  // |dz/dv| by central difference of the sheet depth.
  const double dz_dv = (*model.sheet_depth_at_row_m(0.001) - *model.sheet_depth_at_row_m(0.0)) / 0.001;
  EXPECT_NEAR(view.top_row.depth_per_row_m_per_px, dz_dv, 1e-6);

  p.sheet_angle_rad = 80.0 * kDeg;
  const SheetInView steep = sheet_in_view(StructuredLightModel(p));
  EXPECT_FALSE(steep.bottom_row.has_value());
  EXPECT_LT(steep.vanishing_row_px, 480.0);
}

}  // namespace
}  // namespace structured_light_report_test
}  // namespace stridemap
