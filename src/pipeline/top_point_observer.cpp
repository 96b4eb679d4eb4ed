#include "stridemap/pipeline/top_point_observer.hpp"

namespace stridemap {

void declare_top_point_layers(GridOptions& grid) {
  for (const LayerSpec& spec : {top_point_x_layer(), top_point_y_layer()}) declare_layer_once(grid, spec);
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
