// The visibility clean-up in the pipeline: an object the map holds but the
// sensor now sees through is cleared within the scans its certainty asks
// for, the foothold layers follow, a static floor loses nothing, and the
// per-scan path still allocates nothing.
#include <gtest/gtest.h>

#include "allocation_counting.hpp"

#include <cmath>
#include <cstring>
#include <random>

#include "pipeline_test_support.hpp"
#include "stridemap/core/foothold.hpp"
#include "stridemap/pipeline/mapping_pipeline.hpp"
#include "stridemap/pipeline/scan_integrator.hpp"

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
  // The foothold layers, read, saw the change (the cleared cells reach them).
  const ElevationMap& map = pipeline.map();
  ElevationMap scratch = map;
  FootholdLayers(scratch, options.foothold).recompute_all(scratch);
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

// The clean-up takes the hits the mapper's packed pass formed; after the
// per-point route there are none and it forms them itself. Both must leave
// every layer the same, bit for bit, scan after scan of a turning walk
// with a tilting trunk and an object to clear.
TEST(PipelineVisibility, PackedHitsClearAsBeamsFormedAgain) {
  PipelineOptions options;
  options.mapper.window_ahead_m = 0.3;
  options.visibility.enabled = true;
  TerrainMapper packed(options.mapper, options.mount), formed(options.mapper, options.mount);
  ScanIntegrator with_hits(options), without_hits(options);
  PlanarScan scan;
  scan.resize(682);
  for (std::size_t i = 0; i < scan.size(); ++i) {
    const double t = (static_cast<double>(i) + 44.0 - 384.0) * 2.0 * M_PI / 1024.0;
    const double down = std::cos(t) * std::sin(options.mount.pitch_rad);
    scan.angle_rad[i] = t;
    scan.range_m[i] = down > 0.1 ? options.mount.height_m / down * (i % 50 < 10 ? 0.8 : 1.0) : NAN;
    scan.range_error_m[i] = 0.01;
  }
  std::mt19937_64 rng(3);
  std::normal_distribution<double> tilt(0.0, 0.02);
  const auto no_sink = [](std::size_t, const Eigen::Vector3d&, const SensorPoint&) {};
  TrunkPose pose;
  for (int k = 0; k < 300; ++k) {
    pose.x_m += 0.003;
    pose.yaw_rad += 0.002;
    pose.pitch_rad = tilt(rng);
    pose.roll_rad = tilt(rng);
    scan.time_s += 0.1;
    packed.integrate(scan, pose);
    if (k > 0) ASSERT_NE(packed.last_beam_hits(), nullptr);  // asked for by the first scan's clean-up
    with_hits.clear_visible(scan, pose, packed);
    formed.integrate(scan, pose, no_sink);
    ASSERT_EQ(formed.last_beam_hits(), nullptr);
    without_hits.clear_visible(scan, pose, formed);
    if (k == 1) {
      plant_object(packed.map(), 3.0f);
      plant_object(formed.map(), 3.0f);
    }
    const ElevationMap& a = std::as_const(packed).map();
    const ElevationMap& b = std::as_const(formed).map();
    ASSERT_EQ(a.min_cell(), b.min_cell());
    const auto cells = static_cast<std::size_t>(a.cells_per_side()) * static_cast<std::size_t>(a.cells_per_side());
    for (std::size_t l = 0; l < a.layer_count(); ++l) {
      ASSERT_EQ(std::memcmp(a.layer_bytes(l), b.layer_bytes(l), cells * layer_type_bytes(a.layer_spec(l).type)), 0)
          << "scan " << k << ", layer " << a.layer_spec(l).name;
    }
  }
  EXPECT_GT(with_hits.stats().cells_cleared, 0u);
  EXPECT_EQ(with_hits.stats().cells_cleared, without_hits.stats().cells_cleared);
  EXPECT_EQ(with_hits.stats().cells_contradicted, without_hits.stats().cells_contradicted);
}

}  // namespace
}  // namespace stridemap
