#include "stridemap/core/exported_map.hpp"

#include "stridemap/core/error.hpp"

namespace stridemap {
namespace {

template <typename T, typename Matrix>
void copy_out(const ElevationMap& map, LayerId<T> id, Matrix& out) {
  const int n = map.cells_per_side();
  out.resize(n, n);
  const T* data = map.data(id);
  for (int i = 0; i < n; ++i) {
    for (int j = 0; j < n; ++j) out(i, j) = data[map.slot(map.cell_at_local(i, j))];
  }
}

ExportedLayer export_layer(const ElevationMap& map, std::size_t index) {
  ExportedLayer layer;
  layer.spec = map.layer_spec(index);
  switch (layer.spec.type) {
    case LayerType::f32: copy_out(map, LayerId<float>{index}, layer.f32); break;
    case LayerType::u16: copy_out(map, LayerId<std::uint16_t>{index}, layer.u16); break;
    case LayerType::u8: copy_out(map, LayerId<std::uint8_t>{index}, layer.u8); break;
  }
  return layer;
}

ExportedMap empty_export(const ElevationMap& map) {
  ExportedMap out;
  out.min_cell = map.min_cell();
  out.cell_size_m = map.cell_size_m();
  out.cells_per_side = map.cells_per_side();
  return out;
}

}  // namespace

const ExportedLayer* ExportedMap::find(std::string_view name) const {
  for (const ExportedLayer& l : layers) {
    if (l.spec.name == name) return &l;
  }
  return nullptr;
}

ExportedLayer* ExportedMap::find(std::string_view name) {
  return const_cast<ExportedLayer*>(static_cast<const ExportedMap*>(this)->find(name));
}

std::string ExportedMap::layer_names() const {
  std::string names;
  for (const ExportedLayer& l : layers) names += (names.empty() ? "" : ", ") + l.spec.name;
  return names;
}

const ExportedLayer& ExportedMap::layer(std::string_view name) const {
  if (const ExportedLayer* found = find(name)) return *found;
  throw InputError("exported map: no layer '" + std::string(name) + "'; it holds " +
                   (layers.empty() ? std::string("none") : layer_names()));
}

ExportedLayer& ExportedMap::layer(std::string_view name) {
  return const_cast<ExportedLayer&>(static_cast<const ExportedMap*>(this)->layer(name));
}

ExportedMap export_map(const ElevationMap& map) {
  ExportedMap out = empty_export(map);
  for (std::size_t k = 0; k < map.layer_count(); ++k) {
    if (map.layer_spec(k).exported) out.layers.push_back(export_layer(map, k));
  }
  return out;
}

ExportedMap export_map(const ElevationMap& map, std::span<const std::string> layer_names) {
  ExportedMap out = empty_export(map);
  for (const std::string& name : layer_names) {
    const auto index = map.find_layer(name);
    if (!index) throw InputError("no map layer '" + name + "'; the map has " + map.layer_names());
    out.layers.push_back(export_layer(map, *index));
  }
  return out;
}

double map_coverage(const ExportedMap& map) {
  const CellMask& state = map.state();
  if (state.size() == 0) return 0.0;
  return static_cast<double>((state.array() != static_cast<std::uint8_t>(CellState::unknown)).count()) /
         static_cast<double>(state.size());
}

}  // namespace stridemap
