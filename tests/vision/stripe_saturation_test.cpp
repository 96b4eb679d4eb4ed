// The detector on stripes that clip the sensor (a white core on a bright
// surface) and on dim stripes over dark surfaces: the two cases where one
// fixed red-excess threshold loses the stripe (white objects under
// structured light).
#include <algorithm>
#include <array>
#include <cmath>
#include <random>

#include <gtest/gtest.h>

#include "stridemap/core/error.hpp"
#include "stridemap/vision/stripe_detector.hpp"

namespace stridemap::io {
namespace {

// A surface of `level` DN in all channels with a horizontal band of rows
// [core_top, core_top + core_rows) of signal `core`, and one halo row above
// and below of signal `halo`; Gaussian noise of noise_dn on every channel,
// then the 8-bit clip, as a sensor does (a signal far above 255 reads 255
// whatever its noise).
struct Band {
  int level = 230;
  int core_top = 40;
  int core_rows = 5;
  std::array<int, 3> core{900, 284, 257};  // the laser's red and its leak into green and blue
  std::array<int, 3> halo{300, 236, 234};
  double noise_dn = 3.0;
};

RgbImage banded_image(const Band& band, int width = 80, int height = 100, std::uint64_t seed = 5) {
  RgbImage image(width, height);
  std::mt19937_64 rng(seed);
  std::normal_distribution<double> noise(0.0, band.noise_dn);
  for (int y = 0; y < height; ++y) {
    const bool in_core = y >= band.core_top && y < band.core_top + band.core_rows;
    const bool in_halo = y == band.core_top - 1 || y == band.core_top + band.core_rows;
    for (int x = 0; x < width; ++x) {
      for (int c = 0; c < 3; ++c) {
        const int value = in_core ? band.core[c] : in_halo ? band.halo[c] : band.level;
        image.rgb[image.offset(x, y) + c] =
            static_cast<std::uint8_t>(std::clamp(std::round(value + noise(rng)), 0.0, 255.0));
      }
    }
  }
  return image;
}

std::size_t found_near(const StripeDetection& detection, double row, double tolerance_px) {
  std::size_t n = 0;
  for (const StripeColumnDetection& c : detection.columns) n += c.found && std::abs(c.v_px - row) <= tolerance_px;
  return n;
}

TEST(StripeSaturation, AWhiteCoreWithAFaintHaloIsFoundAtItsCentre) {
  const Band band;  // core rows 40..44: centre 42.5
  const RgbImage image = banded_image(band);
  StripeDetector detector;
  StripeDetection detection;
  detector.detect(image, detection);
  EXPECT_GE(found_near(detection, 42.5, 0.5), 76u);
  EXPECT_GT(detection.saturated_core_pixels, 0u);
  EXPECT_TRUE(detection.columns[40].saturated);

  // Without the saturation rule nothing in it is red enough.
  StripeDetectorOptions no_rule;
  no_rule.saturation_dn = 256;
  StripeDetector(no_rule).detect(image, detection);
  EXPECT_LE(found_near(detection, 42.5, 0.5), 4u);
  EXPECT_EQ(detection.saturated_core_pixels, 0u);
}

TEST(StripeSaturation, ClippedSurfacesAndSpecksAreNotStripes) {
  StripeDetector detector;
  StripeDetection detection;
  // A white object clipped whole: far taller than a core.
  Band tall;
  tall.core_rows = 40;
  detector.detect(banded_image(tall), detection);
  EXPECT_EQ(found_near(detection, 40.0 + 20.0, 30.0), 0u);
  // A lit white surface whose noise clips here and there: its surround is
  // itself at the clip level, so it is no evidence of the laser.
  Band glare;
  glare.level = 249;
  glare.core = {249, 249, 249};
  glare.halo = {249, 249, 249};
  glare.noise_dn = 4.0;
  detector.detect(banded_image(glare), detection);
  EXPECT_EQ(detection.found, 0u);
  // A grey surface with noise only.
  Band plain;
  plain.level = 200;
  plain.core = {200, 200, 200};
  plain.halo = {200, 200, 200};
  detector.detect(banded_image(plain), detection);
  EXPECT_EQ(detection.found, 0u);
}

TEST(StripeSaturation, ADimStripeOnADarkSurfaceClearsTheShotNoiseThreshold) {
  // 0.1-reflectance box under bright light: background 45 DN, the stripe
  // 22 DN of red excess at its peak, below the full-scale threshold of 30.
  Band dark;
  dark.level = 45;
  dark.core_top = 50;
  dark.core_rows = 2;
  dark.core = {67, 47, 45};
  dark.halo = {56, 46, 45};
  dark.noise_dn = 2.0;
  const RgbImage image = banded_image(dark);
  StripeDetector detector;
  StripeDetection detection;
  detector.detect(image, detection);
  EXPECT_GE(found_near(detection, 51.0, 0.6), 76u);
  EXPECT_EQ(detection.saturated_core_pixels, 0u);

  StripeDetectorOptions fixed;
  fixed.threshold_follows_shot_noise = false;
  StripeDetector(fixed).detect(image, detection);
  EXPECT_EQ(detection.found, 0u);
}

TEST(StripeSaturation, BadOptionsNameTheField) {
  const auto message = [](const StripeDetectorOptions& options) {
    try {
      StripeDetector detector(options);
    } catch (const InputError& e) {
      return std::string(e.what());
    }
    return std::string("no error");
  };
  StripeDetectorOptions o;
  o.min_red_excess_floor_dn = 31;
  EXPECT_NE(message(o).find("min_red_excess_floor_dn"), std::string::npos) << message(o);
  o = {};
  o.saturation_dn = 0;
  EXPECT_NE(message(o).find("saturation_dn"), std::string::npos) << message(o);
  o = {};
  o.max_saturated_core_px = 1;
  EXPECT_NE(message(o).find("max_saturated_core_px"), std::string::npos) << message(o);
  o = {};
  o.saturation_contrast_dn = 0;
  EXPECT_NE(message(o).find("saturation_contrast_dn"), std::string::npos) << message(o);
}

}  // namespace
}  // namespace stridemap::io
