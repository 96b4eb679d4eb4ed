#include "stridemap/render/grid_render.hpp"

#include <gtest/gtest.h>

#include <array>
#include <cmath>
#include <limits>
#include <set>
#include <string>

#include "stridemap/core/error.hpp"

namespace stridemap::io {
namespace grid_render_test {
namespace {

using Rgb = std::array<std::uint8_t, 3>;
constexpr float kNaN = std::numeric_limits<float>::quiet_NaN();
// The two greys of the unknown-cell checker (grid_render.cpp).
const std::set<Rgb> kUnknownColours = {Rgb{238, 238, 238}, Rgb{206, 206, 206}};
constexpr Rgb kWhite{255, 255, 255};

Rgb pixel(const RgbImage& image, int x, int y) {
  const auto at = image.offset(x, y);
  return {image.rgb[at], image.rgb[at + 1], image.rgb[at + 2]};
}

// All colours inside the cell's square of pixels.
std::set<Rgb> cell_colours(const RenderedGrid& grid, int row, int col) {
  std::set<Rgb> colours;
  for (int dy = 0; dy < grid.pixels_per_cell; ++dy) {
    for (int dx = 0; dx < grid.pixels_per_cell; ++dx) {
      colours.insert(pixel(grid.image, grid.cell_left_px(col) + dx, grid.cell_top_px(row) + dy));
    }
  }
  return colours;
}

Rgb cell_colour(const RenderedGrid& grid, int row, int col) {
  const auto colours = cell_colours(grid, row, col);
  EXPECT_EQ(colours.size(), 1U) << "cell " << row << "," << col << " is not one flat colour";
  return *colours.begin();
}

bool is_unknown_cell(const RenderedGrid& grid, int row, int col) {
  for (const Rgb& colour : cell_colours(grid, row, col)) {
    if (kUnknownColours.count(colour) == 0) return false;
  }
  return true;
}

template <typename Function>
void expect_input_error(Function&& function, const std::string& fragment) {
  try {
    function();
    ADD_FAILURE() << "no InputError thrown";
  } catch (const InputError& error) {
    EXPECT_NE(std::string(error.what()).find(fragment), std::string::npos) << error.what();
  }
}

TEST(GridRender, UnknownCellsAreGreyCheckerAndKnownCellsNeverAre) {
  Eigen::MatrixXf values(6, 5);
  for (int i = 0; i < 6; ++i) {
    for (int j = 0; j < 5; ++j) values(i, j) = 0.01F * static_cast<float>(i * 5 + j);
  }
  values(2, 3) = kNaN;
  values(5, 0) = kNaN;
  GridRenderOptions options;
  options.pixels_per_cell = 8;  // large enough to hold both checker greys
  const RenderedGrid grid = render_grid(values, options);
  for (int i = 0; i < 6; ++i) {
    for (int j = 0; j < 5; ++j) {
      if (std::isnan(values(i, j))) {
        EXPECT_TRUE(is_unknown_cell(grid, i, j)) << i << "," << j;
        EXPECT_EQ(cell_colours(grid, i, j), kUnknownColours) << "checker pattern expected";
      } else {
        EXPECT_EQ(kUnknownColours.count(cell_colour(grid, i, j)), 0U) << i << "," << j;
      }
    }
  }
}

TEST(GridRender, ColoursFollowTheValueOrder) {
  Eigen::MatrixXf values(1, 5);
  values << 0.0F, 0.25F, 0.5F, 0.75F, 1.0F;
  const RenderedGrid grid = render_grid(values, GridRenderOptions{});
  std::set<Rgb> distinct;
  for (int j = 0; j < 5; ++j) distinct.insert(cell_colour(grid, 0, j));
  EXPECT_EQ(distinct.size(), 5U);
  // Viridis grows brighter with the value: the lightness must rise.
  double previous = -1.0;
  for (int j = 0; j < 5; ++j) {
    const Rgb c = cell_colour(grid, 0, j);
    const double lightness = 0.299 * c[0] + 0.587 * c[1] + 0.114 * c[2];
    EXPECT_GT(lightness, previous) << "cell " << j;
    previous = lightness;
  }
}

TEST(GridRender, ForwardIsUpAndLeftIsLeft) {
  Eigen::MatrixXf values = Eigen::MatrixXf::Constant(4, 3, kNaN);
  values(0, 0) = 1.0F;  // smallest x, smallest y: bottom-right
  const RenderedGrid grid = render_grid(values, GridRenderOptions{});
  const int right = grid.grid_left_px + 3 * grid.pixels_per_cell - 1;
  const int bottom = grid.grid_top_px + 4 * grid.pixels_per_cell - 1;
  EXPECT_EQ(kUnknownColours.count(pixel(grid.image, right, bottom)), 0U) << "cell (0,0) must be bottom-right";
  EXPECT_EQ(kUnknownColours.count(pixel(grid.image, grid.grid_left_px, grid.grid_top_px)), 1U);
  EXPECT_EQ(grid.cell_left_px(0), right + 1 - grid.pixels_per_cell);
  EXPECT_EQ(grid.cell_top_px(0), bottom + 1 - grid.pixels_per_cell);

  values.setConstant(kNaN);
  values(3, 2) = 1.0F;  // largest x, largest y: top-left
  const RenderedGrid flipped = render_grid(values, GridRenderOptions{});
  EXPECT_EQ(kUnknownColours.count(pixel(flipped.image, flipped.grid_left_px, flipped.grid_top_px)), 0U);
  EXPECT_EQ(kUnknownColours.count(pixel(flipped.image, right, bottom)), 1U);
}

TEST(GridRender, PixelsPerCellDefaultAndExplicit) {
  const Eigen::MatrixXf values = Eigen::MatrixXf::Random(100, 100);
  const RenderedGrid automatic = render_grid(values, GridRenderOptions{});
  EXPECT_EQ(automatic.pixels_per_cell, 5);
  GridRenderOptions options;
  options.pixels_per_cell = 3;
  const RenderedGrid fixed = render_grid(values, options);
  EXPECT_EQ(fixed.pixels_per_cell, 3);
  EXPECT_EQ(fixed.cell_left_px(0) - fixed.cell_left_px(1), 3);
}

TEST(GridRender, LegendSitsRightOfTheGrid) {
  const Eigen::MatrixXf values = Eigen::MatrixXf::Random(40, 60);
  GridRenderOptions options;
  options.title = "elevation";
  options.units = "m";
  const RenderedGrid grid = render_grid(values, options);
  const int grid_right = grid.grid_left_px + 60 * grid.pixels_per_cell;
  ASSERT_GT(grid.image.width, grid_right + 60);
  EXPECT_GT(grid.grid_top_px, 20) << "the title needs room above the grid";
  // Colour bar, ticks and labels: many non-white pixels, many colours.
  int inked = 0;
  std::set<Rgb> colours;
  for (int y = 0; y < grid.image.height; ++y) {
    for (int x = grid_right + 2; x < grid.image.width; ++x) {
      const Rgb c = pixel(grid.image, x, y);
      if (c != kWhite) ++inked;
      colours.insert(c);
    }
  }
  EXPECT_GT(inked, 2000);
  EXPECT_GT(colours.size(), 100U);
}

TEST(GridRender, FilledCellsAreHatchedButKeepTheirColour) {
  Eigen::MatrixXf values = Eigen::MatrixXf::Constant(3, 3, 0.5F);
  values(0, 0) = 0.0F;
  values(2, 2) = 1.0F;
  CellMask filled = CellMask::Constant(3, 3, false);
  filled(1, 1) = true;
  GridRenderOptions options;
  options.pixels_per_cell = 8;
  const RenderedGrid grid = render_grid(values, filled, options);
  const Rgb plain = cell_colour(grid, 1, 0);
  const auto hatched = cell_colours(grid, 1, 1);
  EXPECT_EQ(hatched.size(), 2U);
  EXPECT_EQ(hatched.count(plain), 1U) << "a filled cell keeps its value colour between the hatch lines";
  const RenderedGrid unmarked = render_grid(values, options);
  EXPECT_EQ(cell_colour(unmarked, 1, 1), plain);
  EXPECT_GT(grid.image.height * grid.image.width, 0);

  expect_input_error([&] { render_grid(values, CellMask::Constant(3, 4, false), options); }, "mask is 3 x 4");
}

TEST(GridRender, ConstantAndAllUnknownGridsStillRender) {
  const RenderedGrid constant = render_grid(Eigen::MatrixXf::Constant(10, 10, 0.2F), GridRenderOptions{});
  EXPECT_EQ(cell_colours(constant, 0, 0), cell_colours(constant, 9, 9));
  EXPECT_EQ(kUnknownColours.count(cell_colour(constant, 4, 4)), 0U);
  const RenderedGrid unknown = render_grid(Eigen::MatrixXf::Constant(10, 10, kNaN), GridRenderOptions{});
  EXPECT_TRUE(is_unknown_cell(unknown, 5, 5));
}

TEST(GridRender, FixedRangeClampsOutsideValues) {
  Eigen::MatrixXf values(1, 4);
  values << -5.0F, 0.0F, 1.0F, 7.0F;
  GridRenderOptions options;
  options.min_value = 0.0;
  options.max_value = 1.0;
  const RenderedGrid grid = render_grid(values, options);
  EXPECT_EQ(cell_colour(grid, 0, 0), cell_colour(grid, 0, 1));
  EXPECT_EQ(cell_colour(grid, 0, 3), cell_colour(grid, 0, 2));
  EXPECT_NE(cell_colour(grid, 0, 1), cell_colour(grid, 0, 2));
}

TEST(GridRender, ScaleBarAppearsUnderTheGridWithCellSize) {
  const Eigen::MatrixXf values = Eigen::MatrixXf::Random(50, 50);
  GridRenderOptions options;
  const RenderedGrid without = render_grid(values, options);
  options.cell_size_m = 0.01;
  const RenderedGrid with = render_grid(values, options);
  const int below = with.grid_top_px + 50 * with.pixels_per_cell + 12;  // the bar's line
  // 0.5 m wide grid: a 0.1 m bar = 10 cells, its label starts 8 px further right.
  const int bar_px = 10 * with.pixels_per_cell;
  for (int x = with.grid_left_px; x <= with.grid_left_px + bar_px; ++x) {
    EXPECT_NE(pixel(with.image, x, below), kWhite) << "gap in the scale bar at x " << x;
  }
  for (int x = with.grid_left_px + bar_px + 2; x < with.grid_left_px + bar_px + 6; ++x) {
    EXPECT_EQ(pixel(with.image, x, below), kWhite) << "scale bar too long at x " << x;
  }
  EXPECT_GE(with.image.height, without.image.height);
}

TEST(GridRender, SameInputSameImage) {
  const Eigen::MatrixXf values = Eigen::MatrixXf::Random(20, 30);
  GridRenderOptions options;
  options.title = "certainty";
  options.colour_scale = ColourScale::turbo;
  EXPECT_EQ(render_grid(values, options).image.rgb, render_grid(values, options).image.rgb);
}

TEST(GridRender, BadInputIsRejected) {
  expect_input_error([] { render_grid(Eigen::MatrixXf(0, 5), GridRenderOptions{}); }, "empty (0 x 5");
  GridRenderOptions options;
  options.min_value = 2.0;
  options.max_value = 1.0;
  expect_input_error([&] { render_grid(Eigen::MatrixXf::Zero(2, 2), options); }, "min_value");
  options = {};
  options.pixels_per_cell = -1;
  expect_input_error([&] { render_grid(Eigen::MatrixXf::Zero(2, 2), options); }, "pixels_per_cell is -1");
  options = {};
  options.pixels_per_cell = 1000;
  expect_input_error([&] { render_grid(Eigen::MatrixXf::Zero(1000, 2), options); }, "too large");
}

}  // namespace
}  // namespace grid_render_test
}  // namespace stridemap::io

namespace stridemap::io {
namespace grid_render_test {
namespace {

TEST(GridRenderAxisLabels, CompassLabelsAreOptions) {
  const Eigen::MatrixXf values = Eigen::MatrixXf::Constant(20, 20, 1.0f);
  GridRenderOptions maps;
  GridRenderOptions camera;
  camera.up_axis_label = "z_c depth";
  camera.left_axis_label = "x_c left, a much longer axis label";
  const RenderedGrid a = render_grid(values, maps);
  const RenderedGrid b = render_grid(values, camera);
  // The longer label widens the legend: the text is drawn, not the default.
  EXPECT_GT(b.image.width, a.image.width);
  EXPECT_EQ(b.image.height, a.image.height);
}

}  // namespace
}  // namespace grid_render_test
}  // namespace stridemap::io
