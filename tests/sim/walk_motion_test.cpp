#include "stridemap/sim/walk_motion.hpp"

#include <cmath>
#include <string>

#include <gtest/gtest.h>

#include "stridemap/config/scene_yaml.hpp"
#include "stridemap/core/error.hpp"
#include "test_paths.hpp"

namespace stridemap {
namespace {

TEST(WalkMotion, FollowsTheScenesPathAndStopsAtItsEnd) {
  const Scene scene = load_scene_yaml(std::string(STRIDEMAP_SOURCE_DIR) + "/scenes/rocky_mockup.yaml");
  ASSERT_TRUE(scene.walk_path.has_value());
  const WalkMotion walk(scene);
  const TrunkPose start = walk.pose_at(0.0);
  EXPECT_NEAR(start.x_m, scene.walk_path->start_x_m, 1e-9);
  EXPECT_NEAR(start.y_m, scene.walk_path->start_y_m, 1e-9);
  // The same time gives the same pose (the emulator asks again after a reset).
  const TrunkPose middle = walk.pose_at(0.5 * walk.duration_s());
  const TrunkPose again = walk.pose_at(0.5 * walk.duration_s());
  EXPECT_EQ(middle.x_m, again.x_m);
  EXPECT_EQ(middle.yaw_rad, again.yaw_rad);
  EXPECT_GT(std::hypot(middle.x_m - start.x_m, middle.y_m - start.y_m), 0.3);
  const TrunkPose end = walk.pose_at(walk.duration_s());
  const TrunkPose later = walk.pose_at(walk.duration_s() + 100.0);
  EXPECT_EQ(end.x_m, later.x_m);
  EXPECT_EQ(end.y_m, later.y_m);
  EXPECT_NE(walk.describe().find("walking"), std::string::npos);
}

TEST(WalkMotion, ASceneWithoutAPathIsAClearError) {
  const Scene scene = load_scene_yaml(std::string(STRIDEMAP_SOURCE_DIR) + "/scenes/cart_rail_boxes.yaml");
  try {
    WalkMotion walk(scene);
    FAIL() << "a scene without walk_path was accepted";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("no walk_path section"), std::string::npos) << e.what();
  }
}

}  // namespace
}  // namespace stridemap
