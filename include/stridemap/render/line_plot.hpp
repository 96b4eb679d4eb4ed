#pragma once
// A small line plot as an RGB image (OpenCV drawing kept out of this
// header), for experiment results such as Fig. 21's rates against the light
// level: axes with ticks, optional log-scaled x, markers and a legend.
#include <array>
#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "stridemap/render/png_image.hpp"

namespace stridemap::io {

struct PlotSeries {
  std::string label;
  std::vector<double> x, y;  ///< same length; non-finite points are skipped
  std::array<std::uint8_t, 3> colour{0, 90, 180};
};

struct LinePlotOptions {
  std::string title;
  std::string x_label;
  std::string y_label;
  bool log_x = false;  ///< x must then be positive
  /// Ends of the y axis; each one left empty comes from the data.
  std::optional<double> y_min, y_max;
  int width_px = 760;
  int height_px = 420;
};

/// Throws InputError for no series, series of unequal length, a log axis
/// with non-positive x, or a size below 200 x 150.
RgbImage render_line_plot(const std::vector<PlotSeries>& series, const LinePlotOptions& options);

/// The images one above the other (widths may differ; the narrower are
/// padded with white).
RgbImage stack_vertically(const std::vector<RgbImage>& images);

}  // namespace stridemap::io
