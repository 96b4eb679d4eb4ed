#pragma once
// A 3D picture of an elevation map (the paper's Fig. 22b view): the map's
// cells as a shaded surface seen obliquely through a perspective camera,
// coloured by elevation. A small painter's-algorithm renderer on OpenCV's
// polygon fill; no 3D library.
#include <array>
#include <cstdint>
#include <optional>
#include <string>

#include <Eigen/Core>

#include "stridemap/render/grid_render.hpp"
#include "stridemap/render/png_image.hpp"

namespace stridemap::io {

struct TerrainViewOptions {
  std::string title;             ///< drawn at the top; empty draws none
  int width_px = 900;
  int height_px = 650;
  /// Direction the camera looks from, counter-clockwise from +X (the map's
  /// forward) seen from above [deg]. -150: from behind and to the right of
  /// a robot walking along +X.
  double azimuth_deg = -150.0;
  /// The camera's angle above the horizontal [deg], in (0, 90].
  double elevation_deg = 35.0;
  /// Vertical field of view [deg], in (0, 120).
  double field_of_view_deg = 30.0;
  /// Heights are drawn this many times taller than they are, so that a few
  /// centimetres of relief over metres of map can be seen (> 0).
  double vertical_exaggeration = 2.0;
  /// Ends of the colour scale [m]; empty: from the data.
  std::optional<double> min_value, max_value;
  ColourScale colour_scale = ColourScale::viridis;
  /// A panel to the right of the view (the image grows by kTerrainLegendWidthPx):
  /// the colour bar with its range, what holes and paler cells are, and, in
  /// the view, x and y axes of a round length at the map's corner as scale.
  bool legend = true;
  /// Behind the surface; unknown cells are holes through which it shows.
  std::array<std::uint8_t, 3> background_rgb{226, 232, 240};
};

inline constexpr int kTerrainLegendWidthPx = 190;

/// Renders `elevation_m` (row = +X, column = +Y, cell_size_m apart; NaN =
/// unknown, left as a hole). Cells flagged in `filled` are drawn paler.
/// Throws InputError for an empty grid, a shape mismatch, or an option out
/// of range.
RgbImage render_terrain_view(const Eigen::MatrixXf& elevation_m, const CellMask& filled, double cell_size_m,
                             const TerrainViewOptions& options = {});

}  // namespace stridemap::io
