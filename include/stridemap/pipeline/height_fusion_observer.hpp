#pragma once
// Keeps a pipeline's fused height layers (core/height_fusion.hpp), from
// which a walking robot reads its own height where its feet stand
// (core/stance_height.hpp): declared in the map options like a user's
// layer, written by a PipelineObserver from the points of each integrated
// scan. The elevation and every other layer stay as they are, bit for bit.
#include "stridemap/core/height_fusion.hpp"
#include "stridemap/pipeline/mapping_pipeline.hpp"

namespace stridemap {

/// Adds "fused_elevation" and "fused_variance" to the map options (once; a
/// no-op when they are there). Declared before the pipeline is made, they
/// cost no allocation while it maps.
void declare_height_fusion_layers(GridOptions& grid);

class HeightFusionObserver final : public PipelineObserver {
 public:
  /// Declares the layers in the pipeline's map if the options did not,
  /// asks the integrator for its points and observes it. Validates the
  /// options (InputError naming the field). The pipeline must outlive the
  /// observer's use and the observer the pipeline's scans.
  explicit HeightFusionObserver(MappingPipeline& pipeline, const HeightFusionOptions& options = {});
  void on_scan(const ScanReport& report) override;

  const HeightFusion& fusion() const { return fusion_; }

 private:
  MappingPipeline& pipeline_;
  HeightFusion fusion_;
};

}  // namespace stridemap
