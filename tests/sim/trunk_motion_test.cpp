#include "stridemap/sim/trunk_motion.hpp"

#include <cmath>
#include <numbers>

#include <gtest/gtest.h>

#include "stridemap/config/scene_yaml.hpp"
#include "stridemap/core/error.hpp"
#include "test_paths.hpp"

namespace stridemap {
namespace {

constexpr double kPi = std::numbers::pi;

WalkPath straight_path(double length) {
  WalkPath path;
  path.segments.push_back({WalkSegment::Kind::straight, length, 0.0, 0.0});
  return path;
}

TEST(TrunkMotion, DurationFollowsSpeedAndTurnRate) {
  Scene scene;
  scene.terrain.min_y_m = -3.0;
  scene.terrain.max_y_m = 3.0;
  GaitOptions gait;
  WalkPath path = straight_path(0.5);
  path.segments.push_back({WalkSegment::Kind::turn, 0.0, kPi / 2, 0.0});    // in place
  path.segments.push_back({WalkSegment::Kind::turn, 0.0, -kPi / 2, 1.0});   // arc, speed-limited
  path.segments.push_back({WalkSegment::Kind::turn, 0.0, kPi / 2, 0.1});    // arc, turn-rate-limited
  const TrunkMotion motion(scene, path, gait);
  const double expected = 0.5 / gait.forward_speed_m_per_s + (kPi / 2) / gait.turn_rate_rad_per_s +
                          1.0 * (kPi / 2) / gait.forward_speed_m_per_s + (kPi / 2) / gait.turn_rate_rad_per_s;
  EXPECT_NEAR(motion.duration_s(), expected, 1e-9);
  // Half way along the straight, at constant speed.
  const TrunkState mid = motion.at(0.25 / gait.forward_speed_m_per_s);
  EXPECT_NEAR(mid.pose.x_m, 0.25, 1e-9);
  EXPECT_EQ(mid.segment, 0u);
  const TrunkState end = motion.at(1e9);
  EXPECT_EQ(end.segment, path.segments.size());
  EXPECT_NEAR(end.turned_rad, 3 * kPi / 2, 1e-9);
}

TEST(TrunkMotion, GaitOscillationsHaveTheirAmplitudesAndRates) {
  Scene scene;  // flat
  GaitOptions gait;
  const TrunkMotion motion(scene, straight_path(1.0), gait);
  double max_bob = 0, max_pitch = 0, max_roll = 0;
  for (double t = 0; t < motion.duration_s(); t += 0.01) {
    const TrunkPose p = motion.at(t).pose;
    EXPECT_DOUBLE_EQ(p.reference_elevation_m, 0.0);
    max_bob = std::max(max_bob, std::abs(p.height_change_m));
    max_pitch = std::max(max_pitch, std::abs(p.pitch_rad));
    max_roll = std::max(max_roll, std::abs(p.roll_rad));
  }
  EXPECT_NEAR(max_bob, gait.bob_amplitude_m, 1e-5);
  EXPECT_NEAR(max_pitch, gait.pitch_amplitude_rad, 1e-5);
  EXPECT_NEAR(max_roll, gait.roll_amplitude_rad, 1e-5);
  // Bob and pitch repeat every step (half a cycle); roll every cycle and
  // changes sign from one step to the next.
  const double t0 = 0.17, half = gait.gait_cycle_s / 2;
  EXPECT_NEAR(motion.at(t0).pose.height_change_m, motion.at(t0 + half).pose.height_change_m, 1e-12);
  EXPECT_NEAR(motion.at(t0).pose.pitch_rad, motion.at(t0 + half).pose.pitch_rad, 1e-12);
  EXPECT_NEAR(motion.at(t0).pose.roll_rad, -motion.at(t0 + half).pose.roll_rad, 1e-12);
}

TEST(TrunkMotion, TrunkFollowsTheTerrainUnderItsFeet) {
  GaitOptions gait;
  gait.bob_amplitude_m = gait.pitch_amplitude_rad = gait.roll_amplitude_rad = 0.0;
  // A plane rising 0.1 m per metre along +X, sampled as a height field.
  Scene ramp;
  ramp.terrain.resolution_m = 0.05;
  ramp.terrain.nx = 81;
  ramp.terrain.ny = 41;
  ramp.terrain.max_x_m = ramp.terrain.min_x_m + 80 * 0.05;
  ramp.terrain.max_y_m = ramp.terrain.min_y_m + 40 * 0.05;
  for (int j = 0; j < ramp.terrain.ny; ++j)
    for (int i = 0; i < ramp.terrain.nx; ++i)
      ramp.terrain.samples.push_back(static_cast<float>(0.1 * (ramp.terrain.min_x_m + i * 0.05)));
  // Sliding feet sit at their nominal places: the plane is the ramp's.
  gait.feet_stand_in_stance = false;
  const TrunkMotion on_ramp(ramp, straight_path(1.0), gait);
  const TrunkPose p = on_ramp.at(5.0).pose;  // at x = 0.5
  EXPECT_NEAR(p.reference_elevation_m, 0.05, 1e-6);
  EXPECT_NEAR(p.pitch_rad, -gait.terrain_attitude_gain * std::atan(0.1), 1e-6);  // nose up climbing
  EXPECT_NEAR(p.roll_rad, 0.0, 1e-9);
  // Standing feet are up to 3.6 cm off their nominal places along the ramp.
  gait.feet_stand_in_stance = true;
  const TrunkPose stepping = TrunkMotion(ramp, straight_path(1.0), gait).at(5.0).pose;
  EXPECT_NEAR(stepping.reference_elevation_m, 0.05, 0.1 * 0.036);
  EXPECT_NEAR(stepping.pitch_rad, -gait.terrain_attitude_gain * std::atan(0.1), 0.01);

  // A box under every foot lifts the trunk by its height; without terrain
  // following the trunk stays at the base elevation.
  Scene boxed;
  BoxObject box;
  box.name = "pad";
  box.center_x_m = 0.5;
  box.length_m = box.width_m = 1.0;
  box.height_m = 0.07;
  boxed.boxes.push_back(box);
  EXPECT_NEAR(TrunkMotion(boxed, straight_path(1.0), gait).at(5.0).pose.reference_elevation_m, 0.07, 1e-9);
  gait.follow_terrain = false;
  EXPECT_NEAR(TrunkMotion(boxed, straight_path(1.0), gait).at(5.0).pose.reference_elevation_m, 0.0, 1e-12);
}

// On the rocky mock-up's own walk (straights, arcs, a turn in place): a
// foot in stance stays exactly where it landed, on the scene's surface;
// a tripod bears the robot at every instant, both for a moment at each
// switch; the trunk's ground has no jumps when the tripods switch.
TEST(TrunkMotion, StanceFeetStandStillOnTheSurface) {
  const Scene scene = load_scene_yaml(std::string(STRIDEMAP_SOURCE_DIR) + "/scenes/rocky_mockup.yaml");
  ASSERT_TRUE(scene.walk_path.has_value());
  const GaitOptions gait;
  ASSERT_TRUE(gait.feet_stand_in_stance);  // the default
  const TrunkMotion motion(scene, *scene.walk_path, gait);
  constexpr double dt = 0.01;
  std::array<Eigen::Vector3d, 6> landed;
  std::array<bool, 6> was_in_stance{};
  std::array<double, 6> landed_at{};
  int stances = 0;
  double largest_foot_travel = 0.0, largest_ground_step = 0.0, previous_ground = 0.0, double_support_s = 0.0;
  for (double t = 0.0; t <= motion.duration_s(); t += dt) {
    const TrunkState s = motion.at(t);
    int bearing = 0;
    for (std::size_t f = 0; f < 6; ++f) {
      const FootState& foot = s.feet[f];
      bearing += foot.in_stance;
      if (foot.in_stance && !was_in_stance[f]) {
        landed[f] = foot.position_m;
        landed_at[f] = t;
        ++stances;
        EXPECT_NEAR(foot.position_m.z(), scene.surface_height_at(foot.position_m.x(), foot.position_m.y()), 1e-9);
      }
      if (foot.in_stance && was_in_stance[f]) {
        largest_foot_travel = std::max(largest_foot_travel, (foot.position_m - landed[f]).norm());
        EXPECT_LT(t - landed_at[f], gait.stance_fraction * gait.gait_cycle_s + 1e-9);
      }
      was_in_stance[f] = foot.in_stance;
    }
    EXPECT_TRUE(bearing == 3 || bearing == 6) << "t = " << t;
    double_support_s += bearing == 6 ? dt : 0.0;
    EXPECT_EQ(s.feet[0].in_stance, s.feet[4].in_stance);
    EXPECT_EQ(s.feet[0].in_stance, s.feet[2].in_stance);
    EXPECT_EQ(s.feet[3].in_stance, s.feet[1].in_stance);
    if (t > 0.0) largest_ground_step = std::max(largest_ground_step, std::abs(s.pose.reference_elevation_m - previous_ground));
    previous_ground = s.pose.reference_elevation_m;
  }
  EXPECT_EQ(largest_foot_travel, 0.0);
  // Both tripods stand for (stance_fraction - 0.5) of a cycle at each of
  // the two switches per cycle.
  EXPECT_NEAR(double_support_s / motion.duration_s(), 2 * (gait.stance_fraction - 0.5), 0.02);
  EXPECT_GT(stances, 6 * static_cast<int>(motion.duration_s() / gait.gait_cycle_s) - 6);
  // The mock-up's boulders are up to 11 cm tall; a sliding foot climbing
  // onto one lifts the ground by a sixth of that at once, a stepping one
  // by a sixth of its share of a 0.6 s swing per 10 ms.
  EXPECT_LT(largest_ground_step, 0.002);

  // Sliding feet (the old model) move with the trunk while bearing it.
  GaitOptions sliding = gait;
  sliding.feet_stand_in_stance = false;
  const TrunkMotion slide(scene, *scene.walk_path, sliding);
  EXPECT_GT((slide.at(2.0).feet[0].position_m - slide.at(2.1).feet[0].position_m).norm(), 0.005);
}

TEST(TrunkMotion, BadInputIsRejectedBeforeAnyWork) {
  Scene scene;
  GaitOptions gait;
  gait.forward_speed_m_per_s = 0.0;
  EXPECT_THROW(TrunkMotion(scene, straight_path(1.0), gait), InputError);
  gait = GaitOptions{};
  gait.terrain_attitude_gain = 1.5;
  EXPECT_THROW(TrunkMotion(scene, straight_path(1.0), gait), InputError);
  gait = GaitOptions{};
  gait.step_height_m = -0.01;
  EXPECT_THROW(TrunkMotion(scene, straight_path(1.0), gait), InputError);
  gait = GaitOptions{};
  gait.stance_fraction = 0.5;
  EXPECT_THROW(TrunkMotion(scene, straight_path(1.0), gait), InputError);
  gait = GaitOptions{};
  gait.bob_amplitude_m = -0.01;
  try {
    TrunkMotion(scene, straight_path(1.0), gait);
    FAIL() << "negative amplitude accepted";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("bob_amplitude_m"), std::string::npos) << e.what();
  }
  try {
    TrunkMotion(scene, straight_path(10.0), GaitOptions{});  // the extent ends at x = 3
    FAIL() << "a path leaving the scene was accepted";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("walk_path.segments[0]"), std::string::npos) << e.what();
  }
}

}  // namespace
}  // namespace stridemap
