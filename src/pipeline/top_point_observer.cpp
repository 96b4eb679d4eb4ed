#include "stridemap/pipeline/top_point_observer.hpp"

#include <algorithm>

namespace stridemap {

void declare_top_point_layers(GridOptions& grid) {
  for (const LayerSpec& spec : {top_point_x_layer(), top_point_y_layer()}) {
    const bool there = std::any_of(grid.extra_layers.begin(), grid.extra_layers.end(),
                                   [&](const LayerSpec& l) { return l.name == spec.name; });
    if (!there) grid.extra_layers.push_back(spec);
  }
}

TopPointObserver::TopPointObserver(MappingPipeline& pipeline)
    : pipeline_(pipeline), layers_(pipeline.mapper().map()) {
  pipeline_.integrator().set_collect_points(true);
  pipeline_.integrator().add_observer(*this);
}

void TopPointObserver::on_scan(const ScanReport&) {
  ElevationMap& map = pipeline_.mapper().map();
  for (const IntegratedPoint& p : pipeline_.integrator().last_points()) layers_.note(map, p.map_m.x(), p.map_m.y(), p.map_m.z());
}

}  // namespace stridemap
