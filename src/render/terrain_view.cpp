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

void check_view_input(const Eigen::MatrixXf& elevation_m, const CellMask& filled, double cell_size_m,
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
}

// The known cells' extent: their heights' range (the colour scale's unless
// the options fix it) and their index box (the whole grid when none is known).
struct KnownCells {
  double low = 0.0, high = 1.0, mid = 0.0;
  Eigen::Index i_lo = 0, i_hi = -1, j_lo = 0, j_hi = -1;
};

KnownCells known_cells(const Eigen::MatrixXf& elevation_m, const TerrainViewOptions& o) {
  const Eigen::Index rows = elevation_m.rows(), cols = elevation_m.cols();
  KnownCells k;
  double low = std::numeric_limits<double>::infinity(), high = -low;
  k.i_lo = rows, k.j_lo = cols;
  for (Eigen::Index i = 0; i < rows; ++i) {
    for (Eigen::Index j = 0; j < cols; ++j) {
      if (!std::isfinite(elevation_m(i, j))) continue;
      low = std::min(low, double(elevation_m(i, j))), high = std::max(high, double(elevation_m(i, j)));
      k.i_lo = std::min(k.i_lo, i), k.i_hi = std::max(k.i_hi, i), k.j_lo = std::min(k.j_lo, j), k.j_hi = std::max(k.j_hi, j);
    }
  }
  const bool any = low <= high;
  k.mid = any ? 0.5 * (low + high) : 0.0;
  k.low = o.min_value.value_or(any ? low : 0.0);
  k.high = o.max_value.value_or(any ? high : 1.0);
  if (!(k.high > k.low)) k.high = k.low + 0.01;
  if (k.i_hi < 0) k.i_lo = 0, k.i_hi = rows - 1, k.j_lo = 0, k.j_hi = cols - 1;
  return k;
}

struct Camera {
  Eigen::Vector3d eye, forward, right, up;
  double focal = 1.0;
  int width_px = 0, height_px = 0;

  // The pixel of `p`; false when it is behind the camera.
  bool project(const Eigen::Vector3d& p, cv::Point* at, double* depth = nullptr) const {
    const Eigen::Vector3d d = p - eye;
    const double z = d.dot(forward);
    *at = cv::Point(static_cast<int>(std::lround(0.5 * width_px + focal * d.dot(right) / z)),
                    static_cast<int>(std::lround(0.5 * height_px - focal * d.dot(up) / z)));
    if (depth) *depth = z;
    return z > 1e-6;
  }
};

// On a sphere around `target`, far enough for a disk of `radius` to fit the
// vertical field of view.
Camera camera_around(const Eigen::Vector3d& target, double radius, const TerrainViewOptions& o) {
  const double deg = std::numbers::pi / 180.0;
  const double distance = 0.75 * radius / std::tan(0.5 * o.field_of_view_deg * deg);
  const double az = o.azimuth_deg * deg, el = o.elevation_deg * deg;
  Camera c;
  c.eye = target + distance * Eigen::Vector3d(std::cos(el) * std::cos(az), std::cos(el) * std::sin(az), std::sin(el));
  c.forward = (target - c.eye).normalized();
  c.right = c.forward.cross(Eigen::Vector3d::UnitZ());
  if (c.right.norm() < 1e-9) c.right = Eigen::Vector3d::UnitY();  // looking straight down
  c.right.normalize();
  c.up = c.right.cross(c.forward);
  c.focal = 0.5 * o.height_px / std::tan(0.5 * o.field_of_view_deg * deg);
  c.width_px = o.width_px;
  c.height_px = o.height_px;
  return c;
}

// One shaded quad per square of four known cells in front of the camera,
// farthest first.
std::vector<Quad> terrain_quads(const Eigen::MatrixXf& elevation_m, const CellMask& filled, double cell_size_m,
                                const Camera& camera, double ex, const KnownCells& known,
                                const std::array<cv::Vec3b, 256>& palette) {
  const Eigen::Index rows = elevation_m.rows(), cols = elevation_m.cols();
  const Eigen::Vector3d light = Eigen::Vector3d(-0.4, -0.6, 1.0).normalized();
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
        double z = 0.0;
        visible = camera.project(p[k], &q.corners[static_cast<std::size_t>(k)], &z) && visible;
        q.depth += z;
      }
      if (!visible) continue;
      Eigen::Vector3d normal = (p[2] - p[0]).cross(p[3] - p[1]).normalized();
      if (normal.z() < 0) normal = -normal;
      const double shade = 0.35 + 0.65 * std::max(0.0, normal.dot(light));
      const double value = 0.25 * (p[0].z() + p[1].z() + p[2].z() + p[3].z()) / ex;
      const int index = static_cast<int>(std::clamp((value - known.low) / (known.high - known.low), 0.0, 1.0) * 255.0 + 0.5);
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
  return quads;
}

void put_text(cv::Mat& canvas, const std::string& t, int x, int y, double scale = 0.45) {
  cv::putText(canvas, t, cv::Point(x, y), cv::FONT_HERSHEY_SIMPLEX, scale, cv::Scalar(30, 30, 30), 1, cv::LINE_AA);
}

// A round length under a third of the known cells' extent.
double axes_step_m(const KnownCells& known, double cell_size_m) {
  const double extent_m = static_cast<double>(std::max(known.i_hi - known.i_lo, known.j_hi - known.j_lo) + 1) * cell_size_m;
  const double magnitude = std::pow(10.0, std::floor(std::log10(extent_m / 3.0)));
  return extent_m / 3.0 >= 5 * magnitude ? 5 * magnitude : extent_m / 3.0 >= 2 * magnitude ? 2 * magnitude : magnitude;
}

// Scale: x and y axes of `step` from the corner of the known cells, drawn
// in the scene so that they shrink with distance as it does. The corner
// lies nearest the camera and can fall outside the picture (the view is
// framed on the known cells): the axes move towards the centre until all
// of them are in view.
void draw_scale_axes(cv::Mat& view, const Camera& camera, const KnownCells& known, const Eigen::Vector3d& target,
                     double cell_size_m, double ex, double step) {
  const Eigen::Vector3d box_corner(static_cast<double>(known.i_lo) * cell_size_m, static_cast<double>(known.j_lo) * cell_size_m,
                                   known.low * ex);
  const Eigen::Vector3d centre(target.x(), target.y(), known.low * ex);
  cv::Point origin, x_end, y_end;
  const auto in_view = [&](const cv::Point& p) {
    return p.x >= 8 && p.x < camera.width_px - 12 && p.y >= 44 && p.y < camera.height_px - 8;
  };
  bool placed = false;
  for (double t = 1.0; t > 0.0 && !placed; t -= 0.1) {
    const Eigen::Vector3d corner = centre + t * (box_corner - centre);
    placed = camera.project(corner, &origin) && camera.project(corner + Eigen::Vector3d(step, 0, 0), &x_end) &&
             camera.project(corner + Eigen::Vector3d(0, step, 0), &y_end) && in_view(origin) && in_view(x_end) &&
             in_view(y_end);
  }
  if (!placed) return;
  cv::arrowedLine(view, origin, x_end, cv::Scalar(40, 40, 200), 2, cv::LINE_AA, 0, 0.12);
  cv::arrowedLine(view, origin, y_end, cv::Scalar(40, 150, 40), 2, cv::LINE_AA, 0, 0.12);
  put_text(view, "x", x_end.x + 4, x_end.y);
  put_text(view, "y", y_end.x + 4, y_end.y);
}

// The panel right of the view: the colour bar, what holes and pale cells
// mean, the axes' length and the height exaggeration.
void draw_legend_panel(cv::Mat& canvas, const TerrainViewOptions& o, const KnownCells& known,
                       const std::array<cv::Vec3b, 256>& palette, const cv::Scalar& background, double step) {
  char line[96];
  const int left = o.width_px + 14;
  const cv::Scalar ink(30, 30, 30);
  put_text(canvas, "elevation [m]", left, 60);
  const int bar_top = 75, bar_h = std::max(60, o.height_px / 2), bar_w = 22;
  for (int k = 0; k < bar_h; ++k) {
    const cv::Vec3b c = palette[static_cast<std::size_t>(std::lround(255.0 * (bar_h - 1 - k) / (bar_h - 1)))];
    cv::line(canvas, {left, bar_top + k}, {left + bar_w, bar_top + k}, cv::Scalar(c[0], c[1], c[2]));
  }
  cv::rectangle(canvas, cv::Rect(left - 1, bar_top - 1, bar_w + 2, bar_h + 2), cv::Scalar(80, 80, 80));
  for (int k = 0; k <= 4; ++k) {
    const double value = known.high - (known.high - known.low) * k / 4.0;
    const int y = bar_top + (bar_h - 1) * k / 4;
    cv::line(canvas, {left + bar_w, y}, {left + bar_w + 5, y}, ink);
    std::snprintf(line, sizeof line, "%+.3f", value);
    put_text(canvas, line, left + bar_w + 9, y + 5);
  }
  int y = bar_top + bar_h + 30;
  cv::rectangle(canvas, cv::Rect(left, y - 12, 16, 16), background, cv::FILLED);
  cv::rectangle(canvas, cv::Rect(left, y - 12, 16, 16), cv::Scalar(80, 80, 80));
  put_text(canvas, "hole: unknown", left + 24, y);
  y += 24;
  put_text(canvas, "paler: filled", left, y);
  y += 24;
  std::snprintf(line, sizeof line, "axes x, y: %g m", step);
  put_text(canvas, line, left, y);
  y += 24;
  std::snprintf(line, sizeof line, "heights x%g", o.vertical_exaggeration);
  put_text(canvas, line, left, y);
}

RgbImage rgb_of(const cv::Mat& canvas) {
  RgbImage image(canvas.cols, canvas.rows);
  for (int y = 0; y < canvas.rows; ++y) {
    for (int x = 0; x < canvas.cols; ++x) {
      const cv::Vec3b& bgr = canvas.at<cv::Vec3b>(y, x);
      const std::size_t at = image.offset(x, y);
      image.rgb[at] = bgr[2];
      image.rgb[at + 1] = bgr[1];
      image.rgb[at + 2] = bgr[0];
    }
  }
  return image;
}

}  // namespace

RgbImage render_terrain_view(const Eigen::MatrixXf& elevation_m, const CellMask& filled, double cell_size_m,
                             const TerrainViewOptions& o) {
  check_view_input(elevation_m, filled, cell_size_m, o);
  const KnownCells known = known_cells(elevation_m, o);
  const double ex = o.vertical_exaggeration;
  // Camera on a sphere around the centre of the known cells, far enough
  // for all of them to fit the vertical field of view.
  const Eigen::Vector3d target(0.5 * static_cast<double>(known.i_lo + known.i_hi) * cell_size_m,
                               0.5 * static_cast<double>(known.j_lo + known.j_hi) * cell_size_m, known.mid * ex);
  const double radius = 0.5 * std::hypot(static_cast<double>(known.i_hi - known.i_lo + 1) * cell_size_m,
                                         static_cast<double>(known.j_hi - known.j_lo + 1) * cell_size_m);
  const Camera camera = camera_around(target, radius, o);
  const auto palette = detail::colour_scale_bgr(o.colour_scale);
  const std::vector<Quad> quads = terrain_quads(elevation_m, filled, cell_size_m, camera, ex, known, palette);

  const cv::Scalar background(o.background_rgb[2], o.background_rgb[1], o.background_rgb[0]);
  const int panel = o.legend ? kTerrainLegendWidthPx : 0;
  cv::Mat canvas(o.height_px, o.width_px + panel, CV_8UC3, cv::Scalar(255, 255, 255));
  cv::Mat view = canvas(cv::Rect(0, 0, o.width_px, o.height_px));
  view.setTo(background);
  for (const Quad& q : quads) cv::fillConvexPoly(view, q.corners.data(), 4, q.colour, cv::LINE_8);
  if (!o.title.empty()) put_text(canvas, o.title, 16, 30, 0.7);
  if (o.legend) {
    const double step = axes_step_m(known, cell_size_m);
    draw_scale_axes(view, camera, known, target, cell_size_m, ex, step);
    draw_legend_panel(canvas, o, known, palette, background, step);
  }
  return rgb_of(canvas);
}

}  // namespace stridemap::io
