// The visibility clean-up in the pipeline: an object the map holds but the
// sensor now sees through is cleared within the scans its certainty asks
// for, the foothold layers follow, a static floor loses nothing, and the
// per-scan path still allocates nothing.
#include <gtest/gtest.h>

#include "allocation_counting.hpp"

#include <cmath>
#include <cstring>

#include "pipeline_test_support.hpp"
#include "stridemap/core/foothold.hpp"
#include "stridemap/pipeline/mapping_pipeline.hpp"

// operator new is replaced once for this test program, in allocation_test.cpp.

namespace stridemap {
namespace {

using test::floor_scan;
using test::pose_at;

// A 10 cm "object" the floor scans no longer see: 5 x 4 cells just before
// the central beams' stripe (0.37 m ahead of the default mount), where the
// beams pass 1.5-5 cm above the floor.
void plant_object(ElevationMap& map, float certainty) {
  for (int i = 0; i < 5; ++i) {
    for (int j = 0; j < 4; ++j) {
      const std::size_t s = map.slot(map.cell_of(0.305 + 0.01 * i, -0.015 + 0.01 * j));
      map.elevation_data()[s] = 0.10f;
      map.certainty_data()[s] = certainty;
      map.state_data()[s] = static_cast<std::uint8_t>(CellState::measured);
    }
  }
}

std::size_t object_cells_standing(const ElevationMap& map) {
  std::size_t standing = 0;
  for (int i = 0; i < 5; ++i) {
    for (int j = 0; j < 4; ++j) standing += map.elevation(map.cell_of(0.305 + 0.01 * i, -0.015 + 0.01 * j)) > 0.05f;
  }
  return standing;
}

TEST(PipelineVisibility, AnObjectTakenAwayIsClearedAfterItsCertainty) {
  PipelineOptions options;
  options.visibility.enabled = true;
  MappingPipeline pipeline(options);
  pipeline.add(floor_scan(0.0), pose_at(0.0));
  plant_object(pipeline.mapper().map(), 9.0f);  // three readings' worth
  pipeline.recompute_foothold();
  for (int k = 1; k <= 2; ++k) {
    pipeline.add(floor_scan(0.1 * k), pose_at(0.0));
    EXPECT_EQ(object_cells_standing(pipeline.mapper().map()), 20u) << "scan " << k;
  }
  pipeline.add(floor_scan(0.3), pose_at(0.0));
  EXPECT_EQ(object_cells_standing(pipeline.mapper().map()), 0u);
  EXPECT_GE(pipeline.stats().cells_cleared, 20u);
  // The foothold layers saw the change (the cleared cells reach them).
  ElevationMap scratch = pipeline.mapper().map();
  FootholdLayers(scratch, options.foothold).recompute_all(scratch);
  const ElevationMap& map = pipeline.mapper().map();
  const std::size_t cells = static_cast<std::size_t>(map.cells_per_side()) * static_cast<std::size_t>(map.cells_per_side());
  for (const LayerSpec& spec : foothold_layer_specs()) {
    const std::size_t k = *map.find_layer(spec.name);
    EXPECT_EQ(std::memcmp(map.layer_bytes(k), scratch.layer_bytes(k), cells * sizeof(float)), 0) << spec.name;
  }
}

TEST(PipelineVisibility, OffTheObjectStays) {
  PipelineOptions options;
  options.visibility.enabled = false;
  MappingPipeline pipeline(options);
  pipeline.add(floor_scan(0.0), pose_at(0.0));
  plant_object(pipeline.mapper().map(), 9.0f);
  for (int k = 1; k <= 10; ++k) pipeline.add(floor_scan(0.1 * k), pose_at(0.0));
  EXPECT_EQ(object_cells_standing(pipeline.mapper().map()), 20u);
  EXPECT_EQ(pipeline.stats().cells_cleared, 0u);
}

TEST(PipelineVisibility, APlanarScanClearsToo) {
  PipelineOptions options;
  options.visibility.enabled = true;
  MappingPipeline pipeline(options);
  UrgModel urg(options.urg, options.calibration);
  PlanarScan scan;
  urg.to_planar_scan(floor_scan(0.0), scan);
  pipeline.add_planar(scan, pose_at(0.0));
  plant_object(pipeline.mapper().map(), 3.0f);
  scan.time_s = 0.1;
  pipeline.add_planar(scan, pose_at(0.0));
  EXPECT_EQ(object_cells_standing(pipeline.mapper().map()), 0u);
}

TEST(PipelineVisibility, AStaticFloorLosesNothingWhileWalkingAndTurning) {
  PipelineOptions options;
  options.visibility.enabled = true;
  MappingPipeline pipeline(options);
  for (int k = 0; k < 60; ++k) pipeline.add(floor_scan(0.1 * k), pose_at(0.01 * k, 0.01 * k));
  EXPECT_EQ(pipeline.stats().cells_contradicted, 0u);
  EXPECT_EQ(pipeline.stats().cells_cleared, 0u);
}

TEST(PipelineVisibility, PerScanPathAllocatesNothing) {
  STRIDEMAP_SKIP_UNLESS_COUNTING_ALLOCATIONS();
  PipelineOptions options;
  options.visibility.enabled = true;
  MappingPipeline pipeline(options);
  UrgRawScan raw = floor_scan(0.0);
  for (int k = 0; k < 5; ++k) {
    raw.time_s = 0.1 * k;
    pipeline.add(raw, pose_at(0.002 * k, 0.01 * k));
  }
  plant_object(pipeline.mapper().map(), 100.0f);  // contradicted every scan, recorded when cleared
  std::size_t allocations = 0;
  test::allocation_counter().allocations = 0;
  test::allocation_counter().counting = true;
  for (int k = 5; k < 50; ++k) {
    raw.time_s = 0.1 * k;
    pipeline.add(raw, pose_at(0.002 * k, 0.01 * k));
  }
  test::allocation_counter().counting = false;
  allocations = test::allocation_counter().allocations.load();
  EXPECT_EQ(allocations, 0u);
  EXPECT_GT(pipeline.stats().cells_contradicted, 0u);
}

}  // namespace
}  // namespace stridemap
