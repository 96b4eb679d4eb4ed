#pragma once
// Keeps the top-point layers (core/top_point.hpp) of a pipeline's map the
// way a user's layer is kept: declared in the map options, written by a
// PipelineObserver from the points of each integrated scan.
#include "stridemap/core/top_point.hpp"
#include "stridemap/pipeline/mapping_pipeline.hpp"

namespace stridemap {

/// Adds the two layers to the map options (once; a no-op when they are there).
void declare_top_point_layers(GridOptions& grid);

class TopPointObserver final : public PipelineObserver {
 public:
  /// Declares the layers in the pipeline's map if the options did not,
  /// asks the integrator for its points and observes it. The pipeline must
  /// outlive the observer's use and the observer the pipeline's scans.
  explicit TopPointObserver(MappingPipeline& pipeline);
  void on_scan(const ScanReport& report) override;

 private:
  MappingPipeline& pipeline_;
  TopPoints layers_;
};

}  // namespace stridemap
