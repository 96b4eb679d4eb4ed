#include "stridemap/vision/stripe_detector.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>
#include <opencv2/imgproc.hpp>
#include <string>

#include "stridemap/core/error.hpp"

namespace stridemap::io {
namespace {

void require(bool ok, const char* field, const std::string& problem) {
  if (!ok) throw InputError(std::string("stripe detector options: ") + field + ": " + problem);
}

void check_image(const RgbImage& image) {
  const std::string size = std::to_string(image.width) + " x " + std::to_string(image.height);
  if (image.width <= 0 || image.height <= 0) throw InputError("stripe detector: the image is empty (" + size + " pixels)");
  const std::size_t expected = 3 * static_cast<std::size_t>(image.width) * static_cast<std::size_t>(image.height);
  if (image.rgb.size() != expected) {
    throw InputError("stripe detector: the pixel buffer holds " + std::to_string(image.rgb.size()) + " bytes, a " + size +
                     " RGB image needs " + std::to_string(expected));
  }
}

struct Run {
  int top = 0, bottom = 0;  // inclusive rows
  long excess_sum = 0;
  int peak = 0;
  bool saturated = false;
};

// Shot noise grows with the square root of the signal, so a threshold that
// keeps the same number of standard deviations does too.
std::vector<int> excess_thresholds(const StripeDetectorOptions& o) {
  std::vector<int> threshold(256, o.min_red_excess_dn);
  if (!o.threshold_follows_shot_noise) return threshold;
  for (int level = 0; level < 256; ++level) {
    const double scaled = o.min_red_excess_dn * std::sqrt(static_cast<double>(level) / 255.0);
    threshold[static_cast<std::size_t>(level)] = std::max(o.min_red_excess_floor_dn, static_cast<int>(std::ceil(scaled)));
  }
  return threshold;
}

// Mean of max(G, B) over rows [from, to] of a column; NaN-free: -1 when the
// range is empty (outside the image).
double mean_green_blue(const RgbImage& image, int x, int from, int to) {
  from = std::max(from, 0);
  to = std::min(to, image.height - 1);
  if (from > to) return -1.0;
  double sum = 0.0;
  for (int y = from; y <= to; ++y) {
    const std::size_t i = image.offset(x, y);
    sum += std::max(image.rgb[i + 1], image.rgb[i + 2]);
  }
  return sum / (to - from + 1);
}

int red_excess(const RgbImage& image, int x, int y) {
  const std::size_t i = image.offset(x, y);
  return static_cast<int>(image.rgb[i]) - std::max(image.rgb[i + 1], image.rgb[i + 2]);
}

// The red excess at the edges of a clipped run: per side, the largest over
// the run's two outer rows and the two rows beyond (a laser's flank may clip
// red but not green and blue, and so lie inside the run), averaged over the
// column and its neighbours (the stripe runs across columns, the noise does
// not); the stronger side. A side outside the image counts as -255.
double halo_red_excess(const RgbImage& image, int x, int top, int bottom) {
  double strongest = -255.0;
  for (const int step : {-1, 1}) {
    const int first = step < 0 ? top + 1 : bottom - 1;
    double sum = 0.0;
    int columns = 0;
    for (int c = std::max(0, x - 1); c <= std::min(image.width - 1, x + 1); ++c) {
      int best = -255;
      for (int y = first; y != first + 4 * step; y += step) {
        if (y >= 0 && y < image.height) best = std::max(best, red_excess(image, c, y));
      }
      sum += best;
      ++columns;
    }
    strongest = std::max(strongest, sum / columns);
  }
  return strongest;
}

// Marks the saturated stripe cores (header, step 1b) in `mask`, with a
// strength in `strength` on the colour rule's scale; returns how many pixels
// it added.
std::size_t mark_saturated_cores(const RgbImage& image, const StripeDetectorOptions& o, cv::Mat& strength,
                                 cv::Mat& mask, cv::Mat& core) {
  core.create(image.height, image.width, CV_8UC1);
  core.setTo(0);
  constexpr int kSurroundRows = 3;
  std::size_t added = 0;
  for (int x = 0; x < image.width; ++x) {
    int y = 0;
    while (y < image.height) {
      if (image.rgb[image.offset(x, y)] < o.saturation_dn) {
        ++y;
        continue;
      }
      const int top = y;
      while (y < image.height && image.rgb[image.offset(x, y)] >= o.saturation_dn) ++y;
      const int bottom = y - 1;
      const int rows = bottom - top + 1;
      if (rows < 2 || rows > o.max_saturated_core_px) continue;
      // A run at the image's edge may go on beyond it: its height is not
      // known, nor what lies past it, and a white object clipped at the
      // bottom edge beside the stripe would pass the one side's tests.
      if (top == 0 || bottom == image.height - 1) continue;
      const double above = mean_green_blue(image, x, top - kSurroundRows, top - 1);
      const double below = mean_green_blue(image, x, bottom + 1, bottom + kSurroundRows);
      // A surround that is itself near the clip level may be a lit white
      // surface whose noise clips: no evidence of the laser there.
      const double surround = std::max(above, below);
      if (surround > o.saturation_dn - o.saturation_contrast_dn) continue;
      const double contrast = mean_green_blue(image, x, top, bottom) - surround;
      if (contrast < o.saturation_contrast_dn) continue;
      // The laser's profile falls off through the rows beside its clipped
      // core, where red still outruns its leak into green and blue; an
      // ambient-lit white band (a box top seen edge-on) clips the same way
      // but is grey beside it.
      if (o.saturation_halo_dn > 0 && halo_red_excess(image, x, top, bottom) < o.saturation_halo_dn) continue;
      const int scaled = static_cast<int>(std::lround(contrast * o.min_red_excess_dn / o.saturation_contrast_dn));
      for (int r = top; r <= bottom; ++r) {
        auto& m = mask.at<std::uint8_t>(r, x);
        auto& s = strength.at<std::int16_t>(r, x);
        s = static_cast<std::int16_t>(std::max<int>(s, std::min(scaled, 255)));
        added += m == 0;
        m = 255;
        core.at<std::uint8_t>(r, x) = 1;
      }
    }
  }
  return added;
}

}  // namespace

void StripeDetectorOptions::validate() const {
  require(min_red_excess_dn >= 1 && min_red_excess_dn <= 255, "min_red_excess_dn",
          "must be from 1 to 255, got " + std::to_string(min_red_excess_dn));
  require(min_red_dn >= 0 && min_red_dn <= 255, "min_red_dn", "must be from 0 to 255, got " + std::to_string(min_red_dn));
  require(min_red_excess_floor_dn >= 1 && min_red_excess_floor_dn <= min_red_excess_dn, "min_red_excess_floor_dn",
          "must be from 1 to min_red_excess_dn (" + std::to_string(min_red_excess_dn) + "), got " +
              std::to_string(min_red_excess_floor_dn));
  require(saturation_dn >= 1 && saturation_dn <= 256, "saturation_dn",
          "must be from 1 to 256 (256: no saturation rule), got " + std::to_string(saturation_dn));
  require(max_saturated_core_px >= 2 && max_saturated_core_px <= 101, "max_saturated_core_px",
          "must be from 2 to 101, got " + std::to_string(max_saturated_core_px));
  require(saturation_contrast_dn >= 1 && saturation_contrast_dn <= 255, "saturation_contrast_dn",
          "must be from 1 to 255, got " + std::to_string(saturation_contrast_dn));
  require(saturation_halo_dn >= 0 && saturation_halo_dn <= 255, "saturation_halo_dn",
          "must be from 0 (no halo test) to 255, got " + std::to_string(saturation_halo_dn));
  require(opening_size_px >= 1 && opening_size_px <= 101 && opening_size_px % 2 == 1, "opening_size_px",
          "must be an odd number from 1 to 101 (an even square has no centre), got " +
              std::to_string(opening_size_px));
  require(closing_height_px >= 1 && closing_height_px <= 101, "closing_height_px",
          "must be from 1 to 101, got " + std::to_string(closing_height_px));
  require(min_component_px >= 0, "min_component_px", "must be >= 0, got " + std::to_string(min_component_px));
  require(max_stripe_height_px >= 1, "max_stripe_height_px", "must be >= 1, got " + std::to_string(max_stripe_height_px));
  require(centroid_margin_px >= 0 && centroid_margin_px <= 50, "centroid_margin_px",
          "must be from 0 to 50, got " + std::to_string(centroid_margin_px));
}

void StripeDetection::pixels(std::vector<StripePixel>& out, double min_confidence) const {
  out.clear();
  for (const StripeColumnDetection& c : columns) {
    if (c.found && c.confidence >= min_confidence) out.push_back({c.u_px, c.v_px});
  }
}

struct StripeDetector::Buffers {
  StripeDetectorOptions options;
  cv::Mat excess, mask, core, cleaned, labels, stats, centroids;
  cv::Mat open_kernel, close_kernel;
  std::vector<Run> runs;
  std::vector<int> threshold_by_level;  ///< the excess threshold for each background level 0..255
};

StripeDetector::StripeDetector(const StripeDetectorOptions& options) : buffers_(std::make_unique<Buffers>()) {
  options.validate();
  buffers_->options = options;
  buffers_->threshold_by_level = excess_thresholds(options);
  buffers_->open_kernel = cv::getStructuringElement(cv::MORPH_RECT, cv::Size(options.opening_size_px, options.opening_size_px));
  buffers_->close_kernel = cv::getStructuringElement(cv::MORPH_RECT, cv::Size(1, options.closing_height_px));
}

StripeDetector::~StripeDetector() = default;
StripeDetector::StripeDetector(StripeDetector&&) noexcept = default;
StripeDetector& StripeDetector::operator=(StripeDetector&&) noexcept = default;

const StripeDetectorOptions& StripeDetector::options() const { return buffers_->options; }

namespace {

struct StripeCentroid {
  double weight_sum = 0.0;
  double weighted_row = 0.0;
};

// The row of a column's stripe run (step 3 of the header): the red
// excess, not the red channel, since a brightness edge under the stripe
// moves the red channel by far more than the laser's light.
StripeCentroid stripe_centroid(const RgbImage& image, const cv::Mat& excess, int x, const Run& run,
                               const StripeDetectorOptions& o) {
  const int height = image.height;
  const auto red = [&](int y) { return static_cast<int>(image.rgb[image.offset(x, y)]); };
  const auto excess_at = [&](int y) { return static_cast<int>(excess.at<std::int16_t>(y, x)); };
  const auto clipped_red_core = [&](int y) { return red(y) >= o.saturation_dn && excess_at(y) >= o.min_red_excess_floor_dn; };
  int core_top = run.top, core_bottom = run.bottom;
  for (int joined = 0; joined < o.max_saturated_core_px && core_top > 0 && clipped_red_core(core_top - 1); ++joined) {
    --core_top;
  }
  for (int joined = 0; joined < o.max_saturated_core_px && core_bottom < height - 1 && clipped_red_core(core_bottom + 1);
       ++joined) {
    ++core_bottom;
  }
  const int top = std::max(0, core_top - o.centroid_margin_px);
  const int bottom = std::min(height - 1, core_bottom + o.centroid_margin_px);
  int strongest = 0;
  int background = std::numeric_limits<int>::max();
  for (int y = std::max(0, top - 2); y <= std::min(height - 1, bottom + 2); ++y) {
    if (red(y) < o.saturation_dn) strongest = std::max(strongest, excess_at(y));
  }
  const auto laser = [&](int y) {
    const bool core = y >= core_top && y <= core_bottom && red(y) >= o.saturation_dn;
    return core ? std::max(excess_at(y), strongest) : excess_at(y);
  };
  for (int y = std::max(0, top - 2); y <= std::min(height - 1, bottom + 2); ++y) background = std::min(background, laser(y));
  background = std::max(0, background);
  StripeCentroid out;
  for (int y = top; y <= bottom; ++y) {
    const double w = std::max(0, laser(y) - background);
    out.weight_sum += w;
    out.weighted_row += w * (y + 0.5);
  }
  return out;
}

}  // namespace

void StripeDetector::detect(const RgbImage& image, StripeDetection& out) {
  check_image(image);
  Buffers& b = *buffers_;
  const StripeDetectorOptions& o = b.options;
  const int width = image.width, height = image.height;

  // 1. Red excess and the colour threshold.
  b.excess.create(height, width, CV_16SC1);
  b.mask.create(height, width, CV_8UC1);
  out.candidate_pixels = 0;
  for (int y = 0; y < height; ++y) {
    const std::uint8_t* pixel = image.rgb.data() + image.offset(0, y);
    auto* excess = b.excess.ptr<std::int16_t>(y);
    auto* mask = b.mask.ptr<std::uint8_t>(y);
    for (int x = 0; x < width; ++x, pixel += 3) {
      const int red = pixel[0];
      const int background = std::max(pixel[1], pixel[2]);
      const int e = red - background;
      excess[x] = static_cast<std::int16_t>(e);
      const bool candidate = e >= b.threshold_by_level[static_cast<std::size_t>(background)] && red >= o.min_red_dn;
      mask[x] = candidate ? 255 : 0;
      out.candidate_pixels += candidate;
    }
  }
  out.saturated_core_pixels = 0;
  if (o.saturation_dn <= 255) {
    out.saturated_core_pixels = mark_saturated_cores(image, o, b.excess, b.mask, b.core);
  } else {
    b.core.create(height, width, CV_8UC1);
    b.core.setTo(0);
  }
  out.candidate_pixels += out.saturated_core_pixels;

  // 2. Morphological clean-up.
  if (o.opening_size_px > 1) {
    cv::morphologyEx(b.mask, b.cleaned, cv::MORPH_OPEN, b.open_kernel);
  } else {
    b.mask.copyTo(b.cleaned);
  }
  if (o.closing_height_px > 1) cv::morphologyEx(b.cleaned, b.cleaned, cv::MORPH_CLOSE, b.close_kernel);
  if (o.min_component_px > 1) {
    const int count = cv::connectedComponentsWithStats(b.cleaned, b.labels, b.stats, b.centroids, 8, CV_32S);
    for (int y = 0; y < height; ++y) {
      const auto* label = b.labels.ptr<std::int32_t>(y);
      auto* keep = b.cleaned.ptr<std::uint8_t>(y);
      for (int x = 0; x < width; ++x) {
        if (keep[x] != 0 && label[x] > 0 && label[x] < count &&
            b.stats.at<std::int32_t>(label[x], cv::CC_STAT_AREA) < o.min_component_px) {
          keep[x] = 0;
        }
      }
    }
  }
  out.cleaned_pixels = static_cast<std::size_t>(cv::countNonZero(b.cleaned));

  // 3. One run per column.
  out.width = width;
  out.height = height;
  out.columns.assign(static_cast<std::size_t>(width), StripeColumnDetection{});
  out.found = 0;
  out.rejected_tall_runs = 0;
  for (int x = 0; x < width; ++x) {
    StripeColumnDetection& column = out.columns[static_cast<std::size_t>(x)];
    column.u_px = x + 0.5;
    b.runs.clear();
    for (int y = 0; y < height; ++y) {
      if (b.cleaned.at<std::uint8_t>(y, x) == 0) continue;
      const int e = std::max<int>(0, b.excess.at<std::int16_t>(y, x));
      if (b.runs.empty() || b.runs.back().bottom != y - 1) b.runs.push_back({y, y, 0, 0, false});
      Run& run = b.runs.back();
      run.bottom = y;
      run.saturated = run.saturated || b.core.at<std::uint8_t>(y, x) != 0;
      run.excess_sum += e;
      run.peak = std::max(run.peak, e);
    }
    column.runs = static_cast<int>(b.runs.size());
    if (b.runs.empty()) continue;
    long total = 0;
    const Run* best = &b.runs.front();
    for (const Run& run : b.runs) {
      total += run.excess_sum;
      if (run.excess_sum > best->excess_sum) best = &run;
    }
    if (best->bottom - best->top + 1 > o.max_stripe_height_px) {
      ++out.rejected_tall_runs;
      continue;
    }
    const StripeCentroid centroid = stripe_centroid(image, b.excess, x, *best, o);
    const double weight_sum = centroid.weight_sum, weighted_row = centroid.weighted_row;
    if (!(weight_sum > 0.0)) continue;
    column.found = true;
    column.v_px = weighted_row / weight_sum;
    column.peak_red_excess_dn = best->peak;
    column.saturated = best->saturated;
    const double threshold = o.min_red_excess_dn;
    const double contrast = std::clamp((best->peak - threshold) / threshold, 0.0, 1.0);
    const double share = total > 0 ? static_cast<double>(best->excess_sum) / static_cast<double>(total) : 1.0;
    column.confidence = contrast * share;
    ++out.found;
  }
}

namespace {

void check_stripe_header(int width, int height, const PngSourceFormat& format, const std::string& name,
                         int expected_width, int expected_height) {
  if (!format.has_colour) {
    throw InputError(name + ": a " + format.colour_type + " PNG has no colour; the stripe detector needs the camera's " +
                     "colour image (it looks for the laser's red excess)");
  }
  if (width != expected_width || height != expected_height) {
    throw InputError(name + ": the image is " + std::to_string(width) + " x " + std::to_string(height) +
                     " pixels, the configuration describes a " + std::to_string(expected_width) + " x " +
                     std::to_string(expected_height) + " image region (image_width_px, image_height_px)");
  }
}

// The camera configuration fixes the size: checked from the PNG header,
// before a large image would be decoded only to be refused.
PngReadOptions stripe_png_options(const std::string& name, int expected_width, int expected_height) {
  PngReadOptions options;
  options.check_header = [name, expected_width, expected_height](int width, int height, const PngSourceFormat& format) {
    check_stripe_header(width, height, format, name, expected_width, expected_height);
  };
  return options;
}

}  // namespace

void check_stripe_image(const RgbImage& image, const PngSourceFormat& format, const std::string& name,
                        int expected_width, int expected_height) {
  check_stripe_header(image.width, image.height, format, name, expected_width, expected_height);
}

RgbImage read_stripe_image(const std::string& path, int expected_width, int expected_height) {
  PngSourceFormat format;
  RgbImage image = read_png(path, format, stripe_png_options(path, expected_width, expected_height));
  check_stripe_image(image, format, path, expected_width, expected_height);
  return image;
}

RgbImage read_stripe_image(std::span<const std::uint8_t> bytes, const std::string& source_name, int expected_width,
                           int expected_height) {
  PngSourceFormat format;
  RgbImage image = read_png(bytes, source_name, format, stripe_png_options(source_name, expected_width, expected_height));
  check_stripe_image(image, format, source_name, expected_width, expected_height);
  return image;
}

RgbImage stripe_overlay(const RgbImage& image, const StripeDetection& detection) {
  check_image(image);
  if (detection.width != image.width || detection.height != image.height ||
      detection.columns.size() != static_cast<std::size_t>(image.width)) {
    throw InputError("stripe overlay: the detection is for a " + std::to_string(detection.width) + " x " +
                     std::to_string(detection.height) + " image, the image is " + std::to_string(image.width) + " x " +
                     std::to_string(image.height));
  }
  RgbImage out = image;
  cv::Mat canvas(out.height, out.width, CV_8UC3, out.rgb.data());
  const cv::Scalar green(0, 255, 0), yellow(255, 230, 0), magenta(255, 0, 255), ink(255, 255, 255);
  for (const StripeColumnDetection& c : detection.columns) {
    const int x = static_cast<int>(c.u_px);
    if (c.found) {
      const int y = std::clamp(static_cast<int>(c.v_px), 0, out.height - 1);
      cv::Vec3b& p = canvas.at<cv::Vec3b>(y, x);
      const cv::Scalar& colour = c.confidence >= 0.5 ? green : yellow;
      p = cv::Vec3b(static_cast<std::uint8_t>(colour[0]), static_cast<std::uint8_t>(colour[1]),
                    static_cast<std::uint8_t>(colour[2]));
    } else {
      cv::line(canvas, cv::Point(x, out.height - 1), cv::Point(x, std::max(0, out.height - 4)), magenta);
    }
  }
  char text[96];
  std::snprintf(text, sizeof text, "stripe in %zu of %d columns", detection.found, detection.width);
  const double scale = std::clamp(out.width / 900.0, 0.3, 1.0);
  cv::putText(canvas, text, cv::Point(4, std::max(12, static_cast<int>(20 * scale))), cv::FONT_HERSHEY_SIMPLEX, scale,
              cv::Scalar(0, 0, 0), 3, cv::LINE_AA);
  cv::putText(canvas, text, cv::Point(4, std::max(12, static_cast<int>(20 * scale))), cv::FONT_HERSHEY_SIMPLEX, scale,
              ink, 1, cv::LINE_AA);
  return out;
}

}  // namespace stridemap::io
