#include "stridemap/sim/scene.hpp"

#include <cmath>
#include <limits>
#include <numbers>
#include <random>
#include <string>

#include <gtest/gtest.h>

#include "stridemap/core/error.hpp"
#include "stridemap/sim/cart_rail.hpp"
#include "stridemap/sim/scene_ray_caster.hpp"

namespace stridemap {
namespace {

Scene two_objects() {
  Scene scene;
  BoxObject box;
  box.name = "box";
  box.center_x_m = 1.0;
  box.length_m = 0.2;
  box.width_m = 0.1;
  box.height_m = 0.1;
  box.reflectance = 0.6;
  scene.boxes.push_back(box);
  CylinderObject can;
  can.name = "can";
  can.center_x_m = 1.5;
  can.radius_m = 0.05;
  can.height_m = 0.2;
  can.reflectance = 0.4;
  scene.cylinders.push_back(can);
  return scene;
}

std::string validation_error(const Scene& scene) {
  try {
    scene.validate();
  } catch (const InputError& error) {
    return error.what();
  }
  return "(no error)";
}

// Scenes built in code meet the same caps as scene files.
TEST(SceneLimits, TooManyBoxesOrCylindersAreAProblemNamingTheList) {
  Scene scene;
  scene.boxes.resize(kMaxSceneBoxes);
  for (std::size_t k = 0; k < scene.boxes.size(); ++k) {
    scene.boxes[k] = BoxObject{"b" + std::to_string(k), 1.0, 0.0, 0.0, 0.1, 0.1, 0.1};
  }
  if (const auto problem = scene.first_problem()) {
    EXPECT_NE(problem->field_path, "boxes") << problem->message;
  }
  scene.boxes.emplace_back().name = "one too many";
  const auto problem = scene.first_problem();
  ASSERT_TRUE(problem);
  EXPECT_EQ(problem->field_path, "boxes");
  EXPECT_EQ(problem->message, "expected at most 1000 boxes, got 1001");
  scene.boxes.clear();
  scene.cylinders.resize(kMaxSceneCylinders + 1);
  try {
    scene.validate();
    ADD_FAILURE() << "no InputError";
  } catch (const InputError& e) {
    EXPECT_STREQ(e.what(), "scene: cylinders: expected at most 1000 cylinders, got 1001");
  }
}

TEST(SceneCast, NearestSurfaceWithItsIndex) {
  const Scene scene = two_objects();
  auto hit = scene.cast_ray({0.0, 0.0, 0.05}, Eigen::Vector3d::UnitX(), 5.0);
  ASSERT_TRUE(hit);
  EXPECT_EQ(hit->object_index, 0);
  EXPECT_NEAR(hit->range_m, 0.9, 1e-12);
  EXPECT_EQ(hit->reflectance, 0.6);
  // Above the box, the cylinder is next.
  hit = scene.cast_ray({0.0, 0.0, 0.15}, Eigen::Vector3d::UnitX(), 5.0);
  ASSERT_TRUE(hit);
  EXPECT_EQ(hit->object_index, 1);
  EXPECT_NEAR(hit->range_m, 1.45, 1e-12);
  // Down onto the box top rather than the floor below it.
  hit = scene.cast_ray({1.0, 0.0, 1.0}, -Eigen::Vector3d::UnitZ(), 5.0);
  ASSERT_TRUE(hit);
  EXPECT_EQ(hit->object_index, 0);
  EXPECT_NEAR(hit->range_m, 0.9, 1e-12);
  // The floor beside both.
  hit = scene.cast_ray({1.0, 0.5, 1.0}, -Eigen::Vector3d::UnitZ(), 5.0);
  ASSERT_TRUE(hit);
  EXPECT_EQ(hit->object_index, -1);
  EXPECT_NEAR(hit->range_m, 1.0, 1e-12);
  EXPECT_FALSE(scene.cast_ray({0.0, 0.0, 0.5}, Eigen::Vector3d::UnitX(), 5.0));
}

TEST(SceneCast, RayCasterAgreesWithTheScene) {
  Scene scene = two_objects();
  ProceduralTerrainOptions terrain;
  terrain.min_x_m = 0.0;
  terrain.max_x_m = 2.0;
  terrain.amplitude_m = 0.03;
  scene.terrain = make_procedural_height_field(terrain, 9);
  BoxObject turned = scene.boxes[0];
  turned.name = "turned";
  turned.center_y_m = 0.4;
  turned.yaw_rad = 0.5;
  scene.boxes.push_back(turned);
  const SceneRayCaster caster(scene);
  std::mt19937_64 rng(4);
  std::uniform_real_distribution<double> angle(-1.2, 1.2), dip(0.05, 0.9);
  int hits = 0;
  for (int k = 0; k < 2000; ++k) {
    const double yaw = angle(rng), down = dip(rng);
    const Eigen::Vector3d dir(std::cos(down) * std::cos(yaw), std::cos(down) * std::sin(yaw), -std::sin(down));
    const Eigen::Vector3d origin(0.2, 0.0, 0.26);
    const auto a = scene.cast_ray(origin, dir, 5.6);
    const auto b = caster.cast(origin, dir, 5.6);
    ASSERT_EQ(a.has_value(), b.has_value());
    if (!a) continue;
    ++hits;
    EXPECT_EQ(a->object_index, b->object_index);
    EXPECT_NEAR(a->range_m, b->range_m, 1e-12);
  }
  EXPECT_GT(hits, 1500);
}

TEST(SceneGroundTruth, SurfaceHeightAndCellMaximum) {
  Scene scene = two_objects();
  scene.terrain.base_elevation_m = -0.01;
  EXPECT_NEAR(scene.surface_height_at(1.0, 0.0), 0.1, 1e-12);
  EXPECT_NEAR(scene.surface_height_at(1.5, 0.0), 0.2, 1e-12);
  EXPECT_NEAR(scene.surface_height_at(0.5, 0.0), -0.01, 1e-12);
  // Cells 10 mm wide around the box's front face at x = 0.9.
  EXPECT_NEAR(scene.max_height_in_rect(0.89, 0.0, 0.90, 0.01), -0.01, 1e-12);  // touches the face only
  EXPECT_NEAR(scene.max_height_in_rect(0.90, 0.0, 0.91, 0.01), 0.1, 1e-12);
  EXPECT_NEAR(scene.max_height_in_rect(0.895, 0.045, 0.905, 0.055), 0.1, 1e-12);  // corner, partly
  EXPECT_NEAR(scene.max_height_in_rect(0.5, -0.5, 2.0, 0.5), 0.2, 1e-12);        // both, take the higher
  // Near the cylinder's rim diagonally: bounding boxes overlap, the circle does not.
  EXPECT_NEAR(scene.max_height_in_rect(1.54, 0.04, 1.55, 0.05), -0.01, 1e-12);
  EXPECT_NEAR(scene.max_height_in_rect(1.53, 0.03, 1.54, 0.04), 0.2, 1e-12);
  const double nan = std::numeric_limits<double>::quiet_NaN();
  EXPECT_TRUE(std::isnan(scene.max_height_in_rect(nan, 0.0, 1.0, 1.0)));
  EXPECT_TRUE(std::isnan(scene.surface_height_at(1.0, nan)));
}

TEST(SceneValidate, NamesTheObjectAndField) {
  Scene scene = two_objects();
  EXPECT_NO_THROW(scene.validate());
  scene.boxes[0].length_m = -0.1;
  EXPECT_EQ(validation_error(scene), "scene: boxes[0].length_m of \"box\": expected a positive number, got -0.1");
  scene = two_objects();
  scene.cylinders[0].reflectance = 1.5;
  EXPECT_EQ(validation_error(scene),
            "scene: cylinders[0].reflectance of \"can\": expected a reflectance in (0, 1], got 1.5");
  scene = two_objects();
  scene.cylinders[0].center_y_m = std::numeric_limits<double>::quiet_NaN();
  EXPECT_EQ(validation_error(scene), "scene: cylinders[0].center_y_m of \"can\": expected a finite number, got nan");
  scene = two_objects();
  scene.cylinders[0].name = "box";
  EXPECT_EQ(validation_error(scene),
            "scene: cylinders[0].name of \"box\": duplicate name \"box\" (also boxes[0].name)");
  scene = two_objects();
  scene.boxes[0].name = "";
  EXPECT_EQ(validation_error(scene), "scene: boxes[0].name: expected a non-empty name");
  scene = two_objects();
  scene.terrain.samples = {0.0f, 0.0f, 0.0f};
  scene.terrain.nx = 2;
  scene.terrain.ny = 2;
  EXPECT_EQ(validation_error(scene), "scene: terrain.samples: expected nx * ny = 4 samples, got 3");
  scene.terrain.samples.push_back(std::numeric_limits<float>::infinity());
  scene.terrain.max_x_m = scene.terrain.min_x_m + 0.01;
  scene.terrain.max_y_m = scene.terrain.min_y_m + 0.01;
  EXPECT_EQ(validation_error(scene), "scene: terrain.samples[3]: expected a finite number, got inf");
  scene = two_objects();
  scene.cart_rail = CartRailPath{};
  scene.cart_rail->step_m = 0.0;
  EXPECT_EQ(validation_error(scene), "scene: cart_rail.step_m: expected a positive number, got 0");
}

TEST(CartRail, OnePosePerStepBothEndsIncluded) {
  CartRailPath path;
  path.start_x_m = 0.0;
  path.end_x_m = 1.2;
  path.y_m = 0.05;
  path.step_m = 0.01;
  auto poses = cart_rail_poses(path);
  ASSERT_EQ(poses.size(), 121u);
  EXPECT_EQ(poses.front().x_m, 0.0);
  EXPECT_EQ(poses.back().x_m, 1.2);
  EXPECT_NEAR(poses[57].x_m, 0.57, 1e-12);
  for (const TrunkPose& pose : poses) {
    EXPECT_EQ(pose.y_m, 0.05);
    EXPECT_EQ(pose.pitch_rad, 0.0);
    EXPECT_EQ(pose.roll_rad, 0.0);
  }
  path.end_x_m = 1.005;  // not a whole number of steps: the end is added
  poses = cart_rail_poses(path);
  ASSERT_EQ(poses.size(), 102u);
  EXPECT_NEAR(poses[100].x_m, 1.0, 1e-12);
  EXPECT_EQ(poses.back().x_m, 1.005);
  path.start_x_m = 0.5;  // backwards
  path.end_x_m = 0.2;
  path.yaw_rad = std::numbers::pi;
  poses = cart_rail_poses(path);
  ASSERT_EQ(poses.size(), 31u);
  EXPECT_NEAR(poses[1].x_m, 0.49, 1e-12);
  EXPECT_EQ(poses.back().yaw_rad, std::numbers::pi);
  path.end_x_m = path.start_x_m;
  EXPECT_EQ(cart_rail_poses(path).size(), 1u);
  path.step_m = -0.01;
  try {
    cart_rail_poses(path);
    FAIL() << "expected InputError";
  } catch (const InputError& error) {
    EXPECT_STREQ(error.what(), "cart_rail.step_m: expected a positive number, got -0.01");
  }
}

}  // namespace
}  // namespace stridemap
