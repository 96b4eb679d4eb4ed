// Where the detector puts the stripe in a column when the surface under it
// changes: a brightness step across the stripe, a bright surface on which
// the laser's red clips while green and blue do not, and a white object
// clipped at the image's edge right beside the stripe. Each once moved the
// stripe by two rows or more on the structured-light rail's random scenes.
#include <algorithm>
#include <cmath>
#include <functional>
#include <random>
#include <vector>

#include <gtest/gtest.h>

#include "stridemap/vision/stripe_detector.hpp"

namespace stridemap::io {
namespace {

// A column profile repeated across the image: the ambient signal of each
// row (a grey surface: the same in the three channels) plus a red laser line
// of Gaussian profile, with its leak into green and blue; noise, then the
// sensor's 8-bit clip.
struct Column {
  std::function<double(int)> ambient_dn;
  double laser_centre_px = 40.0;  ///< continuous row: row k spans [k, k + 1)
  double laser_peak_dn = 40.0;
  double laser_sigma_px = 1.2;
  double green_leak = 0.08;
  double blue_leak = 0.04;
};

RgbImage column_image(const Column& column, int width = 60, int height = 80, std::uint64_t seed = 11) {
  RgbImage image(width, height);
  std::mt19937_64 rng(seed);
  std::normal_distribution<double> noise(0.0, 2.0);
  for (int y = 0; y < height; ++y) {
    const double offset = (y + 0.5 - column.laser_centre_px) / column.laser_sigma_px;
    const double laser = column.laser_peak_dn * std::exp(-0.5 * offset * offset);
    const double leaks[3] = {1.0, column.green_leak, column.blue_leak};
    for (int x = 0; x < width; ++x) {
      for (int c = 0; c < 3; ++c) {
        const double value = column.ambient_dn(y) + leaks[c] * laser + noise(rng);
        image.rgb[image.offset(x, y) + c] = static_cast<std::uint8_t>(std::clamp(std::round(value), 0.0, 255.0));
      }
    }
  }
  return image;
}

// The largest |row error| over the columns where the stripe is found, and
// how many they are.
struct RowErrors {
  double worst_px = 0.0;
  int found = 0;
};

RowErrors row_errors(const RgbImage& image, double true_row_px) {
  StripeDetector detector;
  StripeDetection detection;
  detector.detect(image, detection);
  RowErrors out;
  for (const StripeColumnDetection& c : detection.columns) {
    if (!c.found) continue;
    ++out.found;
    out.worst_px = std::max(out.worst_px, std::abs(c.v_px - true_row_px));
  }
  return out;
}

TEST(StripeCentroid, AStripeAcrossABrightnessStepIsFoundAtItsPeak) {
  // A dark floor above row 42, a light box top from it on: the stripe's
  // lower flank lies on the bright side.
  Column column;
  column.ambient_dn = [](int y) { return y < 42 ? 30.0 : 150.0; };
  column.laser_centre_px = 41.4;
  column.laser_peak_dn = 35.0;
  const RowErrors errors = row_errors(column_image(column), column.laser_centre_px);
  EXPECT_EQ(errors.found, 60);
  EXPECT_LT(errors.worst_px, 0.6);
}

TEST(StripeCentroid, AStripeWhoseRedClipsOnAWhiteSurfaceIsFoundAtItsCore) {
  // Red clips in the core while green and blue, lifted only by the leak,
  // stay below it: the core's red excess falls under the threshold and
  // only a flank row, where red has not clipped yet, reaches it (in the
  // columns where noise lifts one that far: not in all).
  Column column;
  column.ambient_dn = [](int) { return 222.0; };
  column.laser_centre_px = 40.0;
  column.laser_peak_dn = 150.0;
  column.laser_sigma_px = 1.5;
  const RowErrors errors = row_errors(column_image(column), column.laser_centre_px);
  EXPECT_GE(errors.found, 10);
  EXPECT_LT(errors.worst_px, 0.6);
}

TEST(StripeCentroid, AWhiteObjectClippedAtTheImagesEdgeBesideTheStripeIsNoCore) {
  // The last five rows: a white object under bright light, clipped in
  // every channel; the stripe on the dark floor just above it.
  const int height = 80;
  Column column;
  column.ambient_dn = [](int y) { return y >= 75 ? 400.0 : 30.0; };
  column.laser_centre_px = 72.5;
  column.laser_peak_dn = 30.0;
  const RowErrors errors = row_errors(column_image(column, 60, height), column.laser_centre_px);
  EXPECT_EQ(errors.found, 60);
  EXPECT_LT(errors.worst_px, 0.6);
}

}  // namespace
}  // namespace stridemap::io
