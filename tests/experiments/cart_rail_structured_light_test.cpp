// The cart-rail run with the structured-light sensor: both pipelines on a
// short rail past one box, against the simulator's truth.
#include <cmath>
#include <numbers>
#include <string>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "stridemap/core/error.hpp"
#include "stridemap/experiments/cart_rail.hpp"
#include "stridemap/experiments/cart_rail_report.hpp"
#include "stridemap/experiments/lighting.hpp"

namespace stridemap {
namespace {

// A box 0.40-0.50 m ahead; the stripe (0.225 m ahead of the camera) crosses
// it while the cart moves from 0.10 to 0.32 m.
Scene one_box_scene(double rail_step_m = 0.01) {
  Scene scene;
  BoxObject box;
  box.name = "box";
  box.center_x_m = 0.452;
  box.center_y_m = 0.003;
  box.length_m = 0.10;
  box.width_m = 0.10;
  box.height_m = 0.06;
  box.reflectance = 0.6;
  scene.boxes.push_back(box);
  scene.cart_rail = CartRailPath{0.10, 0.32, 0.0, rail_step_m, 0.0};
  return scene;
}

CartRailOptions structured_light(StripePipeline pipeline) {
  CartRailOptions options;
  options.sensor = CartRailSensor::structured_light;
  options.structured_light.pipeline = pipeline;
  options.cell_size_m = 0.005;
  options.map_filter = MapFilter::cas;
  return options;
}

TEST(CartRailStructuredLight, ImagePathMapsTheBoxLikeTheGeometricTruth) {
  const Scene scene = one_box_scene();
  const CartRailResult image = run_cart_rail(scene, structured_light(StripePipeline::image));
  const CartRailResult geometric = run_cart_rail(scene, structured_light(StripePipeline::geometric));
  EXPECT_EQ(image.scans, 23u);
  EXPECT_EQ(image.stripe.frames, 23u);
  EXPECT_EQ(image.stripe.columns, 23u * 640);
  EXPECT_EQ(image.stripe.truth_visible, geometric.stripe.truth_visible);
  EXPECT_GT(image.stripe.detection_rate(), 0.97);
  EXPECT_LT(image.stripe.false_rate(), 0.01);
  EXPECT_LT(image.stripe.row_error_rms_px, 0.4);
  EXPECT_DOUBLE_EQ(geometric.stripe.detection_rate(), 1.0);
  EXPECT_EQ(geometric.stripe.false_detections, 0u);
  EXPECT_EQ(geometric.stripe.map_points, geometric.stripe.truth_visible);
  for (const CartRailResult* r : {&image, &geometric}) {
    EXPECT_LT(r->score.rms_error_m, 0.008);
    EXPECT_GT(r->score.coverage, 0.6);
    ASSERT_EQ(r->objects.size(), 1u);
    ASSERT_TRUE(r->objects[0].found);
    EXPECT_NEAR(r->objects[0].measured.height_m, 0.06, 0.003);
    EXPECT_NEAR(r->objects[0].measured.width_m, 0.10, 0.011);
    EXPECT_NEAR(r->snapshot.cell_size_m, 0.005, 1e-12);
  }
  const nlohmann::json summary =
      nlohmann::json::parse(cart_rail_summary_json(image, structured_light(StripePipeline::image), {"structured-light", "x"}));
  EXPECT_EQ(summary["structured_light"]["pipeline"], "image");
  EXPECT_EQ(summary["structured_light"]["frames"], 23);
  EXPECT_NEAR(summary["mount"]["height_m"].get<double>(), 0.174, 1e-12);  // Ragno's, not the URG's
  EXPECT_NE(cart_rail_table(image, {"structured-light", "x"}).find("stripe: 23 frames"), std::string::npos);
}

TEST(CartRailStructuredLight, DeterministicForASeed) {
  const Scene scene = one_box_scene(0.11);
  CartRailOptions options = structured_light(StripePipeline::image);
  const CartRailResult a = run_cart_rail(scene, options);
  const CartRailResult b = run_cart_rail(scene, options);
  EXPECT_EQ(a.stripe.detected, b.stripe.detected);
  EXPECT_EQ(a.stripe.row_error_rms_px, b.stripe.row_error_rms_px);
  EXPECT_EQ(a.score.rms_error_m, b.score.rms_error_m);
}

TEST(CartRailStructuredLight, MountThatCannotSeeTheGroundIsAnError) {
  CartRailOptions options = structured_light(StripePipeline::geometric);
  options.structured_light.parameters.mount.pitch_rad = 0.0;  // Ragno level: the stripe falls below the image
  try {
    run_cart_rail(one_box_scene(), options);
    FAIL() << "no error";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("cannot see the ground"), std::string::npos) << e.what();
  }
}

TEST(CartRailStructuredLight, OffSurfaceDistanceOutOfRangeIsAnError) {
  for (double bad : {0.0, -0.005, 1.0, std::nan("")}) {
    CartRailOptions options = structured_light(StripePipeline::geometric);
    options.structured_light.off_surface_m = bad;
    try {
      run_cart_rail(one_box_scene(), options);
      FAIL() << "no error for " << bad;
    } catch (const InputError& e) {
      EXPECT_NE(std::string(e.what()).find("off_surface_m"), std::string::npos) << e.what();
    }
  }
}

TEST(CartRailStructuredLight, LaserLightThresholdNotPositiveIsAnError) {
  for (double bad : {0.0, -3.0, std::nan("")}) {
    CartRailOptions options = structured_light(StripePipeline::image);
    options.structured_light.laser_light_min_snr = bad;
    try {
      run_cart_rail(one_box_scene(), options);
      FAIL() << "no error for " << bad;
    } catch (const InputError& e) {
      EXPECT_NE(std::string(e.what()).find("laser_light_min_snr > 0"), std::string::npos) << e.what();
    }
  }
}

TEST(LightingExperiment, DaylightDrownsTheStripeAndLeavesTheUrgAlone) {
  const Scene scene = one_box_scene(0.11);
  LightingOptions options;
  options.structured_light = structured_light(StripePipeline::image);
  options.levels = {{"lab", 300.0}, {"daylight", 30000.0}};
  options.example_x_m = 0.2;
  std::size_t reports = 0;
  std::size_t last_done = 0, last_total = 0;
  options.progress = [&](std::size_t done, std::size_t total) {
    ++reports;
    last_done = done;
    last_total = total;
  };
  const LightingResult result = run_lighting(scene, options);
  ASSERT_EQ(result.rows.size(), 2u);
  EXPECT_GT(reports, 3u);  // every level and the URG's run report
  EXPECT_EQ(last_done, last_total);
  EXPECT_GT(result.rows[0].stripe.detection_rate(), 0.95);
  EXPECT_LT(result.rows[1].stripe.detection_rate(), 0.05);
  EXPECT_LT(result.rows[0].score.rms_error_m, 0.01);
  EXPECT_EQ(result.rows[1].score.known_cells, 0u);  // nothing to map in daylight
  EXPECT_EQ(result.rows[0].example.width, 640);
  EXPECT_GT(result.urg_range.beams, 1000u);
  EXPECT_LT(result.urg_range.rms_m, 0.008);
  EXPECT_GT(result.urg_range.rms_m, 0.001);  // the model's noise is there
  const std::string table = lighting_table(result);
  EXPECT_NE(table.find("daylight"), std::string::npos);
  options.levels = {{"dark", 0.0}};
  EXPECT_THROW(run_lighting(scene, options), InputError);
}

}  // namespace
}  // namespace stridemap
