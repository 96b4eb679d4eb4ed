#include "stridemap/render/grid_render.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <limits>
#include <opencv2/imgproc.hpp>
#include <vector>

#include "colour_palette.hpp"
#include "stridemap/core/error.hpp"

namespace stridemap::io {
namespace {

using Rgb = std::array<std::uint8_t, 3>;

constexpr Rgb kBackground{255, 255, 255};
constexpr Rgb kInk{30, 30, 30};
constexpr Rgb kFrame{80, 80, 80};
// Light greys: no colour of the three scales comes close to them (cividis's
// greyish middle is around 125), so unknown cells never pass for values.
constexpr Rgb kUnknownLight{238, 238, 238};
constexpr Rgb kUnknownDark{206, 206, 206};

constexpr int kFont = cv::FONT_HERSHEY_SIMPLEX;
constexpr double kTextScale = 0.5;
constexpr double kTitleScale = 0.7;
constexpr int kMargin = 16;
constexpr int kLegendGap = 30;
constexpr int kBarWidth = 22;
constexpr int kTickLength = 5;
constexpr int kSwatch = 16;
constexpr int kCheckerPx = 4;  // side of one checker square of unknown cells
constexpr int kHatchPx = 4;    // spacing of the diagonal hatch lines of filled cells
constexpr int kArrowPx = 34;   // arrow length of the axes glyph

struct Range {
  double low = 0.0;
  double high = 1.0;
};

std::array<Rgb, 256> make_palette(ColourScale scale) {
  const std::array<cv::Vec3b, 256> bgr = detail::colour_scale_bgr(scale);
  std::array<Rgb, 256> palette{};
  for (std::size_t i = 0; i < palette.size(); ++i) palette[i] = {bgr[i][2], bgr[i][1], bgr[i][0]};
  return palette;
}

Range colour_range(const Eigen::MatrixXf& values, const GridRenderOptions& options) {
  if (options.min_value && !std::isfinite(*options.min_value)) throw InputError("render_grid: min_value is not finite");
  if (options.max_value && !std::isfinite(*options.max_value)) throw InputError("render_grid: max_value is not finite");
  if (options.min_value && options.max_value && !(*options.min_value < *options.max_value)) {
    throw InputError("render_grid: min_value " + std::to_string(*options.min_value) + " is not below max_value " +
                     std::to_string(*options.max_value));
  }
  double data_low = std::numeric_limits<double>::infinity();
  double data_high = -data_low;
  for (Eigen::Index j = 0; j < values.cols(); ++j) {
    for (Eigen::Index i = 0; i < values.rows(); ++i) {
      const double value = values(i, j);
      if (!std::isfinite(value)) continue;
      data_low = std::min(data_low, value);
      data_high = std::max(data_high, value);
    }
  }
  const bool any_data = data_low <= data_high;
  if (any_data && options.robust_range) {
    std::vector<float> finite;
    finite.reserve(static_cast<std::size_t>(values.size()));
    for (Eigen::Index k = 0; k < values.size(); ++k)
      if (std::isfinite(values.data()[k])) finite.push_back(values.data()[k]);
    const auto at = [&](double share) {
      const auto n = static_cast<std::size_t>(std::lround(share * static_cast<double>(finite.size() - 1)));
      std::nth_element(finite.begin(), finite.begin() + static_cast<std::ptrdiff_t>(n), finite.end());
      return static_cast<double>(finite[n]);
    };
    data_low = at(0.02);
    data_high = at(0.98);
  }
  Range range;
  range.low = options.min_value.value_or(any_data ? data_low : 0.0);
  range.high = options.max_value.value_or(any_data ? data_high : 1.0);
  if (range.low < range.high) return range;
  // A constant grid (or one fixed end beyond the data) still needs a scale.
  const double anchor = options.min_value ? range.low : range.high;
  const double half_width = std::max(0.1 * std::abs(anchor), 0.01);
  if (options.min_value) {
    range.high = range.low + 2.0 * half_width;
  } else if (options.max_value) {
    range.low = range.high - 2.0 * half_width;
  } else {
    range.low = anchor - half_width;
    range.high = anchor + half_width;
  }
  return range;
}

// "Nice" tick values (1, 2 or 5 times a power of ten apart) inside the range.
std::vector<double> nice_ticks(const Range& range, int* decimals) {
  const double raw_step = (range.high - range.low) / 5.0;
  const double magnitude = std::pow(10.0, std::floor(std::log10(raw_step)));
  const double normalised = raw_step / magnitude;
  const double step = magnitude * (normalised < 1.5 ? 1.0 : normalised < 3.0 ? 2.0 : normalised < 7.0 ? 5.0 : 10.0);
  *decimals = std::max(0, static_cast<int>(-std::floor(std::log10(step) + 1e-9)));
  std::vector<double> ticks;
  const double tolerance = 1e-9 * step;
  for (double tick = std::ceil((range.low - tolerance) / step) * step; tick <= range.high + tolerance; tick += step) {
    ticks.push_back(std::abs(tick) < tolerance ? 0.0 : tick);
  }
  return ticks;
}

std::string format_number(double value, int decimals) {
  char text[64];
  std::snprintf(text, sizeof text, "%.*f", decimals, value);
  return text;
}

std::string format_length(double metres) {
  char text[64];
  if (metres < 0.1) {
    std::snprintf(text, sizeof text, "%g mm", std::round(metres * 1e4) / 10.0);
  } else {
    std::snprintf(text, sizeof text, "%g m", metres);
  }
  return text;
}

// Largest 1, 2 or 5 times a power of ten not above `limit`.
double nice_length_below(double limit) {
  const double magnitude = std::pow(10.0, std::floor(std::log10(limit)));
  for (double factor : {5.0, 2.0, 1.0}) {
    if (factor * magnitude <= limit) return factor * magnitude;
  }
  return magnitude;
}

cv::Size text_size(const std::string& text, double scale) {
  int baseline = 0;
  return cv::getTextSize(text, kFont, scale, 1, &baseline);
}

Rgb blend(const Rgb& a, const Rgb& b, double weight_b) {
  Rgb mixed{};
  for (int c = 0; c < 3; ++c) {
    mixed[c] = static_cast<std::uint8_t>(std::lround((1.0 - weight_b) * a[c] + weight_b * b[c]));
  }
  return mixed;
}

// Pixel (x, y) of a patch, measured from the patch's top-left corner.
Rgb unknown_pixel(int x, int y) { return ((x / kCheckerPx + y / kCheckerPx) % 2 == 0) ? kUnknownLight : kUnknownDark; }

Rgb filled_pixel(const Rgb& colour, int x, int y) {
  if ((x + y) % kHatchPx != 0) return colour;
  const double lightness = 0.299 * colour[0] + 0.587 * colour[1] + 0.114 * colour[2];
  return blend(colour, lightness < 128.0 ? Rgb{255, 255, 255} : Rgb{0, 0, 0}, 0.6);
}

class Canvas {
 public:
  Canvas(int width, int height) : mat_(height, width, CV_8UC3, scalar(kBackground)) {}
  static cv::Scalar scalar(const Rgb& c) { return {double(c[0]), double(c[1]), double(c[2])}; }
  void set(int x, int y, const Rgb& c) { std::memcpy(mat_.ptr<std::uint8_t>(y) + 3 * x, c.data(), 3); }
  void rect(int x, int y, int w, int h, const Rgb& c) {
    cv::rectangle(mat_, cv::Rect(x, y, w, h), scalar(c), 1, cv::LINE_8);
  }
  void line(cv::Point a, cv::Point b, const Rgb& c) { cv::line(mat_, a, b, scalar(c), 1, cv::LINE_AA); }
  void arrow(cv::Point from, cv::Point to) {
    cv::arrowedLine(mat_, from, to, scalar(kInk), 1, cv::LINE_AA, 0, 0.22);
  }
  // (x, y) is the left end of the text's baseline.
  void text(const std::string& s, int x, int y, double scale = kTextScale) {
    cv::putText(mat_, s, cv::Point(x, y), kFont, scale, scalar(kInk), 1, cv::LINE_AA);
  }
  RgbImage to_image() const {
    RgbImage image(mat_.cols, mat_.rows);
    for (int y = 0; y < mat_.rows; ++y) std::memcpy(&image.rgb[image.offset(0, y)], mat_.ptr<std::uint8_t>(y), 3 * mat_.cols);
    return image;
  }

 private:
  cv::Mat mat_;
};

using Palette = std::array<Rgb, 256>;

void check_render_input(const Eigen::MatrixXf& values, const CellMask* filled, const GridRenderOptions& options) {
  if (values.size() == 0) {
    throw InputError("render_grid: the grid is empty (" + std::to_string(values.rows()) + " x " +
                     std::to_string(values.cols()) + " cells)");
  }
  if (filled != nullptr && (filled->rows() != values.rows() || filled->cols() != values.cols())) {
    throw InputError("render_grid: the filled-cell mask is " + std::to_string(filled->rows()) + " x " +
                     std::to_string(filled->cols()) + ", the grid " + std::to_string(values.rows()) + " x " +
                     std::to_string(values.cols()));
  }
  if (options.pixels_per_cell < 0) {
    throw InputError("render_grid: pixels_per_cell is " + std::to_string(options.pixels_per_cell) +
                     " (0 = automatic, or a positive size)");
  }
  if (options.cell_size_m && !(std::isfinite(*options.cell_size_m) && *options.cell_size_m > 0.0)) {
    throw InputError("render_grid: cell_size_m must be positive and finite");
  }
}

// The grid, seen from above: +X up, +Y left.
template <typename ColourOf>
void draw_cells(Canvas& canvas, const RenderedGrid& out, const Eigen::MatrixXf& values, const CellMask* filled,
                const ColourOf& colour_of) {
  for (int row = 0; row < out.rows; ++row) {
    for (int col = 0; col < out.cols; ++col) {
      const float value = values(row, col);
      const bool unknown = std::isnan(value);
      const bool is_filled = !unknown && filled != nullptr && (*filled)(row, col);
      const Rgb colour = unknown ? Rgb{} : colour_of(value);
      const int left = out.cell_left_px(col) - out.grid_left_px;
      const int top = out.cell_top_px(row) - out.grid_top_px;
      for (int y = top; y < top + out.pixels_per_cell; ++y) {
        for (int x = left; x < left + out.pixels_per_cell; ++x) {
          const Rgb pixel = unknown ? unknown_pixel(x, y) : is_filled ? filled_pixel(colour, x, y) : colour;
          canvas.set(out.grid_left_px + x, out.grid_top_px + y, pixel);
        }
      }
    }
  }
}

// A bar of a round length under the grid, a quarter of its width at most.
void draw_scale_bar(Canvas& canvas, const RenderedGrid& out, double cell_size_m, int text_h) {
  const double grid_width_m = cell_size_m * out.cols;
  const double bar_m = nice_length_below(grid_width_m / 4.0);
  const int bar_px = static_cast<int>(std::lround(bar_m / cell_size_m * out.pixels_per_cell));
  const int y = out.grid_top_px + out.rows * out.pixels_per_cell + 12;
  const int x0 = out.grid_left_px;
  if (bar_px < 2) return;
  canvas.line({x0, y}, {x0 + bar_px, y}, kInk);
  canvas.line({x0, y - 4}, {x0, y + 4}, kInk);
  canvas.line({x0 + bar_px, y - 4}, {x0 + bar_px, y + 4}, kInk);
  canvas.text(format_length(bar_m), x0 + bar_px + 8, y + text_h / 2);
}

// The colour bar from `top` down with its ticks and labels.
void draw_colour_bar(Canvas& canvas, const Palette& palette, const Range& range, const std::vector<double>& ticks,
                     int decimals, int left, int top, int bar_h, int text_h) {
  for (int i = 0; i < bar_h; ++i) {
    const Rgb colour = palette[static_cast<std::size_t>(std::lround(255.0 * (bar_h - 1 - i) / (bar_h - 1)))];
    for (int x = 0; x < kBarWidth; ++x) canvas.set(left + x, top + i, colour);
  }
  canvas.rect(left - 1, top - 1, kBarWidth + 2, bar_h + 2, kFrame);
  for (double tick : ticks) {
    const int tick_y = top + static_cast<int>(std::lround((range.high - tick) / (range.high - range.low) * (bar_h - 1)));
    canvas.line({left + kBarWidth, tick_y}, {left + kBarWidth + kTickLength, tick_y}, kInk);
    canvas.text(format_number(tick, decimals), left + kBarWidth + kTickLength + 6, tick_y + text_h / 2);
  }
}

// The axes glyph below `y`: origin at the corner, +X up, +Y left, as in the grid.
void draw_axes_glyph(Canvas& canvas, const std::string& x_axis, const std::string& y_axis, int left, int y, int text_h) {
  const int x_label_w = text_size(x_axis, kTextScale).width;
  const int origin_x = left + text_size(y_axis, kTextScale).width / 2 + kArrowPx;
  const int origin_y = y + text_h + 6 + kArrowPx;
  canvas.text(x_axis, std::max(left, origin_x - x_label_w / 2), y + text_h);
  canvas.arrow({origin_x, origin_y}, {origin_x, origin_y - kArrowPx});
  canvas.arrow({origin_x, origin_y}, {origin_x - kArrowPx, origin_y});
  canvas.text(y_axis, origin_x - kArrowPx - text_size(y_axis, kTextScale).width / 2, origin_y + 6 + text_h);
}

RenderedGrid render(const Eigen::MatrixXf& values, const CellMask* filled, const GridRenderOptions& options) {
  check_render_input(values, filled, options);
  const long long rows = values.rows();
  const long long cols = values.cols();
  const long long longer = std::max(rows, cols);
  const long long cell_px =
      options.pixels_per_cell > 0 ? options.pixels_per_cell : std::max(1LL, std::llround(500.0 / double(longer)));
  if (longer * cell_px > kMaxPngSide / 2) {
    throw InputError("render_grid: a " + std::to_string(rows) + " x " + std::to_string(cols) + " grid at " +
                     std::to_string(cell_px) + " pixels per cell is too large for an image");
  }
  RenderedGrid out;
  out.rows = static_cast<int>(rows);
  out.cols = static_cast<int>(cols);
  out.pixels_per_cell = static_cast<int>(cell_px);
  const int grid_w = out.cols * out.pixels_per_cell;
  const int grid_h = out.rows * out.pixels_per_cell;

  const Range range = colour_range(values, options);
  const Palette palette = make_palette(options.colour_scale);
  const auto colour_of = [&](double value) {
    if (value >= range.high) return palette[255];
    if (!(value > range.low)) return palette[0];
    return palette[static_cast<std::size_t>(std::lround((value - range.low) / (range.high - range.low) * 255.0))];
  };

  // Legend contents and their sizes decide the image size.
  int decimals = 0;
  const std::vector<double> ticks = nice_ticks(range, &decimals);
  const int text_h = text_size("0", kTextScale).height;
  int tick_label_w = 0;
  for (double tick : ticks) tick_label_w = std::max(tick_label_w, text_size(format_number(tick, decimals), kTextScale).width);
  const std::string cell_text = options.cell_size_m ? "cell " + format_length(*options.cell_size_m) : "";
  const std::string& x_axis = options.up_axis_label;
  const std::string& y_axis = options.left_axis_label;
  int legend_w = kBarWidth + kTickLength + 6 + tick_label_w;
  legend_w = std::max(legend_w, text_size(options.units, kTextScale).width);
  legend_w = std::max(legend_w, kSwatch + 8 + text_size(options.unknown_label, kTextScale).width);
  if (filled != nullptr) legend_w = std::max(legend_w, kSwatch + 8 + text_size(options.filled_label, kTextScale).width);
  legend_w = std::max(legend_w, text_size(cell_text, kTextScale).width);
  legend_w = std::max(legend_w, text_size(y_axis, kTextScale).width + kArrowPx + 8 + text_size(x_axis, kTextScale).width / 2);

  const int bar_h = std::clamp(grid_h * 11 / 20, 120, 320);
  const int swatch_rows = filled != nullptr ? 2 : 1;
  const int legend_h = (options.units.empty() ? 0 : text_h + 12) + text_h / 2 + bar_h + text_h / 2 + 20 +
                       swatch_rows * (kSwatch + 8) + (cell_text.empty() ? 0 : text_h + 12) + 16 + text_h + 6 +
                       kArrowPx + 6 + text_h;

  // A title may hold several lines ('\n'): a long one would widen the picture.
  std::vector<std::string> title_lines;
  for (std::size_t begin = 0; !options.title.empty() && begin <= options.title.size();) {
    const std::size_t end = std::min(options.title.find('\n', begin), options.title.size());
    title_lines.push_back(options.title.substr(begin, end - begin));
    begin = end + 1;
  }
  cv::Size title_size(0, 0);
  const int title_line_h = text_size("Ag", kTitleScale).height + 8;
  for (const std::string& line : title_lines) title_size.width = std::max(title_size.width, text_size(line, kTitleScale).width);
  title_size.height = static_cast<int>(title_lines.size()) * title_line_h - 8;
  out.grid_left_px = kMargin;
  out.grid_top_px = kMargin + (options.title.empty() ? 0 : title_size.height + 16);
  const int scale_bar_h = options.cell_size_m ? 16 + text_h + 4 : 0;
  const int legend_left = out.grid_left_px + grid_w + kLegendGap;
  const int width = std::max(legend_left + legend_w + kMargin, 2 * kMargin + title_size.width);
  const int height = out.grid_top_px + std::max(grid_h + scale_bar_h, legend_h) + kMargin;
  Canvas canvas(width, height);

  if (!options.title.empty()) {
    for (std::size_t k = 0; k < title_lines.size(); ++k) {
      canvas.text(title_lines[k], kMargin, kMargin + title_line_h - 8 + static_cast<int>(k) * title_line_h, kTitleScale);
    }
  }

  draw_cells(canvas, out, values, filled, colour_of);
  canvas.rect(out.grid_left_px - 1, out.grid_top_px - 1, grid_w + 2, grid_h + 2, kFrame);

  if (options.cell_size_m) draw_scale_bar(canvas, out, *options.cell_size_m, text_h);

  // Legend: colour bar with ticks, unit, cell markings, cell size, axes.
  int y = out.grid_top_px;
  if (!options.units.empty()) {
    canvas.text(options.units, legend_left, y + text_h);
    y += text_h + 12;
  }
  y += text_h / 2;
  const int bar_top = y;
  draw_colour_bar(canvas, palette, range, ticks, decimals, legend_left, bar_top, bar_h, text_h);
  y = bar_top + bar_h + text_h / 2 + 20;

  const auto swatch = [&](const std::string& label, bool is_filled) {
    const Rgb middle = palette[128];
    for (int sy = 0; sy < kSwatch; ++sy) {
      for (int sx = 0; sx < kSwatch; ++sx) {
        canvas.set(legend_left + sx, y + sy, is_filled ? filled_pixel(middle, sx, sy) : unknown_pixel(sx, sy));
      }
    }
    canvas.rect(legend_left - 1, y - 1, kSwatch + 2, kSwatch + 2, kFrame);
    canvas.text(label, legend_left + kSwatch + 8, y + (kSwatch + text_h) / 2);
    y += kSwatch + 8;
  };
  swatch(options.unknown_label, false);
  if (filled != nullptr) swatch(options.filled_label, true);

  if (!cell_text.empty()) {
    y += 4;
    canvas.text(cell_text, legend_left, y + text_h);
    y += text_h + 8;
  }

  // Axes glyph: origin at the corner, +X up, +Y left, as in the grid.
  if (!options.draw_axes) {
    out.image = canvas.to_image();
    return out;
  }
  y += 16;
  draw_axes_glyph(canvas, x_axis, y_axis, legend_left, y, text_h);

  out.image = canvas.to_image();
  return out;
}

}  // namespace

RenderedGrid render_grid(const Eigen::MatrixXf& values, const GridRenderOptions& options) {
  return render(values, nullptr, options);
}

RenderedGrid render_grid(const Eigen::MatrixXf& values, const CellMask& filled, const GridRenderOptions& options) {
  return render(values, &filled, options);
}

}  // namespace stridemap::io
