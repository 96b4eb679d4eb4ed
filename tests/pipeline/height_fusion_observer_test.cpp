// A walking robot's height from its own map, as a user wires it: the
// pipeline keeps the fused layers beside the paper's, and the stance feet
// read them.
#include "stridemap/pipeline/height_fusion_observer.hpp"

#include <cmath>
#include <vector>

#include <gtest/gtest.h>

#include "pipeline_test_support.hpp"
#include "stridemap/core/error.hpp"
#include "stridemap/core/stance_height.hpp"

namespace stridemap {
namespace {

PipelineOptions floor_options(bool fused_layers) {
  PipelineOptions options;
  options.mapper.follow_robot = false;
  if (fused_layers) declare_height_fusion_layers(options.mapper.grid);
  return options;
}

void map_the_floor(MappingPipeline& pipeline) {
  for (int k = 0; k < 20; ++k) pipeline.add(test::floor_scan(0.1 * k), test::pose_at(0.01 * k));
}

TEST(HeightFusionObserver, FusesEveryIntegratedPointAndLeavesThePapersLayersAsTheyWere) {
  PipelineOptions options = floor_options(true);
  declare_height_fusion_layers(options.mapper.grid);  // twice: declared once
  MappingPipeline pipeline(options);
  const HeightFusionObserver observer(pipeline);
  map_the_floor(pipeline);
  MappingPipeline plain(floor_options(false));
  map_the_floor(plain);

  const ElevationMap& map = pipeline.mapper().map();
  const ElevationMap& reference = plain.mapper().map();
  ASSERT_EQ(map.layer_count(), reference.layer_count() + 2);
  const float* fused = map.data(observer.fusion().elevation_layer());
  const std::size_t cells = static_cast<std::size_t>(map.cells_per_side()) * static_cast<std::size_t>(map.cells_per_side());
  std::size_t fused_cells = 0;
  for (std::size_t s = 0; s < cells; ++s) {
    // Fused where, and only where, a reading landed; the floor is z = 0 (to
    // the millimetre of the URG's ranges).
    ASSERT_EQ(std::isnan(fused[s]), map.state_data()[s] == static_cast<std::uint8_t>(CellState::unknown)) << s;
    if (std::isnan(fused[s])) continue;
    ++fused_cells;
    EXPECT_NEAR(fused[s], 0.0, 0.002) << s;
    ASSERT_EQ(map.elevation_data()[s], reference.elevation_data()[s]) << s;
    ASSERT_EQ(map.certainty_data()[s], reference.certainty_data()[s]) << s;
  }
  EXPECT_GT(fused_cells, 100u);

  // The robot's trunk, 0.1 m above three feet on mapped floor.
  const StanceHeightReader reader(map);
  std::vector<StanceFoot> whole_soles;
  for (std::size_t s = 0; s < cells; ++s) {
    const CellIndex c = map.cell_at_local(static_cast<int>(s) / map.cells_per_side(), static_cast<int>(s) % map.cells_per_side());
    const double x = (c.x + 0.5) * map.cell_size_m(), y = (c.y + 0.5) * map.cell_size_m();
    const std::optional<SoleGround> ground = reader.ground_under(map, x, y);
    if (ground && ground->known_share == 1.0) whole_soles.push_back({x, y, 0.1});
  }
  ASSERT_GE(whole_soles.size(), 3u);
  const std::vector<StanceFoot> feet{whole_soles.front(), whole_soles[whole_soles.size() / 2], whole_soles.back()};
  ASSERT_EQ(feet.size(), 3u);
  const StanceHeight height = StanceHeightReader(map).read(map, feet);
  EXPECT_EQ(height.feet_used, 3);
  EXPECT_NEAR(height.trunk_z_m, 0.1, 0.002);
}

// A scan already in its plane (a ROS LaserScan) reaches the observers too.
TEST(HeightFusionObserver, PlanarScansAreFusedAsEveryOtherScan) {
  MappingPipeline pipeline(floor_options(true));
  const HeightFusionObserver observer(pipeline);
  struct Count final : PipelineObserver {
    int scans = 0;
    void on_scan(const ScanReport&) override { ++scans; }
  } count;
  pipeline.integrator().add_observer(count);
  const UrgModel urg(UrgParameters{});
  PlanarScan scan;
  for (int k = 0; k < 5; ++k) {
    urg.to_planar_scan(test::floor_scan(0.1 * k), scan);
    pipeline.add_planar(scan, test::pose_at(0.01 * k));
  }
  EXPECT_EQ(count.scans, 5);
  EXPECT_EQ(pipeline.stats().integrated, 5u);
  const ElevationMap& map = pipeline.mapper().map();
  const float* fused = map.data(observer.fusion().elevation_layer());
  const std::size_t cells = static_cast<std::size_t>(map.cells_per_side()) * static_cast<std::size_t>(map.cells_per_side());
  std::size_t fused_cells = 0;
  for (std::size_t s = 0; s < cells; ++s) {
    if (std::isnan(fused[s])) continue;
    ++fused_cells;
    EXPECT_NEAR(fused[s], 0.0, 0.002) << s;
  }
  EXPECT_GT(fused_cells, 50u);
}

TEST(HeightFusionObserver, BadOptionsAreRefusedNamingTheField) {
  MappingPipeline pipeline(floor_options(true));
  HeightFusionOptions bad;
  bad.mahalanobis_gate = 0.0;
  try {
    const HeightFusionObserver observer(pipeline, bad);
    FAIL() << "a gate of 0 was taken";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("mahalanobis_gate"), std::string::npos) << e.what();
  }
}

// The switch every front end sets (the config's height_fusion.enabled,
// Python's fused_heights, the ROS node's ~layers): the pipeline keeps the
// layers itself, as an observer a user attaches would.
TEST(HeightFusionObserver, ThePipelinesOwnSwitchKeepsTheSameLayers) {
  PipelineOptions options = floor_options(false);
  EXPECT_EQ(MappingPipeline(options).height_fusion(), nullptr);
  options.height_fusion.enabled = true;
  MappingPipeline owned(options);
  ASSERT_NE(owned.height_fusion(), nullptr);
  MappingPipeline attached(floor_options(true));
  const HeightFusionObserver observer(attached);
  map_the_floor(owned);
  map_the_floor(attached);
  const ElevationMap& a = owned.map();
  const ElevationMap& b = attached.map();
  ASSERT_EQ(a.layer_count(), b.layer_count());
  const std::size_t cells = static_cast<std::size_t>(a.cells_per_side()) * static_cast<std::size_t>(a.cells_per_side());
  const float* fused_a = a.data(owned.height_fusion()->elevation_layer());
  const float* fused_b = b.data(observer.fusion().elevation_layer());
  const float* variance_a = a.data(owned.height_fusion()->variance_layer());
  const float* variance_b = b.data(observer.fusion().variance_layer());
  std::size_t fused_cells = 0;
  for (std::size_t s = 0; s < cells; ++s) {
    ASSERT_EQ(std::isnan(fused_a[s]), std::isnan(fused_b[s])) << s;
    if (std::isnan(fused_a[s])) continue;
    ++fused_cells;
    ASSERT_EQ(fused_a[s], fused_b[s]) << s;
    ASSERT_EQ(variance_a[s], variance_b[s]) << s;
  }
  EXPECT_GT(fused_cells, 100u);

  options.height_fusion.min_variance_m2 = -1.0;
  try {
    const MappingPipeline refused(options);
    FAIL() << "a negative variance floor was taken";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("min_variance_m2"), std::string::npos) << e.what();
  }
  options.height_fusion.enabled = false;  // not kept: not checked
  EXPECT_NO_THROW(MappingPipeline{options});
}

}  // namespace
}  // namespace stridemap
