#include "stridemap/experiments/walk_soak_motion.hpp"

#include <cmath>
#include <numbers>
#include <string>

#include <gtest/gtest.h>

#include "stridemap/config/scene_yaml.hpp"
#include "stridemap/core/error.hpp"
#include "test_paths.hpp"

namespace stridemap {
namespace {

const Scene& loop_scene() {
  static const Scene scene = load_scene_yaml(std::string(STRIDEMAP_SOURCE_DIR) + "/scenes/soak_circuit.yaml");
  return scene;
}

TEST(WalkSoakMotion, LapsJoinWithoutAJumpAndPosesDependOnTheScanAlone) {
  const WalkSoakMotion walk(loop_scene());
  const auto lap = static_cast<std::uint64_t>(std::floor(walk.scans_per_lap()));
  ASSERT_GT(lap, 1000u);
  TrunkPose before, after, estimate, again, unused;
  // Across the end of the first lap and far into the run: neighbouring scans
  // stay a step apart (at most 0.1 m/s x 0.1 s plus the gait's sway).
  for (const std::uint64_t scan : {lap - 1, lap, lap + 1, 50 * lap + 3}) {
    walk.pose_at(scan, before, unused);
    walk.pose_at(scan + 1, after, unused);
    EXPECT_LT(std::hypot(after.x_m - before.x_m, after.y_m - before.y_m), 0.02) << scan;
    EXPECT_LT(std::abs(std::remainder(after.yaw_rad - before.yaw_rad, 2.0 * std::numbers::pi)), 0.05) << scan;
  }
  walk.pose_at(777, estimate, unused);
  walk.pose_at(12, before, unused);
  walk.pose_at(777, again, unused);
  EXPECT_EQ(estimate.x_m, again.x_m);
  EXPECT_EQ(estimate.pitch_rad, again.pitch_rad);
}

TEST(WalkSoakMotion, TheEstimateIsTheTruthWithImuNoise) {
  const WalkSoakMotion walk(loop_scene());
  double sum = 0.0, squares = 0.0;
  const int n = 4000;
  for (int k = 0; k < n; ++k) {
    TrunkPose truth, estimate;
    walk.pose_at(static_cast<std::uint64_t>(k), truth, estimate);
    EXPECT_EQ(estimate.x_m, truth.x_m);
    EXPECT_EQ(estimate.reference_elevation_m, truth.reference_elevation_m);
    const double e = estimate.pitch_rad - truth.pitch_rad;
    sum += e;
    squares += e * e;
  }
  EXPECT_NEAR(sum / n, 0.0, 0.0002);
  EXPECT_NEAR(std::sqrt(squares / n), WalkSoakOptions{}.estimate_sigma_rad, 0.0002);
}

TEST(WalkSoakMotion, APathThatIsNoLoopOrNoPathAtAllIsAClearError) {
  Scene open = loop_scene();
  open.walk_path->segments.pop_back();
  try {
    WalkSoakMotion walk(open);
    FAIL() << "an open path was accepted";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("no closed loop"), std::string::npos) << e.what();
  }
  Scene none = loop_scene();
  none.walk_path.reset();
  EXPECT_THROW(WalkSoakMotion{none}, InputError);
}

}  // namespace
}  // namespace stridemap
