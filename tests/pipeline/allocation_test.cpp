// The pipeline's per-scan path allocates nothing once its buffers have
// grown: URG raw scans with tags through the scan-sequence delay, stripe
// frames and point frames, points handed back included. Global operator new
// is replaced in this test binary to count allocations while a flag is set.
#include <gtest/gtest.h>

#include "allocation_counting.hpp"

#include <cmath>
#include <cstdint>
#include <vector>

#include "pipeline_test_support.hpp"
#include "stridemap/core/stance_height.hpp"
#include "stridemap/pipeline/height_fusion_observer.hpp"
#include "stridemap/pipeline/mapping_pipeline.hpp"

STRIDEMAP_REPLACE_OPERATOR_NEW()

namespace stridemap {
namespace {

using test::allocation_counter;
using test::floor_scan;
using test::pose_at;

using test::Counting;

TEST(PipelineAllocation, UrgScansThroughTheFiltersAllocateNothing) {
  STRIDEMAP_SKIP_UNLESS_COUNTING_ALLOCATIONS();
  PipelineOptions options;
  options.filters = {ScanFilterKind::range_clustering, ScanFilterKind::scan_sequence};
  MappingPipeline pipeline(options);
  pipeline.integrator().set_collect_points(true);
  UrgRawScan raw = floor_scan(0.0);
  const std::vector<std::uint8_t> tags(raw.values_mm.size(), 1);
  for (int k = 0; k < 5; ++k) {
    raw.time_s = 0.1 * k;
    pipeline.add(raw, pose_at(0.002 * k, 0.01 * k), tags);
  }
  std::size_t allocations = 0;
  {
    Counting counting;
    for (int k = 5; k < 50; ++k) {
      raw.time_s = 0.1 * k;
      raw.values_mm[static_cast<std::size_t>(k)] = 0;  // the data change from scan to scan
      pipeline.add(raw, pose_at(0.002 * k, 0.01 * k), tags);
    }
    allocations = counting.allocations();
  }
  EXPECT_EQ(allocations, 0u);
  EXPECT_EQ(pipeline.stats().integrated, 49u);
}

// The packed route (no scan filters) with everything that reads a scan on
// it: tags, an observer, the visibility clean-up, and last_scan() now and then.
TEST(PipelineAllocation, UrgScansOnThePackedRouteAllocateNothing) {
  STRIDEMAP_SKIP_UNLESS_COUNTING_ALLOCATIONS();
  struct Observer : PipelineObserver {
    std::size_t removed = 0;
    void on_scan(const ScanReport& report) override { removed += report.removed.size(); }
  } observer;
  PipelineOptions options;
  options.visibility.enabled = true;
  MappingPipeline pipeline(options);
  pipeline.integrator().add_observer(observer);
  UrgRawScan raw = floor_scan(0.0);
  const std::vector<std::uint8_t> tags(raw.values_mm.size(), 1);
  const auto step = [&](int k) {
    raw.time_s = 0.1 * k;
    raw.values_mm[static_cast<std::size_t>(k)] = 0;  // the data change from scan to scan
    pipeline.add(raw, pose_at(0.002 * k, 0.01 * k), tags);
    if (k % 7 == 0) (void)pipeline.integrator().last_scan();
  };
  for (int k = 0; k < 8; ++k) step(k);
  std::size_t allocations = 0;
  {
    Counting counting;
    for (int k = 8; k < 60; ++k) step(k);
    allocations = counting.allocations();
  }
  EXPECT_EQ(allocations, 0u);
  EXPECT_EQ(pipeline.stats().integrated, 60u);
  EXPECT_EQ(observer.removed, 60u * raw.values_mm.size());
}

TEST(PipelineAllocation, FootholdLayersNotedPerScanAndRefreshedAllocateNothing) {
  STRIDEMAP_SKIP_UNLESS_COUNTING_ALLOCATIONS();
  for (const bool every_scan : {true, false}) {
    PipelineOptions options;
    options.foothold.update_every_scan = every_scan;
    MappingPipeline pipeline(options);
    ASSERT_NE(pipeline.foothold(), nullptr);
    UrgRawScan raw = floor_scan(0.0);
    for (int k = 0; k < 5; ++k) pipeline.add(floor_scan(0.1 * k), pose_at(0.01 * k, 0.02 * k));
    pipeline.refresh_foothold();
    std::size_t allocations = 0;
    {
      Counting counting;
      for (int k = 5; k < 60; ++k) {
        raw.time_s = 0.1 * k;
        pipeline.add(raw, pose_at(0.01 * k, 0.02 * k));  // walking and turning: the window moves
        if (k % 10 == 0) pipeline.refresh_foothold();
      }
      allocations = counting.allocations();
    }
    EXPECT_EQ(allocations, 0u) << (every_scan ? "every scan" : "lazy");
    EXPECT_GT(pipeline.foothold()->last_geometry_cells() + (every_scan ? 1u : 0u), 0u);
  }
}

// A walking robot's loop: the fused layers fed from each scan and the
// stance feet read before the next.
TEST(PipelineAllocation, FusedHeightsAndTheStanceReadingAllocateNothing) {
  STRIDEMAP_SKIP_UNLESS_COUNTING_ALLOCATIONS();
  PipelineOptions options;
  declare_height_fusion_layers(options.mapper.grid);
  MappingPipeline pipeline(options);
  const HeightFusionObserver fusion(pipeline);
  UrgRawScan raw = floor_scan(0.0);
  for (int k = 0; k < 5; ++k) {
    raw.time_s = 0.1 * k;
    pipeline.add(raw, pose_at(0.002 * k));
  }
  const ElevationMap& map = pipeline.mapper().map();
  const StanceHeightReader reader(map);
  const std::array<StanceFoot, 3> feet{{{0.3, 0.05, 0.2}, {0.35, -0.05, 0.2}, {0.4, 0.0, 0.2}}};
  std::size_t allocations = 0;
  int feet_used = 0;
  {
    Counting counting;
    for (int k = 5; k < 50; ++k) {
      feet_used += reader.read(map, feet).feet_used;
      raw.time_s = 0.1 * k;
      pipeline.add(raw, pose_at(0.002 * k));
    }
    allocations = counting.allocations();
  }
  EXPECT_EQ(allocations, 0u);
  EXPECT_EQ(pipeline.stats().integrated, 50u);
  EXPECT_GT(feet_used, 0);  // the feet stood on mapped floor
}

TEST(PipelineAllocation, StripeAndPointFramesAllocateNothing) {
  STRIDEMAP_SKIP_UNLESS_COUNTING_ALLOCATIONS();
  PipelineOptions sl_options;
  sl_options.sensor = SensorKind::structured_light;
  sl_options.mount = sl_options.structured_light.mount;
  MappingPipeline stripes(sl_options);
  StripeFrame frame;
  for (int u = 0; u < sl_options.structured_light.image_width_px; ++u) frame.pixels.push_back({u + 0.5, 300.0});

  PipelineOptions point_options;
  point_options.sensor = SensorKind::points;
  MappingPipeline points(point_options);
  PointFrame cloud;
  for (int i = 0; i < 200; ++i) {
    cloud.points_m.emplace_back(0.3 + 0.002 * i, 0.001 * i, -0.25);
    cloud.height_sigma_m.push_back(0.005);
  }
  const auto step = [&](int k) {
    frame.time_s = cloud.time_s = 0.04 * k;
    stripes.add(frame, pose_at(0.004 * k));
    points.add(cloud, pose_at(0.004 * k));
  };
  for (int k = 0; k < 3; ++k) step(k);
  std::size_t allocations = 0;
  {
    Counting counting;
    for (int k = 3; k < 30; ++k) step(k);
    allocations = counting.allocations();
  }
  EXPECT_EQ(allocations, 0u);
  EXPECT_GT(stripes.mapper().totals().integrated, 0u);
  EXPECT_GT(points.mapper().totals().integrated, 0u);
}

}  // namespace
}  // namespace stridemap
