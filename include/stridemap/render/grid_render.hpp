#pragma once
// Pictures of a map layer (elevation, certainty, errors): a scalar grid drawn
// as colour cells seen from above, with a legend. docs/outputs.md shows the
// layout.
//
// Orientation: values(i, j) is the cell i steps along +X (forward) and j
// steps along +Y (left) from cell (0, 0). The picture shows the map from
// above with the robot driving up the page: +X points up and +Y points left,
// so cell (0, 0) is the bottom-right cell and cell (rows-1, cols-1) the
// top-left one.
#include <Eigen/Core>
#include <optional>
#include <string>

#include "stridemap/render/png_image.hpp"

namespace stridemap::io {

// Per-cell flags, same shape as the value grid (true = flagged).
using CellMask = Eigen::Matrix<bool, Eigen::Dynamic, Eigen::Dynamic>;

enum class ColourScale {
  viridis,  // dark blue -> green -> yellow; perceptually uniform, colour-blind safe (default)
  turbo,    // dark blue -> green -> red; more contrast for fine height steps, not uniform in lightness
  cividis,  // blue -> yellow; uniform and readable with red-green colour blindness
  diverging,  // blue -> white -> red, for signed values (errors): give a range centred on zero
};

struct GridRenderOptions {
  // Drawn above the picture; empty draws none.
  std::string title;
  // Unit of the values, shown beside the colour bar ("m"); empty shows none.
  std::string units;
  // Ends of the colour scale; each one left empty is taken from the finite
  // values (min / max). Values outside are drawn in the end colours. When
  // the range would be empty (a constant grid, or no finite value at all) it
  // is widened around the value by max(10 % of |value|, 0.01), or set to
  // [0, 1] when there is no value at all. Both given with min >= max is an error.
  std::optional<double> min_value;
  std::optional<double> max_value;
  // An end left empty is taken from the 2nd / 98th percentile of the finite
  // values instead of the extremes, so that a few outlier cells do not wash
  // the rest into one colour (values beyond take the end colours).
  bool robust_range = false;
  // Side of one cell in pixels; 0 picks max(1, round(500 / longer side)), so
  // a 100 x 100 grid becomes 500 x 500 pixels.
  int pixels_per_cell = 0;
  // Cell side in metres; when set, the legend states it and a scale bar is
  // drawn under the grid.
  std::optional<double> cell_size_m;
  ColourScale colour_scale = ColourScale::viridis;
  // Labels of the compass arrows: up the page (rows, +X) and to the left
  // (columns, +Y). Grids that are not maps name their own axes, e.g. the
  // structured-light uncertainty maps' "z_c depth" and "x_c left".
  std::string up_axis_label = "x forward";
  std::string left_axis_label = "y left";
  // Legend labels of the two cell markings.
  std::string unknown_label = "unknown";
  std::string filled_label = "filled (estimated)";
  // The map-frame axes glyph in the legend; off for grids that are not maps.
  bool draw_axes = true;
};

// Where the grid lies in the rendered image, for tools that draw on top.
struct RenderedGrid {
  RgbImage image;
  int grid_left_px = 0;  // image x of the grid's left edge
  int grid_top_px = 0;   // image y of the grid's top edge
  int pixels_per_cell = 0;
  int rows = 0;
  int cols = 0;

  // Image x / y of the top-left pixel of cell (row, col) (see orientation above).
  int cell_left_px(int col) const { return grid_left_px + (cols - 1 - col) * pixels_per_cell; }
  int cell_top_px(int row) const { return grid_top_px + (rows - 1 - row) * pixels_per_cell; }
};

// Renders `values` (NaN = unknown, drawn as a light grey checker pattern;
// +-infinity takes the end colours). Throws InputError for an empty grid or
// an invalid option (min >= max, pixels_per_cell < 0, a grid too large for
// a PNG).
RenderedGrid render_grid(const Eigen::MatrixXf& values, const GridRenderOptions& options);

// As above; cells flagged in `filled` (values estimated by fill-in rather
// than measured) are hatched with diagonal lines and get a legend entry.
// Throws InputError when `filled` differs in shape from `values`.
RenderedGrid render_grid(const Eigen::MatrixXf& values, const CellMask& filled, const GridRenderOptions& options);

}  // namespace stridemap::io
