#include "stridemap/core/top_point.hpp"

#include <limits>

namespace stridemap {

// Aggregates, not member assignments: GCC 12 warns falsely (-Wrestrict) on
// assigning a string literal to a member of a returned struct.
LayerSpec top_point_x_layer() {
  return {"top_point_x", LayerType::f32, std::numeric_limits<double>::quiet_NaN(), "m",
          "map-frame x of the reading that set the cell's elevation (sub-cell edges)", false};
}

LayerSpec top_point_y_layer() {
  return {"top_point_y", LayerType::f32, std::numeric_limits<double>::quiet_NaN(), "m",
          "map-frame y of the reading that set the cell's elevation (sub-cell edges)", false};
}

TopPoints::TopPoints(ElevationMap& map) {
  for (const LayerSpec& spec : {top_point_x_layer(), top_point_y_layer()}) {
    if (!map.find_layer(spec.name)) map.add_layer(spec);
  }
  x_ = map.layer<float>("top_point_x");
  y_ = map.layer<float>("top_point_y");
}

std::size_t TopPoints::note_all(ElevationMap& map, std::span<const Eigen::Vector3d> points_m) const {
  std::size_t set = 0;
  for (const Eigen::Vector3d& p : points_m) set += note(map, p.x(), p.y(), p.z()) ? 1 : 0;
  return set;
}

}  // namespace stridemap
