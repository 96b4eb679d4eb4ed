#include "stridemap/render/heat_map.hpp"

#include <algorithm>
#include <cstring>

#include <opencv2/imgproc.hpp>

#include "stridemap/core/error.hpp"

namespace stridemap::io {
namespace {

constexpr int kHeatMapFont = cv::FONT_HERSHEY_SIMPLEX;
constexpr double kScale = 0.45;
const cv::Scalar kHeatMapInk(30, 30, 30);

int text_width(const std::string& s) {
  int baseline = 0;
  return cv::getTextSize(s, kHeatMapFont, kScale, 1, &baseline).width;
}

}  // namespace

RgbImage render_heat_map(const Eigen::MatrixXf& values, const HeatMapOptions& o) {
  if (values.size() == 0) throw InputError("render_heat_map: the grid is empty");
  if (o.x_ticks.size() != static_cast<std::size_t>(values.cols()) ||
      o.y_ticks.size() != static_cast<std::size_t>(values.rows())) {
    throw InputError("render_heat_map: " + std::to_string(o.x_ticks.size()) + " x ticks and " +
                     std::to_string(o.y_ticks.size()) + " y ticks for a grid of " + std::to_string(values.rows()) +
                     " rows and " + std::to_string(values.cols()) + " columns");
  }
  // render_grid draws row i upwards and column j to the LEFT; mirror the
  // columns so that x grows to the right.
  const Eigen::MatrixXf mirrored = values.rowwise().reverse();
  GridRenderOptions grid;
  grid.title = o.title;
  grid.units = o.units;
  grid.min_value = o.min_value;
  grid.max_value = o.max_value;
  grid.colour_scale = o.colour_scale;
  grid.pixels_per_cell = o.pixels_per_cell;
  grid.unknown_label = o.missing_label;
  grid.draw_axes = false;
  const RenderedGrid rendered = render_grid(mirrored, grid);

  int left = text_width(o.y_label) + 8;
  for (const std::string& t : o.y_ticks) left = std::max(left, text_width(t) + 12);
  const int bottom = 48;
  const int top = 22;  // room for the y axis name above the grid
  cv::Mat canvas(rendered.image.height + bottom + top, rendered.image.width + left, CV_8UC3, cv::Scalar(255, 255, 255));
  for (int y = 0; y < rendered.image.height; ++y) {
    std::memcpy(canvas.ptr<std::uint8_t>(y + top) + 3 * left, &rendered.image.rgb[rendered.image.offset(0, y)],
                static_cast<std::size_t>(3 * rendered.image.width));
  }
  const int gx = left + rendered.grid_left_px, gy = top + rendered.grid_top_px, ppc = rendered.pixels_per_cell;
  const int rows = rendered.rows, cols = rendered.cols;
  for (int i = 0; i < rows; ++i) {
    const std::string& t = o.y_ticks[static_cast<std::size_t>(i)];
    const int y = gy + (rows - 1 - i) * ppc + ppc / 2 + 5;
    cv::putText(canvas, t, cv::Point(gx - 6 - text_width(t), y), kHeatMapFont, kScale, kHeatMapInk, 1, cv::LINE_AA);
  }
  for (int k = 0; k < cols; ++k) {
    const std::string& t = o.x_ticks[static_cast<std::size_t>(k)];
    const int x = gx + k * ppc + ppc / 2 - text_width(t) / 2;
    cv::putText(canvas, t, cv::Point(x, gy + rows * ppc + 18), kHeatMapFont, kScale, kHeatMapInk, 1, cv::LINE_AA);
  }
  cv::putText(canvas, o.x_label, cv::Point(gx + cols * ppc / 2 - text_width(o.x_label) / 2, gy + rows * ppc + 40),
              kHeatMapFont, kScale, kHeatMapInk, 1, cv::LINE_AA);
  cv::putText(canvas, o.y_label, cv::Point(4, gy - 8), kHeatMapFont, kScale, kHeatMapInk, 1, cv::LINE_AA);
  if (o.highlight) {
    const auto [row, col] = *o.highlight;
    if (row >= 0 && row < rows && col >= 0 && col < cols) {
      const cv::Rect cell(gx + col * ppc, gy + (rows - 1 - row) * ppc, ppc, ppc);
      cv::rectangle(canvas, cell, cv::Scalar(255, 255, 255), 3);
      cv::rectangle(canvas, cell, cv::Scalar(220, 30, 30), 1);
    }
  }
  RgbImage image(canvas.cols, canvas.rows);
  for (int y = 0; y < canvas.rows; ++y) {
    std::memcpy(&image.rgb[image.offset(0, y)], canvas.ptr<std::uint8_t>(y), static_cast<std::size_t>(3 * canvas.cols));
  }
  return image;
}

}  // namespace stridemap::io
