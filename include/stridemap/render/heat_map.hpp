#pragma once
// A heat map of a quantity over a 2D parameter grid (the mount analysis:
// sensor height across, pitch up), with tick labels on both axes, drawn
// with render_grid's colour bar and legend.
#include <optional>
#include <string>
#include <vector>

#include <Eigen/Core>

#include "stridemap/render/grid_render.hpp"
#include "stridemap/render/png_image.hpp"

namespace stridemap::io {

struct HeatMapOptions {
  std::string title;
  std::string units;           ///< of the values, beside the colour bar
  std::string x_label, y_label;  ///< axis names, e.g. "height [cm]", "pitch [deg]"
  std::vector<std::string> x_ticks;  ///< one per column, left to right
  std::vector<std::string> y_ticks;  ///< one per row, bottom to top
  std::optional<double> min_value, max_value;
  ColourScale colour_scale = ColourScale::viridis;
  std::string missing_label = "no value";  ///< legend of NaN cells
  /// A cell to frame (row, column), e.g. the best one.
  std::optional<std::pair<int, int>> highlight;
  int pixels_per_cell = 36;
};

/// values(row, column): row = y index (bottom to top), column = x index
/// (left to right). Throws InputError for an empty grid or tick lists whose
/// lengths differ from the grid's.
RgbImage render_heat_map(const Eigen::MatrixXf& values, const HeatMapOptions& options);

}  // namespace stridemap::io
