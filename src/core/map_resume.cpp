#include "stridemap/core/map_resume.hpp"

#include <cstring>
#include <sstream>

#include "stridemap/core/error.hpp"

namespace stridemap {

void resume_from_map(TerrainMapper& mapper, const ElevationMap& saved) {
  const ElevationMap& current = mapper.map();
  // Exact comparison on purpose: the saved map's cell size comes back bit
  // for bit, and a grid even slightly different would misplace every cell.
  if (current.cells_per_side() != saved.cells_per_side() || current.cell_size_m() != saved.cell_size_m()) {
    std::ostringstream message;
    message.precision(17);
    message << "cannot resume mapping: the saved map is " << saved.cells_per_side() << " x "
            << saved.cells_per_side() << " cells of " << saved.cell_size_m() << " m, the mapper's grid "
            << current.cells_per_side() << " x " << current.cells_per_side() << " cells of "
            << current.cell_size_m() << " m";
    throw InputError(message.str());
  }
  // The mapper's own registry, so that layer handles taken from its map stay
  // valid: each saved layer goes to the place of the layer of its name, a
  // layer only the file has is appended, one only the mapper has starts
  // from its reset value. Same grid and corner, so the same slots.
  ElevationMap resumed = current;
  resumed.clear();
  resumed.move_corner_to(saved.min_cell());
  const std::size_t cells = static_cast<std::size_t>(saved.cells_per_side()) * static_cast<std::size_t>(saved.cells_per_side());
  for (std::size_t k = 0; k < saved.layer_count(); ++k) {
    const LayerSpec& spec = saved.layer_spec(k);
    const std::size_t to = resumed.find_layer(spec.name).value_or(resumed.layer_count());
    if (to == resumed.layer_count()) resumed.add_layer(spec);
    if (resumed.layer_spec(to).type != spec.type) {
      throw InputError("cannot resume mapping: the saved map's layer '" + spec.name + "' holds " +
                       layer_type_name(spec.type) + ", the mapper's " + layer_type_name(resumed.layer_spec(to).type));
    }
    std::memcpy(resumed.layer_bytes(to), saved.layer_bytes(k), cells * layer_type_bytes(spec.type));
  }
  mapper.map() = std::move(resumed);
}

void resume_from_map(TerrainMapper& mapper, const ElevationMap& saved, std::optional<TrunkPose> last_pose,
                     std::optional<double> last_scan_time_s) {
  resume_from_map(mapper, saved);
  if (!last_pose) return;  // no scan was ever integrated: nothing to remember
  // The mapper learns the last scan's pose and time the one way it offers:
  // a scan of no points at that pose and time. The window is already where
  // that pose puts it (the saved map followed it), so no cell moves or
  // changes; only the scan count of totals() grows by one.
  mapper.integrate_points({}, *last_pose, last_scan_time_s);
}

MapperOptions options_for_map(MapperOptions options, const ElevationMap& saved) {
  options.grid.cells_per_side = saved.cells_per_side();
  options.grid.cell_size_m = saved.cell_size_m();
  return options;
}

}  // namespace stridemap
