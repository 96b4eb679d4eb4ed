#include "stridemap/sim/structured_light_image.hpp"

#include <cmath>
#include <limits>
#include <numbers>

#include <gtest/gtest.h>

#include "stridemap/core/error.hpp"

namespace stridemap {
namespace structured_light_image_test {
namespace {

Scene floor_scene() {
  Scene scene;
  scene.terrain.reflectance = 0.5;
  return scene;
}

// Ragno's geometry on a 160 x 120 image: same angles, a quarter of the pixels.
StructuredLightParameters small_ragno() {
  StructuredLightParameters p;
  p.image_width_px = 160;
  p.image_height_px = 120;
  return p;
}

struct Pixel {
  int r, g, b;
};
Pixel at(const std::vector<std::uint8_t>& rgb, int width, int column, int row) {
  const std::size_t o = 3 * (static_cast<std::size_t>(row) * width + column);
  return {rgb[o], rgb[o + 1], rgb[o + 2]};
}

// Row of the largest red excess in a column, and that excess.
std::pair<int, int> reddest_row(const std::vector<std::uint8_t>& rgb, int width, int height, int column) {
  int best_row = -1, best = std::numeric_limits<int>::min();
  for (int row = 0; row < height; ++row) {
    const Pixel p = at(rgb, width, column, row);
    const int redness = p.r - std::max(p.g, p.b);
    if (redness > best) best = redness, best_row = row;
  }
  return {best_row, best};
}

TEST(StructuredLightImage, StripeLiesOnTheTrueRowInLabLight) {
  StructuredLightImageRenderer renderer(floor_scene(), StructuredLightParameters{});  // Ragno, VGA
  std::vector<std::uint8_t> rgb;
  StructuredLightFrameTruth truth;
  const StripeImageStats stats = renderer.render(TrunkPose{}, rgb, &truth);
  ASSERT_EQ(rgb.size(), 3u * 640 * 480);
  EXPECT_GT(stats.laser_pixels, 640u);
  double redness_sum = 0.0;
  int columns = 0;
  for (int column = 0; column < 640; column += 9, ++columns) {
    const auto [row, redness] = reddest_row(rgb, 640, 480, column);
    EXPECT_NEAR(row + 0.5, truth.columns[column].v_px, 1.5) << column;
    EXPECT_GT(redness, 40) << column;
    redness_sum += redness;
  }
  EXPECT_GT(redness_sum / columns, 60.0);
  // Away from the stripe the (grey) floor shows no colour beyond noise.
  const Pixel floor = at(rgb, 640, 320, 400);
  EXPECT_LT(std::abs(floor.r - floor.g), 15);
  // Auto exposure brings the mean green level to its target of 110.
  double green = 0.0;
  for (std::size_t i = 1; i < rgb.size(); i += 3) green += rgb[i];
  EXPECT_NEAR(green / (640.0 * 480.0), 110.0, 2.0);
}

TEST(StructuredLightImage, DaylightDrownsTheStripeAndDimLightSaturatesIt) {
  StructuredLightImageRenderer renderer(floor_scene(), StructuredLightParameters{});
  std::vector<std::uint8_t> rgb;
  StructuredLightFrameTruth truth;
  AmbientLight light;
  light.illuminance_lux = 50.0;
  renderer.set_ambient(light);
  const StripeImageStats dim = renderer.render(TrunkPose{}, rgb, &truth);
  const int row = static_cast<int>(truth.columns[320].v_px);
  EXPECT_EQ(at(rgb, 640, 320, row).r, 255);
  EXPECT_GT(dim.saturated_pixels, 300u);
  // The exposure limit keeps a dim scene dark.
  EXPECT_LT(at(rgb, 640, 320, 400).g, 70);
  renderer = StructuredLightImageRenderer(floor_scene(), small_ragno());

  light.illuminance_lux = 30000.0;
  renderer.set_ambient(light);
  const StripeImageStats bright = renderer.render(TrunkPose{}, rgb, &truth);
  EXPECT_LT(bright.gain_dn_per_lux, dim.gain_dn_per_lux / 100.0);
  int strong = 0;
  for (int column = 0; column < 160; ++column) strong += reddest_row(rgb, 160, 120, column).second > 30;
  EXPECT_LT(strong, 16);  // the stripe adds about 4 DN: only noise peaks remain
}

TEST(StructuredLightImage, StripeEnergyFollowsRangeIncidenceAndReflectance) {
  // A wall across the optical axis of a level sensor: the laser light a
  // column collects is rho k P cos(i) f_v / (2 phi r z sin(beta)) (the
  // line's power per length over the emitter range r, spread across the
  // rows by the wall's depth z), however the sub-rows and the blur share it.
  StripeImageOptions fixed;
  fixed.camera.auto_exposure = false;
  fixed.camera.enable_noise = false;
  fixed.camera.fixed_gain_dn_per_lux = 0.1;  // nothing saturates
  fixed.ambient.illuminance_lux = 0.0;
  StructuredLightParameters level = small_ragno();
  level.mount.pitch_rad = 0.0;
  const double f_v = 0.5 * level.image_height_px / std::tan(level.half_fov_vertical_rad);
  for (const double wall_m : {0.12, 0.20}) {
    Scene scene = floor_scene();
    BoxObject wall;
    wall.name = "wall";
    wall.center_x_m = wall_m + 0.05;
    wall.length_m = 0.1;
    wall.width_m = 2.0;
    wall.height_m = 1.0;
    wall.reflectance = 0.7;
    scene.boxes.push_back(wall);
    StructuredLightImageRenderer renderer(scene, level, fixed);
    std::vector<std::uint8_t> rgb;
    StructuredLightFrameTruth truth;
    renderer.render(TrunkPose{}, rgb, &truth);
    for (int column : {20, 80, 140}) {
      const StripeColumnTruth& c = truth.columns[column];
      ASSERT_EQ(c.label, StripeColumnLabel::visible);
      double red_sum = 0.0;
      for (int row = 0; row < 120; ++row) red_sum += at(rgb, 160, column, row).r;
      const LaserStripeOptions& laser = fixed.laser;
      const double expected = 0.1 * c.reflectance * laser.red_lux_per_w_per_m2 * laser.power_w * c.cos_incidence * f_v /
                              (2.0 * std::numbers::pi / 4.0 * c.emitter_range_m * c.camera_point_m.z() *
                               std::sin(level.sheet_angle_rad));
      EXPECT_NEAR(red_sum, expected, 0.03 * expected + 3.0) << wall_m << " m, column " << column;
    }
  }
}

TEST(StructuredLightImage, WithoutLaserOrNoiseThePixelsAreAlbedoTimesLight) {
  StripeImageOptions fixed;
  fixed.camera.auto_exposure = false;
  fixed.camera.enable_noise = false;
  std::vector<std::uint8_t> rgb;
  StripeImageOptions no_laser = fixed;
  no_laser.laser.power_w = 0.0;
  StructuredLightImageRenderer dark(floor_scene(), small_ragno(), no_laser);
  EXPECT_EQ(dark.render(TrunkPose{}, rgb).laser_pixels, 0u);
  // Without noise and laser every floor pixel is reflectance x lux x gain.
  const Pixel floor = at(rgb, 160, 80, 100);
  EXPECT_EQ(floor.g, static_cast<int>(std::round(0.5 * 300.0 * 0.8)));
  EXPECT_EQ(floor.r, floor.b);
}

TEST(StructuredLightImage, NoLaserLightWhereTheCameraSeesTheOccluder) {
  // The bar of the geometric test hides the lit ground from the camera: the
  // image shows the bar there, with no stripe on it at the hidden row.
  Scene scene = floor_scene();
  BoxObject bar;
  bar.name = "bar";
  bar.center_x_m = 0.1525;
  bar.length_m = 0.005;
  bar.width_m = 0.06;
  bar.height_m = 0.08;
  scene.boxes.push_back(bar);
  StripeImageOptions options;
  options.camera.enable_noise = false;
  StructuredLightImageRenderer renderer(scene, small_ragno(), options);
  std::vector<std::uint8_t> rgb;
  StructuredLightFrameTruth truth;
  renderer.render(TrunkPose{}, rgb, &truth);
  const StripeColumnTruth& centre = truth.columns[80];
  ASSERT_EQ(centre.label, StripeColumnLabel::hidden_from_camera);
  const Pixel hidden = at(rgb, 160, 80, static_cast<int>(centre.v_px));
  EXPECT_EQ(hidden.r, hidden.g);
  ASSERT_EQ(truth.columns[5].label, StripeColumnLabel::visible);
  EXPECT_GT(reddest_row(rgb, 160, 120, 5).second, 50);
}

TEST(StructuredLightImage, TheLaserLightTruthPeaksOnTheStripeAndIsDarkElsewhere) {
  StructuredLightImageRenderer renderer(floor_scene(), small_ragno());
  EXPECT_EQ(renderer.laser_signal_dn(80, 60), 0.0);  // before the first frame
  std::vector<std::uint8_t> rgb;
  StructuredLightFrameTruth truth;
  renderer.render(TrunkPose{}, rgb, &truth);
  int visible = 0;
  for (int column = 0; column < 160; ++column) {
    if (truth.columns[column].label != StripeColumnLabel::visible) continue;
    ++visible;
    int peak = 0;
    for (int row = 1; row < 120; ++row) {
      if (renderer.laser_signal_dn(column, row) > renderer.laser_signal_dn(column, peak)) peak = row;
    }
    EXPECT_NEAR(peak + 0.5, truth.columns[column].v_px, 1.0) << column;
    EXPECT_GT(renderer.laser_signal_to_noise(column, peak), 10.0) << column;
    // Ten rows off the stripe there is no laser light at all.
    EXPECT_EQ(renderer.laser_signal_dn(column, peak >= 60 ? peak - 10 : peak + 10), 0.0) << column;
  }
  EXPECT_GT(visible, 100);
  EXPECT_EQ(renderer.laser_signal_dn(-1, 60), 0.0);
  EXPECT_EQ(renderer.laser_signal_to_noise(160, 60), 0.0);
  EXPECT_EQ(renderer.laser_signal_to_noise(80, 120), 0.0);
}

TEST(StructuredLightImage, DeterministicForASeed) {
  std::vector<std::uint8_t> a, b, c;
  StructuredLightImageRenderer first(floor_scene(), small_ragno(), {}, {}, 9);
  StructuredLightImageRenderer second(floor_scene(), small_ragno(), {}, {}, 9);
  StructuredLightImageRenderer other(floor_scene(), small_ragno(), {}, {}, 10);
  first.render(TrunkPose{}, a);
  second.render(TrunkPose{}, b);
  other.render(TrunkPose{}, c);
  EXPECT_EQ(a, b);
  EXPECT_NE(a, c);
  first.render(TrunkPose{}, b);
  EXPECT_NE(a, b);  // the next frame draws new noise
  first.reset(9);
  first.render(TrunkPose{}, b);
  EXPECT_EQ(a, b);
}

TEST(StructuredLightImage, RejectsBadOptionsAndPoses) {
  StripeImageOptions options;
  options.ambient.illuminance_lux = -1.0;
  try {
    StructuredLightImageRenderer r(floor_scene(), small_ragno(), options);
    FAIL() << "no error";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("ambient.illuminance_lux"), std::string::npos) << e.what();
  }
  options = {};
  options.camera.sub_rows = 0;
  EXPECT_THROW(StructuredLightImageRenderer(floor_scene(), small_ragno(), options), InputError);
  StructuredLightImageRenderer renderer(floor_scene(), small_ragno());
  AmbientLight light;
  light.diffuse_fraction = 2.0;
  EXPECT_THROW(renderer.set_ambient(light), InputError);
  TrunkPose pose;
  pose.x_m = std::numeric_limits<double>::infinity();
  std::vector<std::uint8_t> rgb;
  EXPECT_THROW(renderer.render(pose, rgb), InputError);
}

}  // namespace
}  // namespace structured_light_image_test
}  // namespace stridemap

namespace stridemap {
namespace structured_light_image_test {
namespace {

// A white box on the grey floor, where metering on the mean clips the box
// top: highlight metering lowers the gain until the brightest 1 % of the
// ambient image is at its limit, and leaves a scene without highlights alone.
TEST(StructuredLightImage, HighlightMeteringKeepsAWhiteBoxBelowTheClip) {
  Scene scene = floor_scene();
  BoxObject box;
  box.name = "white";
  box.center_x_m = 0.45;
  box.length_m = 0.2;
  box.width_m = 0.3;
  box.height_m = 0.1;
  box.reflectance = 0.9;
  scene.boxes.push_back(box);
  StripeImageOptions mean_metering;
  mean_metering.ambient.illuminance_lux = 1000.0;
  mean_metering.camera.highlight_limit_dn = 0.0;
  StripeImageOptions highlight = mean_metering;
  highlight.camera.highlight_limit_dn = 220.0;
  std::vector<std::uint8_t> rgb;
  const StripeImageStats by_mean = StructuredLightImageRenderer(scene, small_ragno(), mean_metering).render({}, rgb);
  const StripeImageStats by_highlight = StructuredLightImageRenderer(scene, small_ragno(), highlight).render({}, rgb);
  EXPECT_LT(by_highlight.gain_dn_per_lux, 0.95 * by_mean.gain_dn_per_lux);
  EXPECT_LT(by_highlight.saturated_pixels, by_mean.saturated_pixels);

  const Scene grey = floor_scene();
  const StripeImageStats grey_mean = StructuredLightImageRenderer(grey, small_ragno(), mean_metering).render({}, rgb);
  const StripeImageStats grey_highlight = StructuredLightImageRenderer(grey, small_ragno(), highlight).render({}, rgb);
  EXPECT_DOUBLE_EQ(grey_highlight.gain_dn_per_lux, grey_mean.gain_dn_per_lux);

  StripeImageOptions bad = highlight;
  bad.camera.highlight_limit_dn = 300.0;
  EXPECT_THROW(StructuredLightImageRenderer(scene, small_ragno(), bad), InputError);
  bad = highlight;
  bad.camera.highlight_fraction = 0.0;
  EXPECT_THROW(StructuredLightImageRenderer(scene, small_ragno(), bad), InputError);
}

}  // namespace
}  // namespace structured_light_image_test
}  // namespace stridemap
