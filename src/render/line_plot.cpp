#include "stridemap/render/line_plot.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <limits>
#include <opencv2/imgproc.hpp>

#include "stridemap/core/error.hpp"

namespace stridemap::io {
namespace {

constexpr int kPlotFont = cv::FONT_HERSHEY_SIMPLEX;
constexpr double kText = 0.45;
const cv::Scalar kPlotInk(30, 30, 30), kGrid(225, 225, 225);

std::string tick_text(double value) {
  char text[32];
  // Thousands and millions as "20k" and "1M": short enough that the ticks of
  // a log axis spanning decades do not run into each other.
  if (std::abs(value) >= 1e6 && std::abs(value) < 1e9) {
    std::snprintf(text, sizeof text, "%gM", value / 1e6);
  } else if (std::abs(value) >= 1e4 && std::abs(value) < 1e6) {
    std::snprintf(text, sizeof text, "%gk", value / 1e3);
  } else if (std::abs(value) >= 1e9 || (std::abs(value) < 1e-2 && value != 0.0)) {
    std::snprintf(text, sizeof text, "%.0e", value);
  } else {
    std::snprintf(text, sizeof text, "%g", value);
  }
  return text;
}

std::vector<double> linear_ticks(double low, double high) {
  const double raw = (high - low) / 5.0;
  const double magnitude = std::pow(10.0, std::floor(std::log10(raw)));
  const double n = raw / magnitude;
  const double step = magnitude * (n < 1.5 ? 1.0 : n < 3.0 ? 2.0 : n < 7.0 ? 5.0 : 10.0);
  std::vector<double> ticks;
  for (double t = std::ceil(low / step - 1e-9) * step; t <= high + 1e-9 * step; t += step) {
    ticks.push_back(std::abs(t) < 1e-12 * step ? 0.0 : t);
  }
  return ticks;
}

}  // namespace

RgbImage render_line_plot(const std::vector<PlotSeries>& series, const LinePlotOptions& options) {
  if (series.empty()) throw InputError("line plot: no series to draw");
  if (options.width_px < 200 || options.height_px < 150 || options.width_px > 8000 || options.height_px > 8000) {
    throw InputError("line plot: the size must be from 200 x 150 to 8000 x 8000 pixels");
  }
  double x_low = std::numeric_limits<double>::infinity(), x_high = -x_low;
  double y_low = x_low, y_high = -x_low;
  for (const PlotSeries& s : series) {
    if (s.x.size() != s.y.size()) throw InputError("line plot: series '" + s.label + "' has x and y of unequal length");
    for (std::size_t i = 0; i < s.x.size(); ++i) {
      if (!std::isfinite(s.x[i]) || !std::isfinite(s.y[i])) continue;
      if (options.log_x && !(s.x[i] > 0.0)) throw InputError("line plot: a log x axis needs positive x values");
      x_low = std::min(x_low, s.x[i]);
      x_high = std::max(x_high, s.x[i]);
      y_low = std::min(y_low, s.y[i]);
      y_high = std::max(y_high, s.y[i]);
    }
  }
  if (!(x_low <= x_high)) x_low = 1.0, x_high = 10.0, y_low = 0.0, y_high = 1.0;
  if (options.y_min) y_low = *options.y_min;
  if (options.y_max) y_high = *options.y_max;
  if (!(y_low < y_high)) y_high = y_low + 1.0;
  const auto fx = [&](double x) { return options.log_x ? std::log10(x) : x; };
  double fx_low = fx(x_low), fx_high = fx(x_high);
  if (!(fx_low < fx_high)) fx_low -= 0.5, fx_high += 0.5;

  cv::Mat canvas(options.height_px, options.width_px, CV_8UC3, cv::Scalar(255, 255, 255));
  const int left = 70, right = 180, top = options.title.empty() ? 20 : 44, bottom = 56;
  const int plot_w = options.width_px - left - right, plot_h = options.height_px - top - bottom;
  const auto px = [&](double x) { return left + static_cast<int>(std::lround((fx(x) - fx_low) / (fx_high - fx_low) * plot_w)); };
  const auto py = [&](double y) {
    const double clamped = std::clamp(y, y_low, y_high);
    return top + plot_h - static_cast<int>(std::lround((clamped - y_low) / (y_high - y_low) * plot_h));
  };
  if (!options.title.empty()) cv::putText(canvas, options.title, {left, 28}, kPlotFont, 0.6, kPlotInk, 1, cv::LINE_AA);

  std::vector<double> x_ticks;
  if (options.log_x) {
    for (double decade = std::floor(fx_low); decade <= std::ceil(fx_high); decade += 1.0) {
      for (double m : {1.0, 2.0, 5.0}) {
        const double t = m * std::pow(10.0, decade);
        if (fx(t) >= fx_low - 1e-9 && fx(t) <= fx_high + 1e-9) x_ticks.push_back(t);
      }
    }
  } else {
    x_ticks = linear_ticks(x_low, x_high);
  }
  for (double t : x_ticks) {
    const int x = px(t);
    cv::line(canvas, {x, top}, {x, top + plot_h}, kGrid);
    cv::line(canvas, {x, top + plot_h}, {x, top + plot_h + 4}, kPlotInk);
    int baseline = 0;
    const cv::Size size = cv::getTextSize(tick_text(t), kPlotFont, kText, 1, &baseline);
    cv::putText(canvas, tick_text(t), {x - size.width / 2, top + plot_h + 18}, kPlotFont, kText, kPlotInk, 1, cv::LINE_AA);
  }
  for (double t : linear_ticks(y_low, y_high)) {
    const int y = py(t);
    cv::line(canvas, {left, y}, {left + plot_w, y}, kGrid);
    cv::line(canvas, {left - 4, y}, {left, y}, kPlotInk);
    int baseline = 0;
    const cv::Size size = cv::getTextSize(tick_text(t), kPlotFont, kText, 1, &baseline);
    cv::putText(canvas, tick_text(t), {left - 8 - size.width, y + 5}, kPlotFont, kText, kPlotInk, 1, cv::LINE_AA);
  }
  cv::rectangle(canvas, cv::Rect(left, top, plot_w, plot_h), kPlotInk);
  int baseline = 0;
  const cv::Size xl = cv::getTextSize(options.x_label, kPlotFont, kText, 1, &baseline);
  cv::putText(canvas, options.x_label, {left + (plot_w - xl.width) / 2, options.height_px - 12}, kPlotFont, kText, kPlotInk, 1,
              cv::LINE_AA);
  cv::putText(canvas, options.y_label, {8, top - 8 > 12 ? top - 8 : 12}, kPlotFont, kText, kPlotInk, 1, cv::LINE_AA);

  int legend_y = top + 10;
  for (const PlotSeries& s : series) {
    const cv::Scalar colour(s.colour[0], s.colour[1], s.colour[2]);
    cv::Point previous(-1, -1);
    for (std::size_t i = 0; i < s.x.size(); ++i) {
      if (!std::isfinite(s.x[i]) || !std::isfinite(s.y[i])) {
        previous = {-1, -1};
        continue;
      }
      const cv::Point p(px(s.x[i]), py(s.y[i]));
      if (previous.x >= 0) cv::line(canvas, previous, p, colour, 2, cv::LINE_AA);
      cv::circle(canvas, p, 4, colour, cv::FILLED, cv::LINE_AA);
      previous = p;
    }
    cv::line(canvas, {left + plot_w + 14, legend_y}, {left + plot_w + 38, legend_y}, colour, 2, cv::LINE_AA);
    cv::circle(canvas, {left + plot_w + 26, legend_y}, 4, colour, cv::FILLED, cv::LINE_AA);
    cv::putText(canvas, s.label, {left + plot_w + 44, legend_y + 5}, kPlotFont, 0.4, kPlotInk, 1, cv::LINE_AA);
    legend_y += 22;
  }
  RgbImage image(canvas.cols, canvas.rows);
  for (int y = 0; y < canvas.rows; ++y) std::memcpy(&image.rgb[image.offset(0, y)], canvas.ptr<std::uint8_t>(y), 3 * canvas.cols);
  return image;
}

RgbImage stack_vertically(const std::vector<RgbImage>& images) {
  int width = 0, height = 0;
  for (const RgbImage& i : images) width = std::max(width, i.width), height += i.height;
  RgbImage out(width, height, 255, 255, 255);
  int y0 = 0;
  for (const RgbImage& i : images) {
    for (int y = 0; y < i.height; ++y) {
      std::memcpy(&out.rgb[out.offset(0, y0 + y)], &i.rgb[i.offset(0, y)], 3 * static_cast<std::size_t>(i.width));
    }
    y0 += i.height;
  }
  return out;
}

}  // namespace stridemap::io
