#include "stridemap/sim/walk_path.hpp"

#include <cmath>
#include <numbers>

#include <gtest/gtest.h>

#include "stridemap/core/error.hpp"

namespace stridemap {
namespace walk_path_test {
namespace {

constexpr double kPi = std::numbers::pi;

WalkSegment straight(double length) { return {WalkSegment::Kind::straight, length, 0.0, 0.0}; }
WalkSegment turn(double rad, double radius = 0.0) { return {WalkSegment::Kind::turn, 0.0, rad, radius}; }

TEST(WalkPath, StraightsAndTurnsEndWhereGeometrySays) {
  const PathPoint start{1.0, 2.0, kPi / 2, 0.0, 0.0};
  const PathPoint a = advance_along(start, straight(0.5), 1.0);
  EXPECT_NEAR(a.x_m, 1.0, 1e-12);
  EXPECT_NEAR(a.y_m, 2.5, 1e-12);
  EXPECT_NEAR(a.distance_m, 0.5, 1e-12);

  const PathPoint in_place = advance_along(start, turn(-kPi / 3), 1.0);
  EXPECT_NEAR(in_place.x_m, 1.0, 1e-12);
  EXPECT_NEAR(in_place.y_m, 2.0, 1e-12);
  EXPECT_NEAR(in_place.yaw_rad, kPi / 6, 1e-12);
  EXPECT_NEAR(in_place.turned_rad, kPi / 3, 1e-12);
  EXPECT_NEAR(in_place.distance_m, 0.0, 1e-12);

  // Facing +X at the origin, a left quarter circle of radius 0.4 ends at
  // (0.4, 0.4) facing +Y; a right one at (0.4, -0.4) facing -Y.
  const PathPoint origin{};
  const PathPoint left = advance_along(origin, turn(kPi / 2, 0.4), 1.0);
  EXPECT_NEAR(left.x_m, 0.4, 1e-12);
  EXPECT_NEAR(left.y_m, 0.4, 1e-12);
  EXPECT_NEAR(left.yaw_rad, kPi / 2, 1e-12);
  EXPECT_NEAR(left.distance_m, 0.4 * kPi / 2, 1e-12);
  const PathPoint right = advance_along(origin, turn(-kPi / 2, 0.4), 1.0);
  EXPECT_NEAR(right.x_m, 0.4, 1e-12);
  EXPECT_NEAR(right.y_m, -0.4, 1e-12);
  // Half way round the arc the trunk is at 45 deg on the circle.
  const PathPoint half = advance_along(origin, turn(kPi / 2, 0.4), 0.5);
  EXPECT_NEAR(std::hypot(half.x_m, half.y_m - 0.4), 0.4, 1e-12);
}

TEST(WalkPath, ProblemsNameTheSegmentAndField) {
  WalkPath path;
  ASSERT_TRUE(walk_path_problem(path));
  EXPECT_EQ(walk_path_problem(path)->field_path, "walk_path.segments");

  path.segments = {straight(1.0), straight(0.0)};
  EXPECT_EQ(walk_path_problem(path)->field_path, "walk_path.segments[1].straight_m");
  path.segments = {turn(0.0)};
  EXPECT_EQ(walk_path_problem(path)->field_path, "walk_path.segments[0].turn_deg");
  path.segments = {turn(5 * kPi)};
  EXPECT_NE(walk_path_problem(path)->message.find("720"), std::string::npos);
  path.segments = {turn(1.0, -0.2)};
  EXPECT_EQ(walk_path_problem(path)->field_path, "walk_path.segments[0].radius_m");
  path.segments = {straight(1.0)};
  path.start_yaw_rad = NAN;
  EXPECT_EQ(walk_path_problem(path)->field_path, "walk_path.start.yaw_deg");
  path.start_yaw_rad = 0.0;
  path.segments = {straight(2e5)};
  EXPECT_TRUE(walk_path_problem(path));
  path.segments = {straight(1.0), turn(kPi / 2, 0.3)};
  EXPECT_FALSE(walk_path_problem(path));
}

TEST(WalkPath, LeavingTheTerrainExtentIsFoundAtItsSegment) {
  HeightField terrain;  // extent x -1..3, y -1..1
  WalkPath path;
  path.segments = {straight(1.0), turn(kPi / 2), straight(0.5), straight(0.6)};
  const auto problem = walk_path_extent_problem(path, terrain);
  ASSERT_TRUE(problem);
  EXPECT_EQ(problem->field_path, "walk_path.segments[3]");
  EXPECT_NE(problem->message.find("leaves"), std::string::npos) << problem->message;
  path.segments.pop_back();
  EXPECT_FALSE(walk_path_extent_problem(path, terrain));
  path.start_x_m = -2.0;
  EXPECT_EQ(walk_path_extent_problem(path, terrain)->field_path, "walk_path.start");
}

TEST(WalkPath, SamplesCoverEverySegmentEnd) {
  WalkPath path;
  path.segments = {straight(0.1), turn(kPi / 2, 0.2), turn(-kPi / 4)};
  const auto points = sample_walk_path(path, 0.01, 0.01);
  ASSERT_GT(points.size(), 10u);
  EXPECT_NEAR(points.back().yaw_rad, kPi / 4, 1e-12);
  EXPECT_NEAR(points.back().x_m, 0.3, 1e-12);
  EXPECT_NEAR(points.back().y_m, 0.2, 1e-12);
  for (std::size_t k = 1; k < points.size(); ++k) {
    EXPECT_LE(std::hypot(points[k].x_m - points[k - 1].x_m, points[k].y_m - points[k - 1].y_m), 0.0100001);
  }
  EXPECT_THROW(sample_walk_path(WalkPath{}), InputError);
}

}  // namespace
}  // namespace walk_path_test
}  // namespace stridemap
