#include "stridemap/pipeline/height_fusion_observer.hpp"

namespace stridemap {

void declare_height_fusion_layers(GridOptions& grid) {
  for (const LayerSpec& spec : {fused_elevation_layer(), fused_variance_layer()}) declare_layer_once(grid, spec);
}

HeightFusionObserver::HeightFusionObserver(MappingPipeline& pipeline, const HeightFusionOptions& options)
    : pipeline_(pipeline), fusion_(pipeline.mapper().map(), options) {
  pipeline_.integrator().set_collect_points(true);
  pipeline_.integrator().add_observer(*this);
}

void HeightFusionObserver::on_scan(const ScanReport&) {
  // The fused layers only: not a change of the elevation the mapper counts.
  ElevationMap& map = pipeline_.mapper().map_without_raising();
  const HeightFusion::Layers cells = fusion_.layers(map);
  for (const IntegratedPoint& p : pipeline_.integrator().last_points()) {
    fusion_.add(map, cells, p.map_m.x(), p.map_m.y(), p.map_m.z(), p.height_uncertainty_m);
  }
}

}  // namespace stridemap
