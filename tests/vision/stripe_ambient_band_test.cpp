// A white surface lit only by ambient light, clipped in a thin band (the top
// of a tall white box seen from afar, between the darker floor behind it and
// its shaded front face): the detector's saturated-core rule must not take
// it for the laser (phantom ridges under ambient light).
#include <algorithm>
#include <cmath>
#include <random>

#include <gtest/gtest.h>

#include "stridemap/core/error.hpp"
#include "stridemap/vision/stripe_detector.hpp"

namespace stridemap::io {
namespace {

constexpr int kWidth = 80, kHeight = 100, kBandTop = 40, kBandRows = 5;

// Grey `above` over rows [0, kBandTop), a band of `band` (per channel, before
// the clip) over kBandRows rows, grey `below` under it, and the laser's
// `flank` red excess added to red in the row right above the band. Noise as
// the sensor's: shot noise of 8 electrons per DN, read noise 1 DN.
RgbImage band_image(double above, double band, double below, double flank = 0.0, std::uint64_t seed = 11) {
  RgbImage image(kWidth, kHeight);
  std::mt19937_64 rng(seed);
  std::normal_distribution<double> gaussian(0.0, 1.0);
  for (int y = 0; y < kHeight; ++y) {
    const double level = y < kBandTop ? above : y < kBandTop + kBandRows ? band : below;
    for (int x = 0; x < kWidth; ++x) {
      for (int c = 0; c < 3; ++c) {
        const double signal = level + (c == 0 && y == kBandTop - 1 ? flank : 0.0);
        const double dn = signal + std::sqrt(signal / 8.0) * gaussian(rng) + gaussian(rng);
        image.rgb[image.offset(x, y) + c] = static_cast<std::uint8_t>(std::clamp(std::round(dn), 0.0, 255.0));
      }
    }
  }
  return image;
}

std::size_t found_in_band(const StripeDetection& detection) {
  std::size_t n = 0;
  for (const StripeColumnDetection& c : detection.columns) {
    n += c.found && c.v_px > kBandTop - 3 && c.v_px < kBandTop + kBandRows + 3;
  }
  return n;
}

TEST(StripeAmbientBand, AClippedWhiteBandWithGreyFlanksIsNoStripe) {
  // The simulated scene's levels at 1000 lux: floor 110 DN, box top 440
  // (clipped), shaded front face 220.
  const RgbImage image = band_image(110.0, 440.0, 220.0);
  StripeDetection detection;
  StripeDetector().detect(image, detection);
  EXPECT_EQ(found_in_band(detection), 0u);
  EXPECT_EQ(detection.saturated_core_pixels, 0u);

  // Without the halo test the band passes the saturated-core rule: the
  // false stripe behind the phantom ridge.
  StripeDetectorOptions no_halo;
  no_halo.saturation_halo_dn = 0;
  StripeDetector(no_halo).detect(image, detection);
  EXPECT_GE(found_in_band(detection), 70u);
}

TEST(StripeAmbientBand, TheSameBandWithTheLasersRedFlankIsAStripe) {
  // A clipped laser core on the same surfaces: its profile leaves red above
  // the leak in the next row.
  const RgbImage image = band_image(110.0, 440.0, 220.0, 40.0);
  StripeDetection detection;
  StripeDetector().detect(image, detection);
  EXPECT_GE(found_in_band(detection), 76u);
  EXPECT_GT(detection.saturated_core_pixels, 0u);
}

TEST(StripeAmbientBand, HaloOptionIsChecked) {
  for (const int bad : {-1, 256}) {
    StripeDetectorOptions o;
    o.saturation_halo_dn = bad;
    try {
      StripeDetector detector(o);
      ADD_FAILURE() << "no InputError for " << bad;
    } catch (const InputError& e) {
      EXPECT_NE(std::string(e.what()).find("saturation_halo_dn"), std::string::npos) << e.what();
    }
  }
}

}  // namespace
}  // namespace stridemap::io
