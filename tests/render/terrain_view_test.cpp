#include "stridemap/render/terrain_view.hpp"

#include <cmath>

#include <gtest/gtest.h>

#include "stridemap/core/error.hpp"
#include "stridemap/render/grid_overlay.hpp"
#include "stridemap/render/heat_map.hpp"

namespace stridemap::io {
namespace {

std::size_t non_white(const RgbImage& image) {
  std::size_t count = 0;
  for (std::size_t k = 0; k + 2 < image.rgb.size(); k += 3) {
    count += !(image.rgb[k] == 255 && image.rgb[k + 1] == 255 && image.rgb[k + 2] == 255);
  }
  return count;
}

Eigen::MatrixXf bump(int n) {
  Eigen::MatrixXf h(n, n);
  for (int i = 0; i < n; ++i)
    for (int j = 0; j < n; ++j) h(i, j) = static_cast<float>(0.05 * std::exp(-((i - n / 2) * (i - n / 2) + (j - n / 2) * (j - n / 2)) / 50.0));
  return h;
}

TEST(TerrainView, DrawsTheKnownCellsAndLeavesHolesForUnknownOnes) {
  TerrainViewOptions o;
  o.width_px = 320;
  o.height_px = 240;
  o.legend = false;
  o.background_rgb = {255, 255, 255};
  const Eigen::MatrixXf h = bump(40);
  const RgbImage full = render_terrain_view(h, CellMask(), 0.01, o);
  ASSERT_EQ(full.width, 320);
  ASSERT_EQ(full.height, 240);
  const std::size_t drawn = non_white(full);
  EXPECT_GT(drawn, 320u * 240u / 10u);  // the surface fills a good part of the picture
  Eigen::MatrixXf holed = h;
  holed.block(10, 10, 20, 20).setConstant(NAN);
  EXPECT_LT(non_white(render_terrain_view(holed, CellMask(), 0.01, o)), drawn);
  const Eigen::MatrixXf unknown = Eigen::MatrixXf::Constant(10, 10, NAN);
  EXPECT_EQ(non_white(render_terrain_view(unknown, CellMask(), 0.01, o)), 0u);
}

TEST(TerrainView, TheLegendPanelWidensThePictureAndHolesShowTheBackground) {
  TerrainViewOptions o;
  o.width_px = 320;
  o.height_px = 240;
  Eigen::MatrixXf h = bump(40);
  h.block(15, 15, 10, 10).setConstant(NAN);
  const RgbImage image = render_terrain_view(h, CellMask(), 0.01, o);
  ASSERT_EQ(image.width, 320 + kTerrainLegendWidthPx);
  std::size_t background = 0, ink_in_panel = 0;
  for (int y = 0; y < image.height; ++y) {
    for (int x = 0; x < image.width; ++x) {
      const std::size_t at = image.offset(x, y);
      const bool is_background = image.rgb[at] == o.background_rgb[0] && image.rgb[at + 1] == o.background_rgb[1] &&
                                 image.rgb[at + 2] == o.background_rgb[2];
      background += is_background && x < 320;
      ink_in_panel += x >= 320 && image.rgb[at] < 128;
    }
  }
  EXPECT_GT(background, 0u);
  EXPECT_GT(ink_in_panel, 200u);  // the colour bar and its labels
}

// Strongly red pixels (the x axis; the surface is viridis, which has none).
std::vector<std::pair<int, int>> red_pixels(const RgbImage& image, int view_width) {
  std::vector<std::pair<int, int>> out;
  for (int y = 0; y < image.height; ++y)
    for (int x = 0; x < view_width; ++x) {
      const std::size_t at = image.offset(x, y);
      if (image.rgb[at] > 150 && image.rgb[at + 1] < 90 && image.rgb[at + 2] < 90) out.emplace_back(x, y);
    }
  return out;
}

TEST(TerrainView, TheScaleAxesStayInsideThePictureForAnLShapedMap) {
  // Known cells in an L whose bounding box's near corner is empty and, seen
  // from behind the start, below the picture (as the rocky walk's mosaic).
  Eigen::MatrixXf h = bump(120);
  h.block(0, 0, 70, 70).setConstant(NAN);
  TerrainViewOptions o;
  const RgbImage image = render_terrain_view(h, CellMask(), 0.01, o);
  const auto red = red_pixels(image, o.width_px);
  ASSERT_GT(red.size(), 20u) << "no x axis drawn";
  for (const auto& [x, y] : red) {
    EXPECT_TRUE(x > 2 && x < o.width_px - 3 && y > 2 && y < o.height_px - 3) << x << "," << y;
  }
}

TEST(TerrainView, BadOptionsAreErrors) {
  const Eigen::MatrixXf h = bump(10);
  TerrainViewOptions o;
  o.elevation_deg = 0.0;
  EXPECT_THROW(render_terrain_view(h, CellMask(), 0.01, o), InputError);
  EXPECT_THROW(render_terrain_view(h, CellMask(), -0.01, TerrainViewOptions{}), InputError);
  EXPECT_THROW(render_terrain_view(Eigen::MatrixXf(1, 1), CellMask(), 0.01, TerrainViewOptions{}), InputError);
  EXPECT_THROW(render_terrain_view(h, CellMask::Zero(3, 3), 0.01, TerrainViewOptions{}), InputError);
}

TEST(HeatMap, LabelsEveryRowAndColumnAndChecksTheirCount) {
  Eigen::MatrixXf values(2, 3);
  values << 0, 1, 2, 3, NAN, 5;
  HeatMapOptions o;
  o.x_ticks = {"10", "20", "30"};
  o.y_ticks = {"5", "15"};
  o.x_label = "height";
  o.y_label = "pitch";
  o.highlight = std::make_pair(1, 2);
  const RgbImage image = render_heat_map(values, o);
  EXPECT_GT(image.width, 3 * o.pixels_per_cell);
  EXPECT_GT(non_white(image), 6u * 30u * 30u);
  o.y_ticks.pop_back();
  EXPECT_THROW(render_heat_map(values, o), InputError);
  EXPECT_THROW(render_heat_map(Eigen::MatrixXf(0, 0), HeatMapOptions{}), InputError);
}

TEST(GridOverlay, DrawsAPathInsideTheGrid) {
  const Eigen::MatrixXf values = Eigen::MatrixXf::Zero(50, 50);
  GridRenderOptions style;
  style.min_value = 0.0;
  style.max_value = 1.0;
  RenderedGrid rendered = render_grid(values, style);
  const RgbImage before = rendered.image;
  draw_path(rendered, {{0.05, 0.05}, {0.4, 0.3}}, 0.0, 0.0, 0.01);
  std::size_t changed = 0;
  for (std::size_t k = 0; k < before.rgb.size(); ++k) changed += before.rgb[k] != rendered.image.rgb[k];
  EXPECT_GT(changed, 100u);
  EXPECT_THROW(draw_path(rendered, {}, 0.0, 0.0, 0.0), InputError);
}

}  // namespace
}  // namespace stridemap::io
