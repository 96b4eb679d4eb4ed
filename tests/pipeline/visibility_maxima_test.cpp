// The visibility clean-up's row and column maxima kept up to date from the
// mapper's changed rows (core/visibility_clearing.hpp, begin_scan(mapper)):
// the results are those of maxima taken from the whole map every scan, bit
// for bit, on a walk that turns, moves the window and clears an object; and
// every change the changed rows do not show (a write through map(), a
// window move with a listener, a clear of the rows before the clean-up saw
// them, another mapper) makes the clean-up look at the whole map. Each of
// those tests puts an object where the beams pass below it that only the
// whole map shows: with the change not counted, the object is not
// contradicted.
#include <gtest/gtest.h>

#include <cstring>
#include <utility>
#include <vector>

#include "pipeline_test_support.hpp"
#include "stridemap/pipeline/mapping_pipeline.hpp"

namespace stridemap {
namespace {

using test::floor_scan;
using test::pose_at;

// A 10 cm object of 5 x 4 cells 0.305-0.345 m ahead of a robot at x_m
// (yaw 0), where the default mount's central beams pass 1.5-5 cm above the
// floor on their way to the stripe 0.37 m ahead.
std::vector<CellIndex> object_cells(const ElevationMap& map, double x_m) {
  std::vector<CellIndex> cells;
  for (int i = 0; i < 5; ++i) {
    for (int j = 0; j < 4; ++j) cells.push_back(map.cell_of(x_m + 0.305 + 0.01 * i, -0.015 + 0.01 * j));
  }
  return cells;
}

void plant_object(ElevationMap& map, double x_m, float certainty = 100.0f) {
  for (const CellIndex c : object_cells(map, x_m)) {
    const std::size_t s = map.slot(c);
    map.elevation_data()[s] = 0.10f;
    map.certainty_data()[s] = certainty;
    map.state_data()[s] = static_cast<std::uint8_t>(CellState::measured);
  }
}

bool same_layers(const ElevationMap& a, const ElevationMap& b) {
  const std::size_t cells = static_cast<std::size_t>(a.cells_per_side()) * static_cast<std::size_t>(a.cells_per_side());
  return a.min_cell() == b.min_cell() &&
         std::memcmp(a.elevation_data(), b.elevation_data(), cells * sizeof(float)) == 0 &&
         std::memcmp(a.certainty_data(), b.certainty_data(), cells * sizeof(float)) == 0 &&
         std::memcmp(a.state_data(), b.state_data(), cells) == 0;
}

const VisibilityStats& last(const MappingPipeline& pipeline) { return pipeline.integrator().visibility()->stats(); }

PipelineOptions visibility_on(bool follow_robot) {
  PipelineOptions options;
  options.visibility.enabled = true;
  options.mapper.follow_robot = follow_robot;
  return options;
}

TEST(VisibilityMaxima, KeptFromTheChangedRowsTheResultsAreTheWholeMapsBitForBit) {
  // Walking, turning and tilting (the window moves every few scans), with an
  // object planted now and then that the beams then clear. The reference
  // pipeline's maxima come from the whole map every scan: a map() call
  // before each scan is a change its mapper counts.
  for (const double turn_rad : {0.0, 0.004, -0.03}) {
    PipelineOptions options = visibility_on(true);
    options.mapper.window_ahead_m = 0.3;
    MappingPipeline kept(options), whole(options);
    std::size_t kept_scans = 0, cleared = 0;
    for (int k = 0; k < 120; ++k) {
      TrunkPose pose = pose_at(0.004 * k, turn_rad * k);
      pose.pitch_rad = 0.01 * std::sin(0.7 * k);
      pose.roll_rad = 0.01 * std::cos(1.3 * k);
      if (k % 40 == 10) {
        plant_object(kept.mapper().map(), pose.x_m, 9.0f);  // cleared after three scans
        plant_object(whole.mapper().map(), pose.x_m, 9.0f);
      }
      (void)whole.mapper().map();
      kept.add(floor_scan(0.1 * k), pose);
      whole.add(floor_scan(0.1 * k), pose);
      ASSERT_TRUE(last(whole).maxima_from_whole_map);
      ASSERT_TRUE(same_layers(std::as_const(kept.mapper()).map(), std::as_const(whole.mapper()).map())) << "turn " << turn_rad << ", scan " << k;
      // The bounds are the same too, not only the results: as many cells walked.
      ASSERT_EQ(last(kept).cells_crossed, last(whole).cells_crossed) << "turn " << turn_rad << ", scan " << k;
      ASSERT_EQ(last(kept).cells_contradicted, last(whole).cells_contradicted);
      kept_scans += !last(kept).maxima_from_whole_map;
      cleared += last(kept).cells_cleared;
    }
    EXPECT_GT(kept_scans, 40u) << "turn " << turn_rad;
    EXPECT_GE(cleared, 20u) << "turn " << turn_rad;  // the clears were exercised
  }
}

TEST(VisibilityMaxima, AWriteNotCountedIsNotSeen) {
  // What the tests below guard against: the same object written past the
  // count (map_without_raising() is for writes that raise nothing) is not
  // in the kept maxima, and the pruned walks pass it by.
  MappingPipeline pipeline(visibility_on(false));
  for (int k = 0; k < 4; ++k) pipeline.add(floor_scan(0.1 * k), pose_at(0.0));
  plant_object(pipeline.mapper().map_without_raising(), 0.0);
  pipeline.add(floor_scan(0.4), pose_at(0.0));
  EXPECT_FALSE(last(pipeline).maxima_from_whole_map);
  EXPECT_EQ(last(pipeline).cells_contradicted, 0u);
}

TEST(VisibilityMaxima, AWriteThroughMapIsCounted) {
  MappingPipeline pipeline(visibility_on(false));
  for (int k = 0; k < 4; ++k) pipeline.add(floor_scan(0.1 * k), pose_at(0.0));
  EXPECT_FALSE(last(pipeline).maxima_from_whole_map);
  const std::uint64_t before = pipeline.mapper().changes().unrecorded;
  plant_object(pipeline.mapper().map(), 0.0);
  EXPECT_GT(pipeline.mapper().changes().unrecorded, before);
  pipeline.add(floor_scan(0.4), pose_at(0.0));
  EXPECT_TRUE(last(pipeline).maxima_from_whole_map);
  EXPECT_GE(last(pipeline).cells_contradicted, 20u);
  pipeline.add(floor_scan(0.5), pose_at(0.0));  // and then kept again
  EXPECT_FALSE(last(pipeline).maxima_from_whole_map);
  EXPECT_GE(last(pipeline).cells_contradicted, 20u);
}

TEST(VisibilityMaxima, ReadingsAndTheLayersReadDoNotCount) {
  PipelineOptions options = visibility_on(false);  // no window moves: every scan kept
  options.foothold.enabled = true;
  MappingPipeline pipeline(options);
  pipeline.add(floor_scan(0.0), pose_at(0.0));
  const MapChanges before = pipeline.mapper().changes();
  for (int k = 1; k < 20; ++k) {
    pipeline.add(floor_scan(0.1 * k), pose_at(0.003 * k, 0.01 * k));
    pipeline.refresh_foothold();
    (void)std::as_const(pipeline.mapper()).map();
    EXPECT_FALSE(last(pipeline).maxima_from_whole_map) << "scan " << k;
  }
  EXPECT_EQ(pipeline.mapper().changes().unrecorded, before.unrecorded);
  EXPECT_EQ(pipeline.mapper().changes().scans, before.scans + 19);
}

// Writes the object into the map at every move it is told of.
class PlantingListener : public WindowMoveListener {
 public:
  explicit PlantingListener(double x_m) : x_m_(x_m) {}
  void window_leaving(const ElevationMap&, CellIndex) override {}
  void window_entered(ElevationMap& map, CellIndex) override {
    if (armed) plant_object(map, x_m_);
    armed = false;
  }
  bool armed = false;

 private:
  double x_m_;
};

TEST(VisibilityMaxima, AWindowMoveWithAListenerIsCounted) {
  MappingPipeline pipeline(visibility_on(true));
  PlantingListener listener(0.05);
  pipeline.mapper().set_window_listener(&listener);
  for (int k = 0; k < 5; ++k) pipeline.add(floor_scan(0.1 * k), pose_at(0.0));  // no move: kept
  EXPECT_FALSE(last(pipeline).maxima_from_whole_map);
  listener.armed = true;  // the next move (one cell) writes the object
  pipeline.add(floor_scan(0.5), pose_at(0.05));
  EXPECT_FALSE(listener.armed);
  EXPECT_TRUE(last(pipeline).maxima_from_whole_map);
  EXPECT_GE(last(pipeline).cells_contradicted, 20u);
  pipeline.mapper().set_window_listener(nullptr);
}

TEST(VisibilityMaxima, ChangedRowsClearedBeforeTheCleanUpSawThemAreCounted) {
  // A caller driving the ScanIntegrator itself, taking the changed cells
  // after each scan (seen by then), and once between readings of its own
  // and the next scan's clean-up.
  const PipelineOptions options = visibility_on(false);
  TerrainMapper mapper(options.mapper, options.mount);
  ScanIntegrator integrator(options);
  for (int k = 0; k < 4; ++k) {
    integrator.push(floor_scan(0.1 * k), pose_at(0.0), mapper);
    (void)mapper.take_changed_cells();
  }
  EXPECT_FALSE(integrator.visibility()->stats().maxima_from_whole_map);
  std::vector<MapPoint> object;
  for (const CellIndex c : object_cells(mapper.map(), 0.0)) {
    const Eigen::Vector2d centre = std::as_const(mapper).map().cell_center(c);
    object.push_back({centre.x(), centre.y(), 0.10, 1.0});
  }
  mapper.integrate_points(object, pose_at(0.0));
  const std::uint64_t from = mapper.changes().record_from_scan;
  (void)mapper.take_changed_cells();
  EXPECT_EQ(mapper.changes().record_from_scan, from + 1);
  integrator.push(floor_scan(0.4), pose_at(0.0), mapper);
  EXPECT_TRUE(integrator.visibility()->stats().maxima_from_whole_map);
  EXPECT_GE(integrator.visibility()->stats().cells_contradicted, 20u);
}

TEST(VisibilityMaxima, AnotherMapperIsCounted) {
  const PipelineOptions options = visibility_on(false);
  TerrainMapper mapper(options.mapper, options.mount);
  ScanIntegrator integrator(options);
  for (int k = 0; k < 3; ++k) integrator.push(floor_scan(0.1 * k), pose_at(0.0), mapper);
  EXPECT_FALSE(integrator.visibility()->stats().maxima_from_whole_map);
  // A copy holds the same counts but is another mapper: its map may differ
  // from here on, so the clean-up must not take it for the first.
  TerrainMapper copy = mapper;
  EXPECT_NE(copy.changes().mapper, mapper.changes().mapper);
  plant_object(copy.map_without_raising(), 0.0);  // uncounted on the copy itself: only the identity tells
  integrator.push(floor_scan(0.3), pose_at(0.0), copy);
  EXPECT_TRUE(integrator.visibility()->stats().maxima_from_whole_map);
  EXPECT_GE(integrator.visibility()->stats().cells_contradicted, 20u);
  TerrainMapper assigned(options.mapper, options.mount);
  const std::uint64_t id = assigned.changes().mapper;
  assigned = mapper;
  EXPECT_NE(assigned.changes().mapper, id);
  EXPECT_NE(assigned.changes().mapper, mapper.changes().mapper);
}

}  // namespace
}  // namespace stridemap
