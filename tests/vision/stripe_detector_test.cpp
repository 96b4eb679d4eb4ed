#include "stridemap/vision/stripe_detector.hpp"

#include <cmath>
#include <functional>
#include <random>

#include <gtest/gtest.h>

#include "stridemap/core/error.hpp"
#include "stridemap/core/sensor_transform.hpp"
#include "stridemap/sim/structured_light_image.hpp"

namespace stridemap::io {
namespace {

// A grey image with a red line whose centre row is row_of(u) (NaN: none),
// Gaussian across rows, integrated over each pixel's height, plus noise.
RgbImage drawn_stripe(int width, int height, const std::function<double(double)>& row_of, double peak_dn = 120.0,
                      double sigma_px = 1.2, double noise_dn = 2.0, std::uint64_t seed = 3) {
  RgbImage image(width, height);
  std::mt19937_64 rng(seed);
  std::normal_distribution<double> noise(0.0, noise_dn);
  for (int x = 0; x < width; ++x) {
    const double centre = row_of(x + 0.5);
    for (int y = 0; y < height; ++y) {
      double laser = 0.0;
      if (std::isfinite(centre)) {
        const double a = (y - centre) / (std::sqrt(2.0) * sigma_px), b = (y + 1 - centre) / (std::sqrt(2.0) * sigma_px);
        laser = peak_dn * sigma_px * std::sqrt(std::numbers::pi / 2.0) * (std::erf(b) - std::erf(a));
      }
      const double base = 100.0;
      const double values[3] = {base + laser, base + 0.08 * laser, base + 0.04 * laser};
      for (int c = 0; c < 3; ++c) {
        image.rgb[image.offset(x, y) + c] =
            static_cast<std::uint8_t>(std::clamp(std::round(values[c] + noise(rng)), 0.0, 255.0));
      }
    }
  }
  return image;
}

TEST(StripeDetector, FindsASubPixelRowPerColumnAndNoneWhereTheStripeIsMissing) {
  const auto row_of = [](double u) { return u > 100 && u < 140 ? NAN : 60.3 + 0.07 * u; };
  const RgbImage image = drawn_stripe(320, 240, row_of);
  StripeDetector detector;
  StripeDetection detection;
  detector.detect(image, detection);
  ASSERT_EQ(detection.columns.size(), 320u);
  double sum_sq = 0.0;
  int found = 0;
  for (const StripeColumnDetection& c : detection.columns) {
    const double truth = row_of(c.u_px);
    if (!std::isfinite(truth)) {
      EXPECT_FALSE(c.found) << c.u_px;
      continue;
    }
    ASSERT_TRUE(c.found) << c.u_px;
    sum_sq += (c.v_px - truth) * (c.v_px - truth);
    ++found;
    EXPECT_GT(c.confidence, 0.9);
    EXPECT_EQ(c.runs, 1);
  }
  EXPECT_EQ(detection.found, static_cast<std::size_t>(found));
  EXPECT_LT(std::sqrt(sum_sq / found), 0.08);  // sub-pixel: far below the 0.29 px of whole rows
}

TEST(StripeDetector, RoundTripThroughTheSheetRecoversKnownPoints) {
  // Known points on Ragno's sheet, at depths that vary across the image:
  // projected, drawn, detected and back-projected.
  const StructuredLightModel model{StructuredLightParameters{}};
  std::vector<Eigen::Vector3d> truth(640);
  std::vector<double> rows(640);
  for (int i = 0; i < 640; ++i) {
    const double u = i + 0.5;
    const double depth = 0.16 + 0.07 * std::sin(u / 90.0);
    const double column_factor = 1.0 - 2.0 * u / 640.0;
    truth[i] = {depth * column_factor * model.tan_half_fov_horizontal(),
                depth * model.cot_sheet_angle() - model.parameters().baseline_m, depth};
    ASSERT_NEAR(model.distance_from_sheet_m(truth[i]), 0.0, 1e-12);
    rows[i] = (*model.project(truth[i]))[1];
  }
  const RgbImage image = drawn_stripe(640, 480, [&](double u) { return rows[static_cast<int>(u)]; });
  StripeDetector detector;
  StripeDetection detection;
  detector.detect(image, detection);
  ASSERT_EQ(detection.found, 640u);
  double worst_m = 0.0;
  for (int i = 0; i < 640; ++i) {
    Eigen::Vector3d point;
    const StripeColumnDetection& c = detection.columns[i];
    ASSERT_EQ(model.back_project(c.u_px, c.v_px, point), StripePointStatus::valid);
    worst_m = std::max(worst_m, (point - truth[i]).norm());
  }
  EXPECT_LT(worst_m, 0.0005);  // 0.5 mm at 9-23 cm
}

TEST(StripeDetector, RoundTripOnASimulatedImageMatchesTheSimulatorsTruth) {
  Scene scene;
  BoxObject box;
  box.name = "box";
  box.center_x_m = 0.25;
  box.center_y_m = -0.05;
  box.length_m = 0.1;
  box.width_m = 0.12;
  box.height_m = 0.05;
  box.reflectance = 0.7;
  scene.boxes.push_back(box);
  const StructuredLightParameters ragno;
  StructuredLightImageRenderer renderer(scene, ragno, {}, {}, 5);
  RgbImage image(640, 480);
  StructuredLightFrameTruth truth;
  renderer.render(TrunkPose{}, image.rgb, &truth);
  StripeDetector detector;
  StripeDetection detection;
  detector.detect(image, detection);
  std::size_t visible = 0, hits = 0, false_found = 0, wrong_run = 0;
  double sum_sq_px = 0.0, worst_mm = 0.0;
  for (int i = 0; i < 640; ++i) {
    const StripeColumnTruth& t = truth.columns[i];
    const StripeColumnDetection& d = detection.columns[i];
    if (t.label != StripeColumnLabel::visible) {
      false_found += d.found;
      continue;
    }
    ++visible;
    if (!d.found) continue;
    ++hits;
    if (std::abs(d.v_px - t.v_px) > 1.0) {
      // Beside an object's edge the lens blurs the object's stripe into the
      // next column: two runs, the wrong one may win, with low confidence.
      ++wrong_run;
      EXPECT_LT(d.confidence, 0.75) << i;
      EXPECT_EQ(d.runs, 2) << i;
      continue;
    }
    sum_sq_px += (d.v_px - t.v_px) * (d.v_px - t.v_px);
    Eigen::Vector3d point;
    ASSERT_EQ(renderer.model().back_project(d.u_px, d.v_px, point), StripePointStatus::valid);
    const Eigen::Vector3d in_map = sensor_point_to_map(camera_to_sensor_frame(point), TrunkPose{}, ragno.mount);
    worst_mm = std::max(worst_mm, 1000.0 * (in_map - t.point_m).norm());
  }
  ASSERT_GT(visible, 500u);
  EXPECT_GE(hits, visible - 6);  // a few columns at the box's edges may go
  EXPECT_LE(false_found, 4u);
  EXPECT_LE(wrong_run, 4u);
  EXPECT_LT(std::sqrt(sum_sq_px / (hits - wrong_run)), 0.35);
  EXPECT_LT(worst_mm, 6.0);
}

TEST(StripeDetector, CleansSpecklesAndRejectsRedObjects) {
  RgbImage image(200, 150, 100, 100, 100);
  const auto paint = [&](int x0, int y0, int w, int h) {
    for (int y = y0; y < y0 + h; ++y)
      for (int x = x0; x < x0 + w; ++x) image.rgb[image.offset(x, y)] = 230;
  };
  paint(10, 30, 1, 1);    // single pixels and small blobs: noise
  paint(20, 80, 2, 2);
  paint(40, 50, 1, 6);    // a hairline, smaller than the area opening's limit
  paint(100, 20, 40, 60); // a red object: far taller than a stripe
  paint(150, 100, 40, 2); // the stripe
  StripeDetector detector;
  StripeDetection detection;
  detector.detect(image, detection);
  EXPECT_GT(detection.candidate_pixels, detection.cleaned_pixels);
  for (int x : {10, 20, 21, 40}) EXPECT_FALSE(detection.columns[x].found) << x;
  for (int x = 100; x < 140; ++x) EXPECT_FALSE(detection.columns[x].found) << x;
  EXPECT_EQ(detection.rejected_tall_runs, 40u);
  for (int x = 150; x < 190; ++x) {
    ASSERT_TRUE(detection.columns[x].found) << x;
    EXPECT_NEAR(detection.columns[x].v_px, 101.0, 1e-9);
  }
  EXPECT_EQ(detection.found, 40u);

  // The square opening alone (no area opening) removes blobs thinner than
  // itself, the 2-row stripe included; the red object stays (as tall runs).
  StripeDetectorOptions opening_only;
  opening_only.opening_size_px = 3;
  opening_only.min_component_px = 0;
  StripeDetector(opening_only).detect(image, detection);
  EXPECT_FALSE(detection.columns[20].found);
  EXPECT_FALSE(detection.columns[150].found);
  EXPECT_EQ(detection.rejected_tall_runs, 40u);
}

TEST(StripeDetector, StrongerOfTwoRunsWinsWithLowerConfidence) {
  RgbImage image(60, 100, 90, 90, 90);
  for (int x = 0; x < 60; ++x) {
    for (int y : {30, 31}) image.rgb[image.offset(x, y)] = 250;  // the stripe
    if (x >= 20 && x < 40) image.rgb[image.offset(x, 70)] = 160;  // a weaker reflection
  }
  StripeDetector detector;
  StripeDetection detection;
  detector.detect(image, detection);
  EXPECT_NEAR(detection.columns[30].v_px, 31.0, 1e-9);
  EXPECT_EQ(detection.columns[30].runs, 2);
  EXPECT_LT(detection.columns[30].confidence, 0.9);
  EXPECT_DOUBLE_EQ(detection.columns[5].confidence, 1.0);
  std::vector<StripePixel> confident;
  detection.pixels(confident, 0.9);
  EXPECT_EQ(confident.size(), 40u);
}

TEST(StripeDetector, OverlayMarksTheStripe) {
  const RgbImage image = drawn_stripe(120, 90, [](double u) { return u < 60 ? 40.5 : NAN; });
  StripeDetector detector;
  StripeDetection detection;
  detector.detect(image, detection);
  const RgbImage overlay = stripe_overlay(image, detection);
  ASSERT_EQ(overlay.rgb.size(), image.rgb.size());
  const std::size_t dot = overlay.offset(30, 40);
  EXPECT_EQ(overlay.rgb[dot + 1], 255);
  EXPECT_EQ(overlay.rgb[dot], 0);
  const std::size_t tick = overlay.offset(90, 89);  // no stripe: magenta tick
  EXPECT_EQ(overlay.rgb[tick], 255);
  EXPECT_EQ(overlay.rgb[tick + 1], 0);
}

TEST(StripeDetector, RejectsBadImagesAndOptions) {
  StripeDetector detector;
  StripeDetection detection;
  EXPECT_THROW(detector.detect(RgbImage{}, detection), InputError);
  RgbImage short_buffer(10, 10);
  short_buffer.rgb.resize(200);
  try {
    detector.detect(short_buffer, detection);
    FAIL() << "no error";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("300"), std::string::npos) << e.what();
  }
  StripeDetectorOptions options;
  options.min_red_excess_dn = 0;
  EXPECT_THROW(StripeDetector{options}, InputError);
  options = {};
  options.opening_size_px = 0;
  EXPECT_THROW(StripeDetector{options}, InputError);
  options.opening_size_px = 2;
  EXPECT_THROW(StripeDetector{options}, InputError);
  const RgbImage image(20, 10);
  detector.detect(image, detection);
  EXPECT_THROW(stripe_overlay(RgbImage(21, 10), detection), InputError);
}

}  // namespace
}  // namespace stridemap::io
