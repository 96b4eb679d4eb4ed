// 10,000 scans over a loop 40 m round (the map is 1 m across): the map
// keeps its memory, nothing is allocated per scan once the buffers have
// grown, and no cell ever holds a value the layers must not hold.
// Allocations are counted by the program's operator new
// (operator_new_test.cpp) while a flag is set.
#include <atomic>
#include <cmath>
#include <cstdlib>
#include <new>
#include <numbers>

#include <gtest/gtest.h>

#include "allocation_counting.hpp"

#include "stridemap/experiments/urg_walk_sensor.hpp"
#include "stridemap/experiments/walk.hpp"

namespace stridemap {
namespace {

std::atomic<bool>& counting = test::allocation_counter().counting;
std::atomic<std::size_t>& allocations = test::allocation_counter().allocations;

constexpr double kPi = std::numbers::pi;

TEST(LongWalk, TenThousandScansKeepMemoryConstantAndTheMapValid) {
  Scene scene;
  scene.terrain.min_x_m = scene.terrain.min_y_m = -2.0;
  scene.terrain.max_x_m = scene.terrain.max_y_m = 12.0;
  // Boxes along the loop, so that the map holds steps, shadows and
  // implausible readings, not only floor.
  for (int k = 0; k < 24; ++k) {
    BoxObject box;
    box.name = "box" + std::to_string(k);
    const double s = 0.4 + 0.37 * (k % 24);
    box.center_x_m = k < 12 ? s : 9.5 + 0.3;
    box.center_y_m = k < 12 ? 0.25 : s - 4.0;
    box.length_m = 0.12;
    box.width_m = 0.1;
    box.height_m = 0.03 + 0.01 * (k % 5);
    scene.boxes.push_back(box);
  }
  // A closed loop of straights, arcs and turns in place, walked three times.
  WalkPath path;
  for (int lap = 0; lap < 3; ++lap) {
    path.segments.push_back({WalkSegment::Kind::straight, 9.0, 0.0, 0.0});
    path.segments.push_back({WalkSegment::Kind::turn, 0.0, kPi / 2, 0.5});
    path.segments.push_back({WalkSegment::Kind::straight, 9.0, 0.0, 0.0});
    path.segments.push_back({WalkSegment::Kind::turn, 0.0, kPi / 2, 0.0});
    path.segments.push_back({WalkSegment::Kind::straight, 9.5, 0.0, 0.0});
    path.segments.push_back({WalkSegment::Kind::turn, 0.0, kPi / 2, 0.5});
    path.segments.push_back({WalkSegment::Kind::straight, 9.0, 0.0, 0.0});
    path.segments.push_back({WalkSegment::Kind::turn, 0.0, kPi / 2, 0.0});
    path.segments.push_back({WalkSegment::Kind::straight, 0.5, 0.0, 0.0});
  }
  WalkOptions options;  // default pose errors, h_ref from the map
  options.build_mosaic = false;
  UrgWalkSensor sensor(scene, UrgWalkSensorOptions{}, options.mapper.update, 5);
  WalkRun run(scene, path, sensor, options);
  ASSERT_GE(run.total_scans(), 10000u);

  for (int k = 0; k < 100; ++k) run.step();  // buffers grow here
  const float* elevation_storage = run.mapper().map().elevation_data();
  allocations = 0;
  counting = true;
  std::size_t invalid = 0, checks = 0;
  while (run.scans_done() < 10000) {
    run.step();
    ASSERT_FALSE(run.last_stats().pose_rejected);
    if (run.scans_done() % 25 == 0) {
      invalid += count_invalid_cells(run.mapper().map(), options.mapper.update.certainty_max);
      ++checks;
    }
  }
  counting = false;
  EXPECT_EQ(allocations.load(), 0u);
  EXPECT_EQ(run.mapper().map().elevation_data(), elevation_storage);
  EXPECT_EQ(invalid, 0u) << "over " << checks << " checks";
  EXPECT_EQ(checks, 396u);

  const MapperTotals& totals = run.mapper().totals();
  EXPECT_EQ(totals.scans, 10000u);
  EXPECT_EQ(totals.scans_rejected_for_pose, 0u);
  EXPECT_GT(totals.implausible, 0u);
  EXPECT_GT(run.last_truth().distance_m, 80.0);  // 80 times the map's side
  EXPECT_EQ(count_invalid_cells(run.mapper().map(), options.mapper.update.certainty_max), 0u);
}

}  // namespace
}  // namespace stridemap
