#include "stridemap/render/terrain_view.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <numbers>
#include <vector>

#include <Eigen/Geometry>
#include <opencv2/imgproc.hpp>

#include "colour_palette.hpp"
#include "stridemap/core/error.hpp"

namespace stridemap::io {
namespace {

struct Quad {
  std::array<cv::Point, 4> corners;
  double depth = 0.0;
  cv::Scalar colour;
};

void check(bool ok, const std::string& what) {
  if (!ok) throw InputError("render_terrain_view: " + what);
}

}  // namespace

RgbImage render_terrain_view(const Eigen::MatrixXf& elevation_m, const CellMask& filled, double cell_size_m,
                             const TerrainViewOptions& o) {
  check(elevation_m.rows() >= 2 && elevation_m.cols() >= 2, "the grid must have at least 2 x 2 cells");
  check(filled.size() == 0 || (filled.rows() == elevation_m.rows() && filled.cols() == elevation_m.cols()),
        "the filled mask differs in shape from the grid");
  check(std::isfinite(cell_size_m) && cell_size_m > 0.0, "cell_size_m must be positive");
  check(o.width_px >= 64 && o.height_px >= 64 && o.width_px <= 8000 && o.height_px <= 8000,
        "width_px and height_px must lie between 64 and 8000");
  check(o.elevation_deg > 0.0 && o.elevation_deg <= 90.0, "elevation_deg must lie in (0, 90]");
  check(o.field_of_view_deg > 0.0 && o.field_of_view_deg < 120.0, "field_of_view_deg must lie in (0, 120)");
  check(std::isfinite(o.vertical_exaggeration) && o.vertical_exaggeration > 0.0, "vertical_exaggeration must be positive");
  check(std::isfinite(o.azimuth_deg), "azimuth_deg must be finite");

  const Eigen::Index rows = elevation_m.rows(), cols = elevation_m.cols();
  double low = std::numeric_limits<double>::infinity(), high = -low;
  for (Eigen::Index i = 0; i < rows; ++i)
    for (Eigen::Index j = 0; j < cols; ++j)
      if (std::isfinite(elevation_m(i, j))) low = std::min(low, double(elevation_m(i, j))), high = std::max(high, double(elevation_m(i, j)));
  const bool any = low <= high;
  const double mid = any ? 0.5 * (low + high) : 0.0;
  low = o.min_value.value_or(any ? low : 0.0);
  high = o.max_value.value_or(any ? high : 1.0);
  if (!(high > low)) high = low + 0.01;

  // Camera on a sphere around the centre of the known cells, far enough
  // for all of them to fit the vertical field of view.
  Eigen::Index i_lo = rows, i_hi = -1, j_lo = cols, j_hi = -1;
  for (Eigen::Index i = 0; i < rows; ++i)
    for (Eigen::Index j = 0; j < cols; ++j)
      if (std::isfinite(elevation_m(i, j))) i_lo = std::min(i_lo, i), i_hi = std::max(i_hi, i), j_lo = std::min(j_lo, j), j_hi = std::max(j_hi, j);
  if (i_hi < 0) i_lo = 0, i_hi = rows - 1, j_lo = 0, j_hi = cols - 1;
  const double deg = std::numbers::pi / 180.0;
  const double ex = o.vertical_exaggeration;
  const Eigen::Vector3d target(0.5 * static_cast<double>(i_lo + i_hi) * cell_size_m,
                               0.5 * static_cast<double>(j_lo + j_hi) * cell_size_m, mid * ex);
  const double radius = 0.5 * std::hypot(static_cast<double>(i_hi - i_lo + 1) * cell_size_m,
                                         static_cast<double>(j_hi - j_lo + 1) * cell_size_m);
  const double distance = 0.75 * radius / std::tan(0.5 * o.field_of_view_deg * deg);
  const double az = o.azimuth_deg * deg, el = o.elevation_deg * deg;
  const Eigen::Vector3d eye = target + distance * Eigen::Vector3d(std::cos(el) * std::cos(az), std::cos(el) * std::sin(az), std::sin(el));
  const Eigen::Vector3d forward = (target - eye).normalized();
  Eigen::Vector3d right = forward.cross(Eigen::Vector3d::UnitZ());
  if (right.norm() < 1e-9) right = Eigen::Vector3d::UnitY();  // looking straight down
  right.normalize();
  const Eigen::Vector3d up = right.cross(forward);
  const double focal = 0.5 * o.height_px / std::tan(0.5 * o.field_of_view_deg * deg);
  const Eigen::Vector3d light = Eigen::Vector3d(-0.4, -0.6, 1.0).normalized();
  const auto palette = detail::colour_scale_bgr(o.colour_scale);

  const auto project = [&](const Eigen::Vector3d& p, cv::Point* at) {
    const Eigen::Vector3d d = p - eye;
    const double z = d.dot(forward);
    *at = cv::Point(static_cast<int>(std::lround(0.5 * o.width_px + focal * d.dot(right) / z)),
                    static_cast<int>(std::lround(0.5 * o.height_px - focal * d.dot(up) / z)));
    return z > 1e-6;
  };
  const auto vertex = [&](Eigen::Index i, Eigen::Index j) {
    return Eigen::Vector3d(static_cast<double>(i) * cell_size_m, static_cast<double>(j) * cell_size_m, elevation_m(i, j) * ex);
  };
  std::vector<Quad> quads;
  quads.reserve(static_cast<std::size_t>((rows - 1) * (cols - 1)));
  for (Eigen::Index i = 0; i + 1 < rows; ++i) {
    for (Eigen::Index j = 0; j + 1 < cols; ++j) {
      const std::array<Eigen::Vector3d, 4> p = {vertex(i, j), vertex(i + 1, j), vertex(i + 1, j + 1), vertex(i, j + 1)};
      if (!(p[0].allFinite() && p[1].allFinite() && p[2].allFinite() && p[3].allFinite())) continue;
      Quad q;
      bool visible = true;
      for (int k = 0; k < 4; ++k) {
        const Eigen::Vector3d d = p[k] - eye;
        const double z = d.dot(forward);
        if (z <= 1e-6) visible = false;
        q.corners[static_cast<std::size_t>(k)] =
            cv::Point(static_cast<int>(std::lround(0.5 * o.width_px + focal * d.dot(right) / z)),
                      static_cast<int>(std::lround(0.5 * o.height_px - focal * d.dot(up) / z)));
        q.depth += z;
      }
      if (!visible) continue;
      Eigen::Vector3d normal = (p[2] - p[0]).cross(p[3] - p[1]).normalized();
      if (normal.z() < 0) normal = -normal;
      const double shade = 0.35 + 0.65 * std::max(0.0, normal.dot(light));
      const double value = 0.25 * (p[0].z() + p[1].z() + p[2].z() + p[3].z()) / ex;
      const int index = static_cast<int>(std::clamp((value - low) / (high - low), 0.0, 1.0) * 255.0 + 0.5);
      const cv::Vec3b c = palette[static_cast<std::size_t>(index)];
      const bool is_filled = filled.size() != 0 && (filled(i, j) || filled(i + 1, j) || filled(i + 1, j + 1) || filled(i, j + 1));
      // Filled cells are mixed a third of the way towards white: estimated,
      // not measured.
      const auto channel = [&](int k) {
        const double lit = c[k] * shade;
        return is_filled ? (2.0 * lit + 255.0) / 3.0 : lit;
      };
      q.colour = cv::Scalar(channel(0), channel(1), channel(2));
      quads.push_back(q);
    }
  }
  std::sort(quads.begin(), quads.end(), [](const Quad& a, const Quad& b) { return a.depth > b.depth; });

  const cv::Scalar background(o.background_rgb[2], o.background_rgb[1], o.background_rgb[0]);
  const int panel = o.legend ? kTerrainLegendWidthPx : 0;
  cv::Mat canvas(o.height_px, o.width_px + panel, CV_8UC3, cv::Scalar(255, 255, 255));
  cv::Mat view = canvas(cv::Rect(0, 0, o.width_px, o.height_px));
  view.setTo(background);
  for (const Quad& q : quads) cv::fillConvexPoly(view, q.corners.data(), 4, q.colour, cv::LINE_8);
  const cv::Scalar ink(30, 30, 30);
  const auto text = [&](const std::string& t, int x, int y, double scale = 0.45) {
    cv::putText(canvas, t, cv::Point(x, y), cv::FONT_HERSHEY_SIMPLEX, scale, ink, 1, cv::LINE_AA);
  };
  if (!o.title.empty()) text(o.title, 16, 30, 0.7);
  if (o.legend) {
    // Scale: x and y axes of a round length from the corner of the known
    // cells, drawn in the scene so that they shrink with distance as it does.
    const double extent_m = static_cast<double>(std::max(i_hi - i_lo, j_hi - j_lo) + 1) * cell_size_m;
    const double magnitude = std::pow(10.0, std::floor(std::log10(extent_m / 3.0)));
    const double step = extent_m / 3.0 >= 5 * magnitude ? 5 * magnitude : extent_m / 3.0 >= 2 * magnitude ? 2 * magnitude : magnitude;
    // The bounding box's corner lies nearest the camera and can fall
    // outside the picture (the view is framed on the known cells): the axes
    // move towards the centre until all of them are in view.
    const Eigen::Vector3d box_corner(static_cast<double>(i_lo) * cell_size_m, static_cast<double>(j_lo) * cell_size_m, low * ex);
    const Eigen::Vector3d centre(target.x(), target.y(), low * ex);
    cv::Point origin, x_end, y_end;
    const auto in_view = [&](const cv::Point& p) {
      return p.x >= 8 && p.x < o.width_px - 12 && p.y >= 44 && p.y < o.height_px - 8;
    };
    bool placed = false;
    for (double t = 1.0; t > 0.0 && !placed; t -= 0.1) {
      const Eigen::Vector3d corner = centre + t * (box_corner - centre);
      placed = project(corner, &origin) && project(corner + Eigen::Vector3d(step, 0, 0), &x_end) &&
               project(corner + Eigen::Vector3d(0, step, 0), &y_end) && in_view(origin) && in_view(x_end) &&
               in_view(y_end);
    }
    if (placed) {
      cv::arrowedLine(view, origin, x_end, cv::Scalar(40, 40, 200), 2, cv::LINE_AA, 0, 0.12);
      cv::arrowedLine(view, origin, y_end, cv::Scalar(40, 150, 40), 2, cv::LINE_AA, 0, 0.12);
      text("x", x_end.x + 4, x_end.y);
      text("y", y_end.x + 4, y_end.y);
    }
    char line[96];
    const int left = o.width_px + 14;
    text("elevation [m]", left, 60);
    const int bar_top = 75, bar_h = std::max(60, o.height_px / 2), bar_w = 22;
    for (int k = 0; k < bar_h; ++k) {
      const cv::Vec3b c = palette[static_cast<std::size_t>(std::lround(255.0 * (bar_h - 1 - k) / (bar_h - 1)))];
      cv::line(canvas, {left, bar_top + k}, {left + bar_w, bar_top + k}, cv::Scalar(c[0], c[1], c[2]));
    }
    cv::rectangle(canvas, cv::Rect(left - 1, bar_top - 1, bar_w + 2, bar_h + 2), cv::Scalar(80, 80, 80));
    for (int k = 0; k <= 4; ++k) {
      const double value = high - (high - low) * k / 4.0;
      const int y = bar_top + (bar_h - 1) * k / 4;
      cv::line(canvas, {left + bar_w, y}, {left + bar_w + 5, y}, ink);
      std::snprintf(line, sizeof line, "%+.3f", value);
      text(line, left + bar_w + 9, y + 5);
    }
    int y = bar_top + bar_h + 30;
    cv::rectangle(canvas, cv::Rect(left, y - 12, 16, 16), background, cv::FILLED);
    cv::rectangle(canvas, cv::Rect(left, y - 12, 16, 16), cv::Scalar(80, 80, 80));
    text("hole: unknown", left + 24, y);
    y += 24;
    text("paler: filled", left, y);
    y += 24;
    std::snprintf(line, sizeof line, "axes x, y: %g m", step);
    text(line, left, y);
    y += 24;
    std::snprintf(line, sizeof line, "heights x%g", ex);
    text(line, left, y);
  }
  const int width = canvas.cols;
  RgbImage image(width, o.height_px);
  for (int y = 0; y < o.height_px; ++y) {
    for (int x = 0; x < width; ++x) {
      const cv::Vec3b& bgr = canvas.at<cv::Vec3b>(y, x);
      const std::size_t at = image.offset(x, y);
      image.rgb[at] = bgr[2];
      image.rgb[at + 1] = bgr[1];
      image.rgb[at + 2] = bgr[0];
    }
  }
  return image;
}

}  // namespace stridemap::io
