// Eq. (1) and (2): hand-computed cases, the inverse projection, invalid
// pixels, the analytic derivatives against finite differences, and the
// parameter checks.
#include <gtest/gtest.h>

#include <cmath>
#include <functional>
#include <numbers>
#include <random>
#include <string>

#include "stridemap/core/error.hpp"
#include "stridemap/sensors/structured_light.hpp"

namespace stridemap {
namespace structured_light_test {
namespace {

constexpr double kDeg = std::numbers::pi / 180.0;

// Fig. 3's example sensor (section 3.2).
StructuredLightParameters fig3_parameters() {
  StructuredLightParameters p;
  p.baseline_m = 0.100;
  p.sheet_angle_rad = 70.0 * kDeg;
  p.half_fov_vertical_rad = 19.1 * kDeg;
  p.half_fov_horizontal_rad = 24.8 * kDeg;
  p.image_width_px = 640;
  p.image_height_px = 480;
  return p;
}

// b = 1, beta = tau_c = gamma_c = 45 deg, a 2 x 2 image: every tangent is 1,
// so eq. (1) can be done in one's head.
StructuredLightParameters unit_parameters() {
  StructuredLightParameters p;
  p.baseline_m = 1.0;
  p.sheet_angle_rad = p.half_fov_vertical_rad = p.half_fov_horizontal_rad = 45.0 * kDeg;
  p.image_width_px = p.image_height_px = 2;
  return p;
}

Eigen::Vector3d point_at(const StructuredLightModel& model, double u, double v) {
  Eigen::Vector3d point = Eigen::Vector3d::Constant(-99.0);
  EXPECT_EQ(model.back_project(u, v, point), StripePointStatus::valid) << "u=" << u << " v=" << v;
  return point;
}

TEST(StructuredLightModel, UnitCasesByHand) {
  const StructuredLightModel model(unit_parameters());
  // Top-left corner: n_u = n_v = 1, D = 1 + 1: z = 0.5, x = z, y = z - b.
  Eigen::Vector3d p = point_at(model, 0.0, 0.0);
  EXPECT_NEAR(p.x(), 0.5, 1e-15);
  EXPECT_NEAR(p.y(), -0.5, 1e-15);
  EXPECT_NEAR(p.z(), 0.5, 1e-15);
  // Right edge, v = 1.5: n_u = -1, n_v = -0.5, D = 0.5: z = 2, x = -2, y = 1.
  p = point_at(model, 2.0, 1.5);
  EXPECT_NEAR(p.x(), -2.0, 1e-14);
  EXPECT_NEAR(p.y(), 1.0, 1e-14);
  EXPECT_NEAR(p.z(), 2.0, 1e-14);
  // The bottom edge's ray runs parallel to the sheet (D = 0): no point.
  EXPECT_EQ(model.back_project(1.0, 2.0, p), StripePointStatus::no_intersection);
  EXPECT_DOUBLE_EQ(model.vanishing_row_px(), 2.0);
}

TEST(StructuredLightModel, Fig3CasesMatchThePrintedFormulas) {
  // Values from eq. (1) exactly as printed, including its form of y_c,
  // evaluated separately (Python, double precision).
  struct Case {
    double u, v, x, y, z;
  };
  const Case cases[] = {
      {0.0, 0.0, 0.0650565344678, -0.0487547233359, 0.140795240488},
      {320.0, 240.0, 0.0, 0.0, 0.274747741945},
      {640.0, 480.0, -2.61213175934, 1.95758600247, 5.65317108037},
      {160.0, 360.0, 0.121067329708, 0.0907303810939, 0.52402741526},
      {500.25, 100.5, -0.0460458693416, -0.0356085360421, 0.17691409323},
  };
  const StructuredLightModel model(fig3_parameters());
  for (const Case& c : cases) {
    const Eigen::Vector3d p = point_at(model, c.u, c.v);
    const double tolerance = 1e-11 * (1.0 + p.norm());
    EXPECT_NEAR(p.x(), c.x, tolerance) << c.u << "," << c.v;
    EXPECT_NEAR(p.y(), c.y, tolerance) << c.u << "," << c.v;
    EXPECT_NEAR(p.z(), c.z, tolerance) << c.u << "," << c.v;
  }
}

TEST(StructuredLightModel, ConventionsOfTheFrame) {
  const StructuredLightModel model(fig3_parameters());
  // v = 0 (top row) sees above the optical axis (y_c < 0: y_c points down),
  // u = 0 (left column) sees to the left (x_c > 0).
  EXPECT_LT(point_at(model, 320.0, 0.0).y(), 0.0);
  EXPECT_GT(point_at(model, 320.0, 480.0).y(), 0.0);
  EXPECT_GT(point_at(model, 0.0, 240.0).x(), 0.0);
  // Rows further down see the sheet farther away (the emitter is above).
  EXPECT_LT(point_at(model, 320.0, 100.0).z(), point_at(model, 320.0, 400.0).z());
  // The sheet crosses the optical axis at b tan(beta).
  EXPECT_NEAR(point_at(model, 320.0, 240.0).z(), 0.1 * std::tan(70.0 * kDeg), 1e-15);
  // Sensor frame of core: forward, left, up.
  const Eigen::Vector3d s = camera_to_sensor_frame({0.1, 0.2, 0.3});
  EXPECT_EQ(s, Eigen::Vector3d(0.3, 0.1, -0.2));
}

TEST(StructuredLightModel, InvalidPixelsAreReportedNotNaN) {
  StructuredLightParameters p = fig3_parameters();
  p.sheet_angle_rad = 80.0 * kDeg;  // cot = 0.176 < tan(tau) = 0.346: the sheet vanishes inside the image
  const StructuredLightModel model(p);
  const double vanishing = model.vanishing_row_px();
  EXPECT_NEAR(vanishing, 240.0 * (1.0 + (1.0 / std::tan(80.0 * kDeg)) / std::tan(19.1 * kDeg)), 1e-9);
  Eigen::Vector3d point(7.0, 7.0, 7.0);
  EXPECT_EQ(model.back_project(320.0, vanishing, point), StripePointStatus::no_intersection);
  EXPECT_EQ(model.back_project(320.0, 479.0, point), StripePointStatus::no_intersection);
  EXPECT_EQ(model.back_project(std::nan(""), 10.0, point), StripePointStatus::not_finite);
  EXPECT_EQ(model.back_project(10.0, INFINITY, point), StripePointStatus::not_finite);
  EXPECT_EQ(model.back_project(-0.01, 10.0, point), StripePointStatus::outside_image);
  EXPECT_EQ(model.back_project(10.0, 480.01, point), StripePointStatus::outside_image);
  EXPECT_EQ(point, Eigen::Vector3d(7.0, 7.0, 7.0)) << "an invalid pixel must not touch the output";
  EXPECT_FALSE(model.sheet_depth_at_row_m(400.0).has_value());
  // Just above the vanishing row the point is far away but finite.
  ASSERT_EQ(model.back_project(320.0, vanishing - 0.01, point), StripePointStatus::valid);
  EXPECT_TRUE(point.allFinite());
  EXPECT_GT(point.z(), 100.0);
  EXPECT_STREQ(to_string(StripePointStatus::no_intersection), "no intersection with the sheet");
}

TEST(StructuredLightModel, RoundTripSheetPointToPixelAndBack) {
  const StructuredLightModel model(fig3_parameters());
  std::mt19937_64 random(20240607);
  std::uniform_real_distribution<double> depth(0.15, 3.0), spread(-1.0, 1.0);
  int checked = 0;
  for (int i = 0; i < 2000; ++i) {
    const double z = depth(random);
    const Eigen::Vector3d on_sheet(spread(random) * z * std::tan(24.8 * kDeg), z / std::tan(70.0 * kDeg) - 0.1, z);
    ASSERT_NEAR(model.distance_from_sheet_m(on_sheet), 0.0, 1e-15);
    const auto pixel = model.project(on_sheet);
    ASSERT_TRUE(pixel.has_value());
    if (!model.in_image(pixel->x(), pixel->y())) continue;
    const Eigen::Vector3d back = point_at(model, pixel->x(), pixel->y());
    EXPECT_LT((back - on_sheet).norm(), 1e-12 * z) << "z=" << z;
    EXPECT_NEAR(model.row_at_sheet_depth_px(z), pixel->y(), 1e-9);
    ++checked;
  }
  EXPECT_GT(checked, 500);
  // And pixel -> point -> pixel.
  for (double u = 0.0; u <= 640.0; u += 63.7) {
    for (double v = 0.0; v <= 480.0; v += 47.3) {
      const Eigen::Vector3d point = point_at(model, u, v);
      EXPECT_NEAR(model.distance_from_sheet_m(point), 0.0, 1e-14 * (1.0 + point.norm()));
      const auto pixel = model.project(point);
      ASSERT_TRUE(pixel.has_value());
      EXPECT_NEAR(pixel->x(), u, 1e-9);
      EXPECT_NEAR(pixel->y(), v, 1e-9);
    }
  }
  EXPECT_GT(model.distance_from_sheet_m(Eigen::Vector3d::Zero()), 0.0) << "positive on the camera's side";
  EXPECT_FALSE(model.project({0.0, 0.0, -1.0}).has_value());
}

// Central difference of the back-projected point when one parameter moves.
using Move = std::function<void(StructuredLightParameters&, double&, double&, double)>;

Eigen::Vector3d numeric_derivative(const StructuredLightParameters& base, double u, double v, const Move& move,
                                   double step) {
  StructuredLightParameters plus = base, minus = base;
  double u_plus = u, v_plus = v, u_minus = u, v_minus = v;
  move(plus, u_plus, v_plus, step);
  move(minus, u_minus, v_minus, -step);
  Eigen::Vector3d a, b;
  EXPECT_EQ(StructuredLightModel(plus).back_project(u_plus, v_plus, a), StripePointStatus::valid);
  EXPECT_EQ(StructuredLightModel(minus).back_project(u_minus, v_minus, b), StripePointStatus::valid);
  return (a - b) / (2.0 * step);
}

TEST(StructuredLightModel, DerivativesMatchFiniteDifferences) {
  const Move baseline = [](StructuredLightParameters& p, double&, double&, double h) { p.baseline_m += h; };
  const Move sheet = [](StructuredLightParameters& p, double&, double&, double h) { p.sheet_angle_rad += h; };
  const Move tau = [](StructuredLightParameters& p, double&, double&, double h) { p.half_fov_vertical_rad += h; };
  const Move gamma = [](StructuredLightParameters& p, double&, double&, double h) { p.half_fov_horizontal_rad += h; };
  const Move row = [](StructuredLightParameters&, double&, double& v, double h) { v += h; };
  const Move column = [](StructuredLightParameters&, double& u, double&, double h) { u += h; };

  for (const StructuredLightParameters& parameters : {fig3_parameters(), StructuredLightParameters{}}) {
    const StructuredLightModel model(parameters);
    for (const auto& pixel : {std::pair{17.0, 33.0}, {320.0, 240.0}, {601.5, 410.25}, {250.0, 5.0}}) {
      // Plain copies: clang 14 cannot capture structured bindings in lambdas.
      const double u = pixel.first, v = pixel.second;
      CameraPointPartials d;
      ASSERT_EQ(model.back_project(u, v, d), StripePointStatus::valid);
      Eigen::Vector3d plain;
      model.back_project(u, v, plain);
      EXPECT_LT((d.point - plain).norm(), 1e-15);
      const auto expect_close = [&](const Eigen::Vector3d& analytic, const Eigen::Vector3d& numeric, const char* name) {
        EXPECT_LT((analytic - numeric).norm(), 1e-6 * (1.0 + numeric.norm()))
            << name << " at (" << u << ", " << v << "): analytic " << analytic.transpose() << ", numeric "
            << numeric.transpose();
      };
      expect_close(d.d_baseline, numeric_derivative(parameters, u, v, baseline, 1e-6), "d/db");
      expect_close(d.d_sheet_angle, numeric_derivative(parameters, u, v, sheet, 1e-6), "d/dbeta");
      expect_close(d.d_half_fov_vertical, numeric_derivative(parameters, u, v, tau, 1e-6), "d/dtau_c");
      expect_close(d.d_half_fov_horizontal, numeric_derivative(parameters, u, v, gamma, 1e-6), "d/dgamma_c");
      expect_close(d.d_row, numeric_derivative(parameters, u, v, row, 1e-3), "d/dv");
      expect_close(d.d_column, numeric_derivative(parameters, u, v, column, 1e-3), "d/du");
    }
  }
}

TEST(StructuredLightModel, FocalLengthEquationTwo) {
  // Fig. 3's angles are one focal length of about 693 px for a VGA image.
  const double f = focal_length_from_half_fov_px(480.0, 19.1 * kDeg);
  EXPECT_NEAR(f, 693.1, 0.1);
  EXPECT_NEAR(focal_length_from_half_fov_px(640.0, 24.8 * kDeg), 692.5, 0.1);
  EXPECT_NEAR(half_fov_from_focal_length_rad(480.0, f), 19.1 * kDeg, 1e-12);
  EXPECT_NEAR(half_fov_from_focal_length_rad(640.0, 320.0), std::numbers::pi / 4, 1e-15);
  EXPECT_THROW(half_fov_from_focal_length_rad(480.0, 0.0), InputError);
  EXPECT_THROW(focal_length_from_half_fov_px(480.0, 90.0 * kDeg), InputError);
}

std::string problem_of(const StructuredLightParameters& p) {
  try {
    p.validate();
  } catch (const InputError& e) {
    return e.what();
  }
  return "(accepted)";
}

TEST(StructuredLightParametersCheck, NamesTheFieldAndTheValue) {
  EXPECT_EQ(problem_of(StructuredLightParameters{}), "(accepted)");
  StructuredLightParameters p;
  p.baseline_m = -0.12;
  EXPECT_EQ(problem_of(p), "structured light parameters: baseline_m: must be a positive number of metres up to 10 "
                          "(is it in millimetres?), got -0.12");
  p.baseline_m = 120.0;
  EXPECT_EQ(problem_of(p), "structured light parameters: baseline_m: must be a positive number of metres up to 10 "
                          "(is it in millimetres?), got 120");
  p = {};
  p.sheet_angle_rad = 90.0 * kDeg;
  EXPECT_EQ(problem_of(p),
            "structured light parameters: sheet_angle_rad: must lie strictly between 0 and 90 deg, got 90 deg");
  p = {};
  p.half_fov_horizontal_rad = std::nan("");
  EXPECT_NE(problem_of(p).find("half_fov_horizontal_rad: must lie strictly between 0 and 90 deg"), std::string::npos);
  p = {};
  p.image_height_px = 0;
  EXPECT_NE(problem_of(p).find("image_height_px: must be a whole number of pixels"), std::string::npos);
  p = {};
  p.mount.height_m = 0.0;
  EXPECT_NE(problem_of(p).find("mount.height_m: must be a positive number of metres, got 0"), std::string::npos);
  p = {};
  p.mount.pitch_rad = -95.0 * kDeg;
  EXPECT_NE(problem_of(p).find("mount.pitch_rad: must lie strictly between -90 and 90 deg, got -95 deg"),
            std::string::npos);
  p = {};
  p.sheet_angle_error_rad = -0.5 * kDeg;
  EXPECT_NE(problem_of(p).find("sheet_angle_error_rad: must be a number >= 0, got -0.5 deg"), std::string::npos);
  p = {};
  p.row_error_px = INFINITY;
  EXPECT_NE(problem_of(p).find("row_error_px"), std::string::npos);
  EXPECT_THROW(StructuredLightModel{p}, InputError);
}

}  // namespace
}  // namespace structured_light_test
}  // namespace stridemap
