// Camera frames the stripe detector must cope with (docs/reliability.md):
// the wrong size or no colour (refused, naming the frame), and frames it
// takes but that are hard: dark, saturated by the laser, without a stripe,
// with the stripe on the top or bottom row.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <fstream>
#include <functional>
#include <iterator>
#include <string>
#include <vector>

#include "live/test_folder.hpp"
#include "stridemap/core/error.hpp"
#include "stridemap/vision/stripe_detector.hpp"
#include "test_paths.hpp"

namespace stridemap::io {
namespace {

// Grey 90 with a red line along `centre(u)`; `laser_dn` at its centre, so
// that above ~400 DN the core saturates to white (no red excess left).
RgbImage frame(int width, int height, const std::function<double(double)>& centre, double laser_dn) {
  RgbImage image(width, height, 90, 90, 90);
  for (int x = 0; x < width; ++x) {
    const double c = centre(x + 0.5);
    for (int y = 0; y < height && std::isfinite(c); ++y) {
      const double d = y + 0.5 - c;
      const double laser = laser_dn * std::exp(-d * d / (2.0 * 1.5 * 1.5));
      const double rgb[3] = {90 + laser, 90 + 0.4 * laser, 90 + 0.3 * laser};
      for (int k = 0; k < 3; ++k) image.rgb[image.offset(x, y) + k] = static_cast<std::uint8_t>(std::min(255.0, rgb[k]));
    }
  }
  return image;
}

std::vector<std::uint8_t> png_bytes(const test::TestFolder& dir, const RgbImage& image) {
  write_png(dir / "frame.png", image);
  const std::string text = dir.read("frame.png");
  return {text.begin(), text.end()};
}

std::string refusal(const std::vector<std::uint8_t>& bytes, int width, int height) {
  try {
    read_stripe_image(bytes, "cam0/frame_17.png", width, height);
  } catch (const InputError& e) {
    return e.what();
  }
  return "no error";
}

TEST(StripeFrames, WrongSizeAndGreyFramesAreRefusedNamingTheFrame) {
  test::TestFolder dir;
  const std::vector<std::uint8_t> colour = png_bytes(dir, frame(64, 48, [](double) { return 20.0; }, 150));
  EXPECT_EQ(refusal(colour, 64, 48), "no error");
  EXPECT_EQ(refusal(colour, 640, 480),
            "cam0/frame_17.png: the image is 64 x 48 pixels, the configuration describes a 640 x 480 image region "
            "(image_width_px, image_height_px)");
  // A grey PNG (colour type 0), as a monochrome camera sends; write_png only
  // writes RGB, so the fuzz seed made for this serves.
  const std::string corpus = std::string(STRIDEMAP_SOURCE_DIR) + "/fuzz/corpus/stripe_detector/grey_64x48.png";
  std::ifstream in(corpus, std::ios::binary);
  const std::vector<std::uint8_t> grey_bytes{std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
  ASSERT_FALSE(grey_bytes.empty()) << corpus;
  EXPECT_NE(refusal(grey_bytes, 64, 48).find("cam0/frame_17.png: a grey PNG has no colour"), std::string::npos)
      << refusal(grey_bytes, 64, 48);
  EXPECT_NE(refusal({0x89, 'P', 'N', 'G'}, 64, 48).find("cam0/frame_17.png"), std::string::npos);
}

TEST(StripeFrames, DarkFrameAndFrameWithoutStripeFindNothingAndSayNothingWrong) {
  StripeDetector detector;
  StripeDetection d;
  detector.detect(RgbImage(64, 48, 3, 3, 3), d);
  EXPECT_EQ(d.found, 0u);
  EXPECT_EQ(d.candidate_pixels, 0u);
  detector.detect(frame(64, 48, [](double) { return NAN; }, 0), d);
  EXPECT_EQ(d.found, 0u);
  ASSERT_EQ(d.columns.size(), 64u);
  for (const StripeColumnDetection& c : d.columns) EXPECT_FALSE(c.found);
}

TEST(StripeFrames, SaturatedStripeIsFoundAtItsCentre) {
  StripeDetector detector;
  StripeDetection d;
  const RgbImage image = frame(64, 48, [](double u) { return 18.0 + 0.1 * u; }, 700);
  // The core is white: no red excess there, only in the fringes.
  EXPECT_EQ(image.rgb[image.offset(10, 19)], 255);
  EXPECT_EQ(image.rgb[image.offset(10, 19) + 1], 255);
  detector.detect(image, d);
  EXPECT_EQ(d.found, 64u);
  for (const StripeColumnDetection& c : d.columns) EXPECT_NEAR(c.v_px, 18.0 + 0.1 * c.u_px, 0.5) << "u " << c.u_px;
}

TEST(StripeFrames, StripeOnTheTopOrBottomRowIsFoundInsideTheImage) {
  StripeDetector detector;
  StripeDetection d;
  for (const double centre : {0.6, 47.4}) {
    detector.detect(frame(64, 48, [&](double) { return centre; }, 200), d);
    EXPECT_EQ(d.found, 64u) << "stripe at row " << centre;
    for (const StripeColumnDetection& c : d.columns) {
      EXPECT_GE(c.v_px, 0.0);
      EXPECT_LE(c.v_px, 48.0);
      EXPECT_NEAR(c.v_px, centre, 1.0);  // half the stripe is cut off: the centroid moves inwards
    }
  }
}

}  // namespace
}  // namespace stridemap::io
