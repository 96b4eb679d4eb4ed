// A scan filter registered from the test tree runs in the mapping pipeline,
// chosen by name like a built-in one (docs/architecture.md, "Adding a scan
// filter").
#include <cstdint>
#include <memory>
#include <vector>

#include <gtest/gtest.h>

#include "pipeline_test_support.hpp"
#include "stridemap/pipeline/mapping_pipeline.hpp"
#include "stridemap/preprocess/scan_filter_registry.hpp"

namespace stridemap {
namespace {

class DropOddBeams final : public ScanFilterStage {
 public:
  ScanFilterStats apply(PlanarScan& scan, std::vector<std::uint8_t>& removed) override {
    ScanFilterStats stats;
    stats.beams = scan.size();
    removed.assign(scan.size(), 0);
    for (std::size_t i = 1; i < scan.size(); i += 2) removed[i] = 1;
    stats.removed = apply_removal_mask(scan, removed);
    return stats;
  }
};

const ScanFilterRegistrar drop_odd_beams({
    "drop-odd-beams",
    "drops every other beam",
    {},
    [](const ScanFilterChainOptions&, const ScanFilterParameters&) -> std::unique_ptr<ScanFilterStage> {
      return std::make_unique<DropOddBeams>();
    },
});

class RemovedRecorder final : public PipelineObserver {
 public:
  void on_scan(const ScanReport& report) override { removed.assign(report.removed.begin(), report.removed.end()); }
  std::vector<std::uint8_t> removed;
};

TEST(RegisteredScanFilter, RunsInThePipelineByName) {
  PipelineOptions options;
  options.filters = parse_scan_filter_list("drop-odd-beams");
  MappingPipeline filtered(options);
  RemovedRecorder recorder;
  filtered.integrator().add_observer(recorder);
  for (int k = 0; k < 3; ++k) {
    filtered.add(test::floor_scan(0.1 * k), test::pose_at(0.01 * k));
  }
  ASSERT_FALSE(recorder.removed.empty());
  std::size_t odd_removed = 0;
  for (std::size_t i = 0; i < recorder.removed.size(); ++i) {
    if (i % 2 == 0) EXPECT_EQ(recorder.removed[i], 0) << i;
    odd_removed += recorder.removed[i];
  }
  EXPECT_GT(odd_removed, 0u);
  EXPECT_EQ(filtered.stats().integrated, 3u);
}

}  // namespace
}  // namespace stridemap
