#include "stridemap/mapfile/map_outputs.hpp"

#include <cmath>
#include <filesystem>
#include <string>
#include <system_error>

#include "stridemap/core/error.hpp"
#include "stridemap/mapfile/grid_csv.hpp"
#include "stridemap/render/grid_render.hpp"
#include "stridemap/render/png_image.hpp"

namespace stridemap::io {

void write_map_layers(const ExportedMap& s, const std::string& directory, const MapOutputOptions& options) {
  const std::filesystem::path dir(directory);
  std::error_code ec;
  std::filesystem::create_directories(dir, ec);
  if (ec) throw InputError(dir.string() + ": cannot create the output folder: " + ec.message());

  const stridemap::CellMask& states = s.state();
  CellMask filled(states.rows(), states.cols());
  Eigen::MatrixXf certainty = s.certainty();
  for (Eigen::Index i = 0; i < states.rows(); ++i) {
    for (Eigen::Index j = 0; j < states.cols(); ++j) {
      const auto state = static_cast<CellState>(states(i, j));
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
  elevation_style.robust_range = true;
  write_png((dir / "elevation.png").string(), render_grid(s.elevation_m(), filled, elevation_style).image);

  GridRenderOptions certainty_style;
  certainty_style.title = "Certainty";
  certainty_style.cell_size_m = s.cell_size_m;
  certainty_style.min_value = 0.0;
  certainty_style.max_value = options.certainty_max;
  write_png((dir / "certainty.png").string(), render_grid(certainty, certainty_style).image);

  // The foothold layers (core/foothold.hpp), when the map has them, each on
  // a fixed scale so that images of different runs compare.
  struct FootholdImage {
    const char* layer;
    const char* title;
    const char* units;
    double max_value;
  };
  for (const FootholdImage& f : {FootholdImage{"foothold_score", "Foothold score", "", 1.0},
                                 FootholdImage{"slope_deg", "Slope", "deg", 45.0},
                                 FootholdImage{"step_height_m", "Step height", "m", 0.1}}) {
    const ExportedLayer* layer = s.find(f.layer);
    if (!layer || layer->spec.type != LayerType::f32) continue;
    GridRenderOptions style;
    style.title = f.title;
    style.units = f.units;
    style.cell_size_m = s.cell_size_m;
    style.min_value = 0.0;
    style.max_value = f.max_value;
    write_png((dir / (std::string(f.layer) + ".png")).string(), render_grid(layer->f32, style).image);
  }

  const Eigen::Vector2d origin = s.cell_center(0, 0);
  const auto csv = [&](const std::string& name, const Eigen::MatrixXf& values, const std::string& units) {
    GridCsvOptions o;
    o.layer_name = name;
    o.units = units;
    o.cell_size_m = s.cell_size_m;
    o.origin_x_m = origin.x();
    o.origin_y_m = origin.y();
    write_grid_csv((dir / (name + ".csv")).string(), values, o);
  };
  // Every layer the export holds, a user's own included.
  for (const ExportedLayer& layer : s.layers) {
    switch (layer.spec.type) {
      case LayerType::f32: csv(layer.spec.name, layer.f32, layer.spec.unit); break;
      case LayerType::u16: csv(layer.spec.name, layer.u16.cast<float>(), layer.spec.unit); break;
      case LayerType::u8: csv(layer.spec.name, layer.u8.cast<float>(), layer.spec.unit); break;
    }
  }
}

}  // namespace stridemap::io
