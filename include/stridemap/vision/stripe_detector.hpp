#pragma once
// Laser-stripe detection in colour camera images (paper section 3.1: colour
// thresholding, then morphological clean-up of the binary image, as in its
// refs. [12, 13]), then one sub-pixel stripe row per image column with a
// confidence. Works on any 8-bit RGB image, simulated or real; OpenCV
// (imgproc) does the image operations, kept out of this header.
//
// Steps, each with its option below:
// 1. red excess e = R - max(G, B) per pixel; a pixel is a stripe candidate
//    when e reaches the threshold and R >= min_red_dn (a red laser on a
//    white-balanced image: the stripe is the only strongly red thing). The
//    threshold is min_red_excess_dn on a full-scale background and follows
//    the shot noise (square root of the background level max(G, B)) below
//    it, never under min_red_excess_floor_dn: a dark surface is quieter, so
//    its dimmer stripe is found at the same number of standard deviations;
// 1b. saturation: where the laser outshines the sensor, red clips at 255
//    and the green and blue leak clips too, a white core with (sometimes)
//    a faint red halo and no red excess. In each column a run of clipped red
//    no taller than max_saturated_core_px, whose mean max(G, B) exceeds the
//    brighter of the 3 rows above and below by saturation_contrast_dn,
//    and whose flanks are red (saturation_halo_dn), is a stripe candidate
//    too (a clipped white object is taller; a lone clipped speck is one row
//    and dropped; a white surface lit by ambient light alone, clipped in a
//    thin band such as a box top seen from afar, is grey beside the band;
//    a run touching the image's top or bottom row is never a core: it may
//    go on beyond the image, and a white object clipped at the edge beside
//    the stripe would pass the one side's tests);
// 2. morphological clean-up: an optional opening with a square (drops
//    specks and hairlines thinner than it), closing with a vertical line
//    (joins a stripe that noise split across rows), and an area opening
//    that removes connected regions smaller than min_component_px (specks
//    of any shape, while a stripe of any slope stays: a square opening
//    erodes a steep stripe, which is why it is off by default);
// 3. per column, the runs of candidate rows; the run with the largest summed
//    red excess is the stripe, unless it is taller than max_stripe_height_px
//    (a red object, not a line). Its row is the centroid, over the run and
//    centroid_margin_px rows either side, of the red excess above its least
//    value there: ambient light adds to the three channels alike, so an
//    edge of brightness under the stripe moves the excess little and the
//    red channel a lot. A row whose red clipped inside the run weighs as
//    much as the strongest unclipped row around it (where the laser clips,
//    green and blue go on rising and the excess says nothing); clipped rows
//    next to the run that are still redder than green or blue by
//    min_red_excess_floor_dn join it (up to max_saturated_core_px: a red
//    core clipped on a bright surface, whose excess fell under the
//    threshold while a flank reached it).
//
// Coordinates follow structured_light.hpp: the pixel (column i, row k) has
// its centre at (i + 0.5, k + 0.5).
#include <cstddef>
#include <cstdint>
#include <memory>
#include <span>
#include <string>
#include <vector>

#include "stridemap/render/png_image.hpp"
#include "stridemap/sensors/structured_light_mapping.hpp"

namespace stridemap::io {

struct StripeDetectorOptions {
  /// Least red excess R - max(G, B) of a stripe pixel [DN of 255]. 30: six
  /// times the noise of the excess on a mid-grey webcam image (about 5 DN).
  int min_red_excess_dn = 30;
  /// Least red value of a stripe pixel [DN], so that dark noise never counts.
  int min_red_dn = 50;
  /// Scale the excess threshold with the square root of the background level
  /// (shot noise) below full scale; false: min_red_excess_dn everywhere.
  bool threshold_follows_shot_noise = true;
  /// The scaled threshold never drops below this [DN]: 10 is about six
  /// times the read noise of the excess on a dark webcam image.
  int min_red_excess_floor_dn = 10;
  /// Red at or above this is clipped [DN]; 256 turns the saturation rule off.
  int saturation_dn = 250;
  /// Tallest run of clipped red that can be a saturated stripe core [px].
  int max_saturated_core_px = 12;
  /// Least rise of the run's mean max(G, B) over its surroundings [DN]; the
  /// laser's leak into green and blue lifts them in the core. 8: over
  /// three standard deviations of a 2-row mean at mid-grey.
  int saturation_contrast_dn = 8;
  /// Least red excess R - max(G, B) at the run's edge [DN]: on the
  /// stronger side, the largest over its two outer rows and the two beyond,
  /// averaged over the column and its two neighbours. The laser's flanks are red, an
  /// ambient-lit white surface that clips is grey (its flanks' excess is
  /// noise: under 9 DN in simulated frames at 300-1000 lux, the laser's
  /// 28 DN and more). 15: four standard deviations of that mean near full
  /// scale. 0 turns the test off.
  int saturation_halo_dn = 15;
  /// Side of the square of the opening [px], odd; 1 (default) turns it off.
  int opening_size_px = 1;
  /// Height of the vertical closing line [px]; 1 turns the closing off. 7
  /// joins the two halves of a stripe whose saturated core has no red excess.
  int closing_height_px = 7;
  /// Connected candidate regions smaller than this are dropped [px].
  int min_component_px = 12;
  /// A run of candidate rows taller than this is not a stripe [px].
  int max_stripe_height_px = 25;
  /// Rows either side of the run that the centroid also weighs [px].
  int centroid_margin_px = 1;

  /// Throws InputError "stripe detector options: <field>: <problem>".
  void validate() const;
};

struct StripeColumnDetection {
  bool found = false;
  double u_px = 0.0;        ///< the column's centre, i + 0.5
  double v_px = 0.0;        ///< sub-pixel row (found only)
  /// In [0, 1]: how far the peak red excess clears the threshold (0 at the
  /// threshold, 1 at twice it and above) times the share of the column's
  /// candidate red excess that the chosen run holds (1 when it is alone).
  double confidence = 0.0;
  /// Peak strength of the run [DN]: the red excess, or for a saturated core
  /// its contrast scaled so that saturation_contrast_dn counts as
  /// min_red_excess_dn.
  int peak_red_excess_dn = 0;
  bool saturated = false;   ///< the run holds a saturated core
  int runs = 0;             ///< candidate runs in the column after the clean-up
};

struct StripeDetection {
  int width = 0;
  int height = 0;
  std::vector<StripeColumnDetection> columns;  ///< one per image column, left to right
  std::size_t found = 0;
  std::size_t candidate_pixels = 0;   ///< after thresholding
  std::size_t cleaned_pixels = 0;     ///< after the morphological clean-up
  std::size_t rejected_tall_runs = 0; ///< columns whose best run was too tall
  std::size_t saturated_core_pixels = 0; ///< candidates from the saturation rule

  /// The found columns' (u, v) with confidence >= min_confidence, for
  /// stripe_to_map_points. Clears `out` first.
  void pixels(std::vector<StripePixel>& out, double min_confidence = 0.0) const;
};

class StripeDetector {
 public:
  /// Throws InputError for unusable options.
  explicit StripeDetector(const StripeDetectorOptions& options = {});
  ~StripeDetector();
  StripeDetector(StripeDetector&&) noexcept;
  StripeDetector& operator=(StripeDetector&&) noexcept;

  /// Detects the stripe; reuses `out` and its own image buffers across
  /// same-sized frames (OpenCV's morphology may still allocate scratch
  /// memory inside). Throws InputError
  /// for an empty image or one whose buffer does not hold width x height
  /// RGB pixels.
  void detect(const RgbImage& image, StripeDetection& out);

  const StripeDetectorOptions& options() const;

 private:
  struct Buffers;
  std::unique_ptr<Buffers> buffers_;
};

/// Reads a camera image for the detector. Throws InputError naming the file
/// when it cannot be read (see read_png), holds no colour (a grey PNG: the
/// stripe is found by its red excess), or is not expected_width x
/// expected_height pixels (the image region the configuration describes).
RgbImage read_stripe_image(const std::string& path, int expected_width, int expected_height);
/// The same from a PNG file's bytes (a frame from a camera driver);
/// `source_name` stands for the file in messages.
RgbImage read_stripe_image(std::span<const std::uint8_t> bytes, const std::string& source_name, int expected_width,
                           int expected_height);
/// The checks of read_stripe_image on an image already read.
void check_stripe_image(const RgbImage& image, const PngSourceFormat& format, const std::string& name,
                        int expected_width, int expected_height);

/// A copy of the image with the detected stripe drawn on it: green dots
/// (yellow below confidence 0.5), a magenta tick at the bottom edge of each
/// column without a stripe, and a line of text with the count. Throws
/// InputError when the detection does not belong to an image of this size.
RgbImage stripe_overlay(const RgbImage& image, const StripeDetection& detection);

}  // namespace stridemap::io
