#include "stridemap/io/map_outputs.hpp"

#include <cmath>
#include <filesystem>
#include <system_error>

#include "stridemap/core/error.hpp"
#include "stridemap/io/grid_csv.hpp"
#include "stridemap/io/grid_render.hpp"
#include "stridemap/io/png_image.hpp"

namespace stridemap::io {

MapLayers export_map_layers(const ElevationMap& map) {
  MapLayers layers;
  map.export_layers(&layers.elevation_m, &layers.certainty, &layers.state);
  layers.min_cell = map.min_cell();
  layers.cell_size_m = map.cell_size_m();
  return layers;
}

double map_coverage(const MapLayers& layers) {
  if (layers.state.size() == 0) return 0.0;
  const auto known = (layers.state.array() != static_cast<std::uint8_t>(CellState::unknown)).count();
  return static_cast<double>(known) / static_cast<double>(layers.state.size());
}

void write_map_layers(const MapLayers& s, const std::string& directory, const MapOutputOptions& options) {
  const std::filesystem::path dir(directory);
  std::error_code ec;
  std::filesystem::create_directories(dir, ec);
  if (ec) throw InputError(dir.string() + ": cannot create the output folder: " + ec.message());

  CellMask filled(s.state.rows(), s.state.cols());
  Eigen::MatrixXf certainty = s.certainty;
  for (Eigen::Index i = 0; i < s.state.rows(); ++i) {
    for (Eigen::Index j = 0; j < s.state.cols(); ++j) {
      const auto state = static_cast<CellState>(s.state(i, j));
      filled(i, j) = state == CellState::filled;
      if (state == CellState::unknown) certainty(i, j) = NAN;
    }
  }

  GridRenderOptions elevation_style;
  elevation_style.title = options.elevation_title;
  elevation_style.units = std::string(1, 'm');
  elevation_style.cell_size_m = s.cell_size_m;
  elevation_style.min_value = options.elevation_min_m;
  elevation_style.max_value = options.elevation_max_m;
  write_png((dir / "elevation.png").string(), render_grid(s.elevation_m, filled, elevation_style).image);

  GridRenderOptions certainty_style;
  certainty_style.title = "Certainty";
  certainty_style.cell_size_m = s.cell_size_m;
  certainty_style.min_value = 0.0;
  certainty_style.max_value = options.certainty_max;
  write_png((dir / "certainty.png").string(), render_grid(certainty, certainty_style).image);

  const double origin_x = (static_cast<double>(s.min_cell.x) + 0.5) * s.cell_size_m;
  const double origin_y = (static_cast<double>(s.min_cell.y) + 0.5) * s.cell_size_m;
  const auto csv = [&](const char* name, const Eigen::MatrixXf& values, const char* units) {
    GridCsvOptions o;
    o.layer_name = name;
    o.units = units;
    o.cell_size_m = s.cell_size_m;
    o.origin_x_m = origin_x;
    o.origin_y_m = origin_y;
    write_grid_csv((dir / (std::string(name) + ".csv")).string(), values, o);
  };
  csv("elevation", s.elevation_m, "m");
  csv("certainty", s.certainty, "");
  csv("state", s.state.cast<float>(), "");
}

}  // namespace stridemap::io
