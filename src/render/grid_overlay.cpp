#include "stridemap/render/grid_overlay.hpp"

#include <cmath>
#include <vector>

#include <opencv2/imgproc.hpp>

#include "stridemap/core/error.hpp"

namespace stridemap::io {

void draw_path(RenderedGrid& rendered, const std::vector<Eigen::Vector2d>& points_m, double origin_x_m,
               double origin_y_m, double cell_size_m, std::array<std::uint8_t, 3> rgb, int thickness_px) {
  if (!(cell_size_m > 0.0) || thickness_px < 1) throw InputError("draw_path: cell size and thickness must be positive");
  RgbImage& image = rendered.image;
  // The buffer is RGB; OpenCV only sees three channels in a row.
  cv::Mat canvas(image.height, image.width, CV_8UC3, image.rgb.data());
  const int ppc = rendered.pixels_per_cell;
  // Map (x, y) to image pixels: +X up from the bottom row, +Y left from the
  // right column (grid_render.hpp's orientation), at cell centres.
  const auto pixel = [&](const Eigen::Vector2d& p) {
    const double row = (p.x() - origin_x_m) / cell_size_m;
    const double col = (p.y() - origin_y_m) / cell_size_m;
    const double x = rendered.grid_left_px + (rendered.cols - 1 - col + 0.5) * ppc;
    const double y = rendered.grid_top_px + (rendered.rows - 1 - row + 0.5) * ppc;
    return cv::Point(static_cast<int>(std::lround(x)), static_cast<int>(std::lround(y)));
  };
  cv::Mat grid = canvas(cv::Rect(rendered.grid_left_px, rendered.grid_top_px, rendered.cols * ppc, rendered.rows * ppc));
  const cv::Point shift(-rendered.grid_left_px, -rendered.grid_top_px);
  const cv::Scalar colour(rgb[0], rgb[1], rgb[2]);
  for (std::size_t k = 1; k < points_m.size(); ++k) {
    if (!points_m[k - 1].allFinite() || !points_m[k].allFinite()) continue;
    cv::line(grid, pixel(points_m[k - 1]) + shift, pixel(points_m[k]) + shift, colour, thickness_px, cv::LINE_AA);
  }
  // Where the path starts (a green dot ringed in black) and which way it
  // ends (an arrow past its last point), so direction reads without a legend.
  std::vector<cv::Point> finite;
  for (const Eigen::Vector2d& p : points_m)
    if (p.allFinite()) finite.push_back(pixel(p) + shift);
  if (finite.empty()) return;
  const int radius = 3 + thickness_px;
  cv::circle(grid, finite.front(), radius, cv::Scalar(44, 160, 44), cv::FILLED, cv::LINE_AA);
  cv::circle(grid, finite.front(), radius, cv::Scalar(20, 20, 20), 1, cv::LINE_AA);
  const cv::Point last = finite.back();
  for (auto it = finite.rbegin(); it != finite.rend(); ++it) {
    const cv::Point2d d(last - *it);
    const double length = std::hypot(d.x, d.y);
    if (length < 6.0) continue;  // a few pixels back, so that jitter does not turn the arrow
    const cv::Point tip(static_cast<int>(std::lround(last.x + 16.0 * d.x / length)),
                        static_cast<int>(std::lround(last.y + 16.0 * d.y / length)));
    cv::arrowedLine(grid, last, tip, colour, thickness_px + 1, cv::LINE_AA, 0, 0.5);
    break;
  }
}

}  // namespace stridemap::io
