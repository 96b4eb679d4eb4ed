// A user of MappingPipeline gets the foothold layers, kept current after
// every scan exactly as a recomputation from scratch would have them.
#include <cmath>
#include <cstring>

#include <gtest/gtest.h>

#include "pipeline_test_support.hpp"
#include "stridemap/core/foothold.hpp"
#include "stridemap/core/map_publisher.hpp"
#include "stridemap/pipeline/mapping_pipeline.hpp"

namespace stridemap {
namespace {

using test::floor_scan;
using test::pose_at;

void expect_as_recomputed(const ElevationMap& map, const FootholdOptions& options) {
  ElevationMap scratch = map;
  FootholdLayers(scratch, options).recompute_all(scratch);
  const std::size_t cells = static_cast<std::size_t>(map.cells_per_side()) * static_cast<std::size_t>(map.cells_per_side());
  for (const LayerSpec& spec : foothold_layer_specs()) {
    const std::size_t k = *map.find_layer(spec.name);
    EXPECT_EQ(std::memcmp(map.layer_bytes(k), scratch.layer_bytes(k), cells * sizeof(float)), 0) << spec.name;
  }
}

TEST(PipelineFoothold, ScansUpdateTheLayersAsARecomputationWould) {
  PipelineOptions options;
  MappingPipeline pipeline(options);
  ASSERT_NE(pipeline.foothold(), nullptr);
  // Walking forward and turning: the window moves, scan lines cross it.
  for (int k = 0; k < 40; ++k) pipeline.add(floor_scan(0.1 * k), pose_at(0.01 * k, 0.02 * k));
  const ElevationMap& map = pipeline.map();
  expect_as_recomputed(map, options.foothold);
  // The floor is flat: every known cell with a score has a slope within what
  // millimetre range steps give over a 2 cm foot, and a score in [0, 1].
  const auto score = map.layer<float>("foothold_score");
  const auto slope = map.layer<float>("slope_deg");
  std::size_t scored = 0;
  for (int i = 0; i < map.cells_per_side(); ++i) {
    for (int j = 0; j < map.cells_per_side(); ++j) {
      const CellIndex c = map.cell_at_local(i, j);
      const float value = map.data(score)[map.slot(c)];
      if (map.state(c) == CellState::unknown) {
        EXPECT_TRUE(std::isnan(value));
        continue;
      }
      if (std::isnan(value)) continue;
      ++scored;
      EXPECT_GE(value, 0.0f);
      EXPECT_LE(value, 1.0f);
      EXPECT_LT(map.data(slope)[map.slot(c)], 5.0f);
    }
  }
  EXPECT_GT(scored, 50u);
}

TEST(PipelineFoothold, LazyLayersReadEveryFewScansEqualThoseUpdatedEveryScan) {
  PipelineOptions eager_options, lazy_options;
  eager_options.foothold.update_every_scan = true;
  ASSERT_FALSE(lazy_options.foothold.update_every_scan) << "lazy is the default";
  MappingPipeline eager(eager_options), lazy(lazy_options);
  const auto bytes_equal = [](const ElevationMap& a, const ElevationMap& b) {
    const std::size_t cells = static_cast<std::size_t>(a.cells_per_side()) * static_cast<std::size_t>(a.cells_per_side());
    for (const LayerSpec& spec : foothold_layer_specs()) {
      const std::size_t k = *a.find_layer(spec.name);
      if (std::memcmp(a.layer_bytes(k), b.layer_bytes(k), cells * sizeof(float)) != 0) return false;
    }
    return true;
  };
  bool stale_seen = false;
  for (int k = 0; k < 60; ++k) {
    const TrunkPose pose = pose_at(0.01 * k, 0.03 * k);
    eager.add(floor_scan(0.1 * k), pose);
    lazy.add(floor_scan(0.1 * k), pose);
    ASSERT_TRUE(eager.foothold()->current());
    if (k % 7 != 6) {
      stale_seen = stale_seen || !bytes_equal(eager.mapper().map(), lazy.mapper().map());
      continue;
    }
    EXPECT_FALSE(lazy.foothold()->current());
    lazy.refresh_foothold();
    EXPECT_TRUE(lazy.foothold()->current());
    ASSERT_TRUE(bytes_equal(eager.mapper().map(), lazy.mapper().map())) << "after scan " << k;
  }
  // Before a refresh the lazy layers lag: the test can tell them apart.
  EXPECT_TRUE(stale_seen);
  lazy.refresh_foothold();
  expect_as_recomputed(lazy.mapper().map(), lazy_options.foothold);
}

TEST(PipelineFoothold, TheFilteredMapCarriesLayersOfTheFilledMap) {
  MappingPipeline pipeline(PipelineOptions{});
  for (int k = 0; k < 10; ++k) pipeline.add(floor_scan(0.1 * k), pose_at(0.01 * k));
  const ElevationMap filtered = pipeline.filtered_map();
  expect_as_recomputed(filtered, PipelineOptions{}.foothold);
  pipeline.apply_map_filter();
  expect_as_recomputed(pipeline.mapper().map(), PipelineOptions{}.foothold);
}

bool every_layer_equal(const ElevationMap& a, const ElevationMap& b) {
  if (a.min_cell() != b.min_cell() || a.layer_count() != b.layer_count()) return false;
  const std::size_t cells = static_cast<std::size_t>(a.cells_per_side()) * static_cast<std::size_t>(a.cells_per_side());
  for (std::size_t k = 0; k < a.layer_count(); ++k) {
    if (std::memcmp(a.layer_bytes(k), b.layer_bytes(k), cells * layer_type_bytes(a.layer_spec(k).type)) != 0) return false;
  }
  return true;
}

// map(), the accessor every reader takes, and a snapshot published from it
// give what an eager pipeline holds, however many scans went by unread.
TEST(PipelineFoothold, ReadersOfALazyPipelineGetTheEagerMap) {
  PipelineOptions eager_options, lazy_options;
  eager_options.foothold.update_every_scan = true;
  MappingPipeline eager(eager_options), lazy(lazy_options);
  MapPublisher eager_publisher(eager_options.mapper.grid), lazy_publisher(lazy_options.mapper.grid);
  bool stale_seen = false;
  for (int k = 0; k < 80; ++k) {
    const TrunkPose pose = pose_at(0.015 * k, 0.03 * k);
    eager.add(floor_scan(0.1 * k), pose);
    lazy.add(floor_scan(0.1 * k), pose);
    if (k % 10 != 9) continue;
    stale_seen = stale_seen || !every_layer_equal(eager.mapper().map(), lazy.mapper().map());
    ASSERT_TRUE(lazy_publisher.publish(lazy.mapper(), lazy.map()));
    ASSERT_TRUE(eager_publisher.publish(eager.mapper(), eager.map()));
    ASSERT_TRUE(every_layer_equal(eager.map(), lazy.map())) << "after scan " << k;
    ASSERT_TRUE(every_layer_equal(eager_publisher.latest()->map, lazy_publisher.latest()->map)) << "after scan " << k;
  }
  EXPECT_TRUE(stale_seen) << "the unread lazy layers must lag, or this test shows nothing";
}

TEST(PipelineFoothold, DisabledLeavesTheMapWithoutThem) {
  PipelineOptions options;
  options.foothold.enabled = false;
  MappingPipeline pipeline(options);
  EXPECT_EQ(pipeline.foothold(), nullptr);
  pipeline.add(floor_scan(0.0), pose_at(0.0));
  EXPECT_FALSE(pipeline.mapper().map().find_layer("foothold_score"));
}

TEST(PipelineFoothold, BadOptionsAreRefusedBeforeAnyScan) {
  PipelineOptions options;
  options.foothold.foot_radius_m = std::nan("");
  EXPECT_THROW(MappingPipeline{options}, InputError);
}

}  // namespace
}  // namespace stridemap
