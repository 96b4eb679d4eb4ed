// Section 3.2, Fig. 3: spatial uncertainty over the x_c-z_c plane for the
// paper's example sensor, checked against the paper's description and the
// closed forms of the pixel terms.
#include <gtest/gtest.h>

#include <cmath>
#include <numbers>
#include <string>

#include "stridemap/core/error.hpp"
#include "stridemap/sensors/structured_light_uncertainty.hpp"

namespace stridemap {
namespace structured_light_uncertainty_test {
namespace {

constexpr double kDeg = std::numbers::pi / 180.0;

StructuredLightModel fig3_model() {
  StructuredLightParameters p;
  p.baseline_m = 0.100;
  p.sheet_angle_rad = 70.0 * kDeg;
  p.half_fov_vertical_rad = 19.1 * kDeg;
  p.half_fov_horizontal_rad = 24.8 * kDeg;
  p.row_error_px = p.column_error_px = 0.5;
  return StructuredLightModel(p);
}

TEST(StructuredLightUncertainty, PixelTermsHaveTheirClosedForms) {
  const StructuredLightModel model = fig3_model();
  const double tan_tau = std::tan(19.1 * kDeg), tan_gamma = std::tan(24.8 * kDeg);
  for (const double depth : {0.2, 0.5, 1.0}) {
    const double row = model.row_at_sheet_depth_px(depth);
    const auto axis = pixel_point_uncertainty(model, 320.0, row);
    ASSERT_TRUE(axis.has_value());
    // |dz/dv| = 2 tan(tau) z^2 / (R_ver b); |dx/du| = 2 z tan(gamma) / R_hor.
    EXPECT_NEAR(axis->z_m, 0.5 * 2.0 * tan_tau * depth * depth / (480.0 * 0.1), 1e-12);
    EXPECT_NEAR(axis->x_m, 0.5 * 2.0 * depth * tan_gamma / 640.0, 1e-12);
  }
  EXPECT_NEAR(pixel_point_uncertainty(model, 320.0, model.row_at_sheet_depth_px(0.5))->z_m, 0.0018036, 1e-7);
  EXPECT_FALSE(pixel_point_uncertainty(model, -5.0, 100.0).has_value());
  // Calibration errors only add.
  const auto with_calibration = pixel_point_uncertainty(model, 100.0, 300.0, true);
  const auto pixels_only = pixel_point_uncertainty(model, 100.0, 300.0, false);
  EXPECT_GT(with_calibration->z_m, pixels_only->z_m);
  EXPECT_GT(with_calibration->x_m, pixels_only->x_m);
}

TEST(StructuredLightUncertainty, Fig3MapsFollowThePapersDescription) {
  const StructuredLightModel model = fig3_model();
  UncertaintyMapOptions options;
  options.cell_size_m = 0.01;
  options.max_depth_m = 1.0;
  const UncertaintyMaps maps = structured_light_uncertainty_maps(model, options);
  ASSERT_EQ(maps.z_uncertainty_m.rows(), 100);
  const int columns = static_cast<int>(maps.z_uncertainty_m.cols());
  ASSERT_EQ(columns % 2, 0);
  const int centre = columns / 2;  // first column left of the axis
  const auto depth_row = [&](double depth) { return static_cast<int>(std::floor(depth / maps.cell_size_m)); };

  // Nearer than the top row's depth (0.141 m) and outside the view: unseen.
  EXPECT_TRUE(std::isnan(maps.z_uncertainty_m(depth_row(0.1), centre)));
  EXPECT_TRUE(std::isnan(maps.x_uncertainty_m(depth_row(0.3), 0)));
  EXPECT_FALSE(std::isnan(maps.z_uncertainty_m(depth_row(0.3), centre)));

  // z: grows with distance like z^2 ("hyperbolically").
  const double z_near = maps.z_uncertainty_m(depth_row(0.4), centre);
  const double z_far = maps.z_uncertainty_m(depth_row(0.8), centre);
  EXPECT_NEAR(z_far / z_near, std::pow(0.805 / 0.405, 2.0), 0.01);
  for (int i = depth_row(0.2); i + 1 < maps.z_uncertainty_m.rows(); ++i) {
    EXPECT_LT(maps.z_uncertainty_m(i, centre), maps.z_uncertainty_m(i + 1, centre));
  }
  // x: grows only slightly with distance on the axis (linearly, below 1 mm
  // within 1 m), much more with the lateral offset.
  const double x_axis_near = maps.x_uncertainty_m(depth_row(0.4), centre);
  const double x_axis_far = maps.x_uncertainty_m(depth_row(0.8), centre);
  EXPECT_GT(x_axis_far, x_axis_near);
  EXPECT_LT(x_axis_far, 0.001);
  const int row = depth_row(0.8);
  double previous = maps.x_uncertainty_m(row, centre);
  int lateral_steps = 0;
  for (int j = centre + 1; j < columns && !std::isnan(maps.x_uncertainty_m(row, j)); ++j, ++lateral_steps) {
    EXPECT_GT(maps.x_uncertainty_m(row, j), previous);
    previous = maps.x_uncertainty_m(row, j);
  }
  EXPECT_GT(lateral_steps, 20);
  EXPECT_GT(previous, 3.0 * x_axis_far);
  // Symmetric about the optical axis.
  EXPECT_NEAR(maps.x_uncertainty_m(row, centre + 10), maps.x_uncertainty_m(row, centre - 11), 1e-9);
  // Cell (i, j) is at the documented place.
  EXPECT_NEAR(maps.first_depth_m, 0.005, 1e-15);
  EXPECT_NEAR(maps.first_lateral_m + centre * maps.cell_size_m, 0.005, 1e-12);
}

TEST(StructuredLightUncertainty, BadOptionsAreNamed) {
  const StructuredLightModel model = fig3_model();
  UncertaintyMapOptions options;
  options.cell_size_m = 0.0;
  try {
    structured_light_uncertainty_maps(model, options);
    FAIL() << "accepted a zero cell size";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("cell_size_m must be a positive number of metres, got 0"), std::string::npos);
  }
  options = {};
  options.cell_size_m = 0.0001;
  options.max_depth_m = 10.0;
  try {
    structured_light_uncertainty_maps(model, options);
    FAIL() << "accepted a 100000-cell grid";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("max_depth_m / cell_size_m gives 100000 cells"), std::string::npos)
        << e.what();
  }
  options = {};
  options.max_depth_m = std::nan("");
  EXPECT_THROW(structured_light_uncertainty_maps(model, options), InputError);
}

}  // namespace
}  // namespace structured_light_uncertainty_test
}  // namespace stridemap
