#include "stridemap/core/height_fusion.hpp"

#include <limits>
#include <string>

#include "stridemap/core/error.hpp"

namespace stridemap {

void HeightFusionOptions::validate() const {
  const std::pair<const char*, double> fields[] = {{"mahalanobis_gate", mahalanobis_gate},
                                                   {"outlier_variance_m2", outlier_variance_m2},
                                                   {"min_variance_m2", min_variance_m2},
                                                   {"sigma_per_uncertainty", sigma_per_uncertainty}};
  for (const auto& [field, value] : fields) {
    if (!(std::isfinite(value) && value > 0.0)) {
      throw InputError(std::string("height fusion options: ") + field + ": expected a positive number, got " +
                       std::to_string(value));
    }
  }
}

// Aggregates, not member assignments: GCC 12 warns falsely (-Wrestrict) on
// assigning a string literal to a member of a returned struct.
LayerSpec fused_elevation_layer() {
  return {"fused_elevation", LayerType::f32, std::numeric_limits<double>::quiet_NaN(), "m",
          "variance-weighted mean of the readings within the Mahalanobis gate (the robot's h_ref)", false};
}

LayerSpec fused_variance_layer() {
  return {"fused_variance", LayerType::f32, std::numeric_limits<double>::quiet_NaN(), "m^2",
          "variance of fused_elevation", false};
}

HeightFusion::HeightFusion(ElevationMap& map, const HeightFusionOptions& options) : options_(options) {
  options_.validate();
  for (const LayerSpec& spec : {fused_elevation_layer(), fused_variance_layer()}) {
    if (!map.find_layer(spec.name)) map.add_layer(spec);
  }
  elevation_ = map.layer<float>("fused_elevation");
  variance_ = map.layer<float>("fused_variance");
}

}  // namespace stridemap
