// Camera frames as PNG bytes into the stripe detector (vision/stripe_detector.hpp)
// and on to map points with a structured-light configuration (Ragno's, as
// configs/ragno_structured_light.yaml, its image size set to the frame's).
// What must hold:
//  - read_stripe_image refuses exactly the grey frames and the frames of
//    another size than the configuration's, naming the file;
//  - the detection has one column per image column, its counts agree with
//    its columns, every found row lies inside the image and is finite, and
//    every confidence is in [0, 1];
//  - every detected pixel becomes a finite map point or is counted as a ray
//    that misses the sheet (never "not finite" nor "outside the image");
//  - the overlay is an image of the same size.
#include <cmath>
#include <optional>
#include <string>
#include <vector>

#include "fuzz_target.hpp"
#include "stridemap/config/structured_light_config.hpp"
#include "stridemap/core/error.hpp"
#include "stridemap/render/png_image.hpp"
#include "stridemap/sensors/structured_light_mapping.hpp"
#include "stridemap/vision/stripe_detector.hpp"

namespace stripe_detector_fuzz {
namespace {

using namespace stridemap;
using fuzz::check;

const std::string kName = "fuzz.png";

const char* const kConfig = R"(structured_light:
  baseline_m: 0.120
  sheet_angle_deg: 45.0
  image_width_px: 64
  image_height_px: 48
  half_fov_vertical_deg: 28.14
  half_fov_horizontal_deg: 38.8
mount:
  pitch_deg: 10.0
  height_m: 0.174
)";

bool refused(std::span<const std::uint8_t> bytes, int width, int height) {
  try {
    (void)io::read_stripe_image(bytes, kName, width, height);
  } catch (const InputError& e) {
    check(std::string(e.what()).find(kName) != std::string::npos, std::string("an error that does not name the file: ") + e.what());
    return true;
  }
  return false;
}

void check_detection(const io::RgbImage& image, const io::StripeDetection& d) {
  check(d.width == image.width && d.height == image.height, "a detection of another size");
  check(d.columns.size() == static_cast<std::size_t>(image.width), "not one column per image column");
  const std::size_t pixels = static_cast<std::size_t>(image.width) * static_cast<std::size_t>(image.height);
  check(d.candidate_pixels <= pixels && d.cleaned_pixels <= pixels, "more candidate pixels than the image has");
  std::size_t found = 0;
  for (std::size_t x = 0; x < d.columns.size(); ++x) {
    const io::StripeColumnDetection& c = d.columns[x];
    check(c.u_px == static_cast<double>(x) + 0.5, "a column's u is not its centre");
    check(c.runs >= 0 && c.runs <= image.height, "a column with more runs than rows");
    if (!c.found) continue;
    ++found;
    check(c.runs >= 1, "a stripe found in a column without a run");
    check(std::isfinite(c.v_px) && c.v_px >= 0.0 && c.v_px <= image.height, "a stripe row outside the image");
    check(c.confidence >= 0.0 && c.confidence <= 1.0, "a confidence outside [0, 1]");
  }
  check(found == d.found, "found = " + std::to_string(d.found) + ", but " + std::to_string(found) + " columns say so");
  check(d.found + d.rejected_tall_runs <= d.columns.size(), "more columns found or rejected than there are");
}

}  // namespace

STRIDEMAP_FUZZ_TARGET(stripe_detector) {
  static const StructuredLightConfig config = parse_structured_light_config(kConfig, "fuzz_config.yaml");
  io::PngSourceFormat format;
  io::RgbImage image;
  try {
    image = io::read_png(data, kName, format);
  } catch (const InputError& e) {
    check(std::string(e.what()).find(kName) != std::string::npos, std::string("an error that does not name the file: ") + e.what());
    check(refused(data, config.parameters.image_width_px, config.parameters.image_height_px),
          "read_stripe_image accepts what read_png refuses");
    return;
  }
  const int w = config.parameters.image_width_px, h = config.parameters.image_height_px;
  check(refused(data, w, h) == (!format.has_colour || image.width != w || image.height != h),
        "read_stripe_image refuses a frame it should take, or takes one it should refuse");
  check(refused(data, image.width, image.height) == !format.has_colour, "the size check refuses the frame's own size");
  // Large frames take the fuzzer's time, not the detector's bugs.
  if (static_cast<long long>(image.width) * image.height > (1 << 18)) return;

  io::StripeDetectorOptions tight;
  tight.opening_size_px = 3;
  tight.closing_height_px = 1;
  tight.min_component_px = 0;
  tight.max_stripe_height_px = 3;
  tight.centroid_margin_px = 4;
  StructuredLightParameters parameters = config.parameters;
  parameters.image_width_px = image.width;
  parameters.image_height_px = image.height;
  std::optional<StructuredLightModel> model;
  try {
    model.emplace(parameters);
  } catch (const InputError&) {
    // A frame size the camera model refuses (one pixel wide...): detect only.
  }
  for (const io::StripeDetectorOptions& options : {io::StripeDetectorOptions{}, tight}) {
    io::StripeDetector detector(options);
    io::StripeDetection detection;
    detector.detect(image, detection);
    check_detection(image, detection);
    const io::RgbImage overlay = io::stripe_overlay(image, detection);
    check(overlay.width == image.width && overlay.height == image.height && overlay.rgb.size() == image.rgb.size(),
          "an overlay of another size");
    if (!model) continue;
    std::vector<StripePixel> pixels;
    detection.pixels(pixels);
    std::vector<MapPoint> points;
    const StripeConversionStats stats =
        stripe_to_map_points(*model, pixels, TrunkPose{}, ScanMotion{}, UpdateOptions{}, points);
    check(stats.pixels == pixels.size() && stats.converted == points.size() &&
              stats.converted + stats.not_finite + stats.outside_image + stats.no_intersection == stats.pixels,
          "the conversion loses pixels without counting them");
    check(stats.not_finite == 0 && stats.outside_image == 0, "a detected pixel that is not finite or not in the image");
    for (const MapPoint& p : points) {
      check(std::isfinite(p.x_m) && std::isfinite(p.y_m) && std::isfinite(p.elevation_m) &&
                std::isfinite(p.max_elevation_change_m) && p.max_elevation_change_m >= 0.0,
            "a map point that is not finite");
    }
  }
}

}  // namespace stripe_detector_fuzz
