// Issue 37: a tall white box beside the rail's line under bright ambient
// light. Its ambient-lit top, clipped in a thin band of the camera image,
// once passed for a saturated stripe and raised a ridge at the box's height
// over the free floor in front of it.
#include <gtest/gtest.h>

#include "stridemap/experiments/cart_rail.hpp"

namespace stridemap {
namespace {

Scene white_box_beside_the_line() {
  Scene scene;
  scene.terrain.reflectance = 0.2;  // a dark floor: auto exposure lifts the box top into the clip
  BoxObject box;
  box.name = "white_box";
  box.center_x_m = 1.0;
  box.center_y_m = 0.07;
  box.length_m = 0.10;
  box.width_m = 0.08;
  box.height_m = 0.12;
  box.reflectance = 0.8;
  scene.boxes.push_back(box);
  // The stripe sweeps the floor in front of the box, seen from afar.
  scene.cart_rail = CartRailPath{0.30, 0.60, 0.0, 0.02, 0.0};
  return scene;
}

CartRailResult run(int saturation_halo_dn) {
  CartRailOptions options;
  options.sensor = CartRailSensor::structured_light;
  options.structured_light.pipeline = StripePipeline::image;
  options.structured_light.image.ambient.illuminance_lux = 1000.0;
  options.structured_light.detector.saturation_halo_dn = saturation_halo_dn;
  options.cell_size_m = 0.005;
  options.map_filter = MapFilter::cas;
  return run_cart_rail(white_box_beside_the_line(), options);
}

TEST(PhantomRidge, TheWhiteBoxAt1000LuxLeavesTheFloorInFrontOfItFlat) {
  const CartRailResult fixed = run(io::StripeDetectorOptions{}.saturation_halo_dn);
  EXPECT_GT(fixed.score.clear_cells, 1000u);
  EXPECT_EQ(fixed.score.clear_artifact_cells, 0u);
  EXPECT_LT(fixed.score.clear_max_error_m, 0.01);
  EXPECT_LT(fixed.stripe.off_row_rate(), 0.005);
  // What is left false is light on the box, not points in the air.
  EXPECT_LE(fixed.stripe.off_surface, fixed.stripe.false_detections);
  EXPECT_LT(fixed.stripe.off_surface_rate(), 0.001);
  // and each of them lies on a peak of the laser's light in the image.
  EXPECT_LT(fixed.stripe.no_laser_light_rate(), 0.0005);
  // Nothing anywhere lies beyond the heights a reading near it could hold,
  // and the level cells (floor and top away from the edges) are exact.
  EXPECT_EQ(fixed.score.beyond_span_artifact_cells, 0u);
  EXPECT_LT(fixed.score.rms_error_level_m, 0.002);

  // The control: without the halo test the box top is taken for the stripe.
  const CartRailResult ridge = run(0);
  EXPECT_GT(ridge.score.clear_artifact_cells, 50u);
  EXPECT_GT(ridge.score.clear_max_error_m, 0.08);
  EXPECT_GT(ridge.stripe.off_row_rate(), 0.02);
  // The box top taken for the stripe maps above the floor in front of it.
  EXPECT_GT(ridge.stripe.off_surface_rate(), 0.02);
  // ... where the image holds no laser light.
  EXPECT_GT(ridge.stripe.no_laser_light_rate(), 0.02);
  // The span score sees the ridge too: its floor cells are level.
  EXPECT_GE(ridge.score.beyond_span_artifact_cells, ridge.score.clear_artifact_cells);
  EXPECT_GT(ridge.score.rms_error_level_m, 0.01);
}

}  // namespace
}  // namespace stridemap
