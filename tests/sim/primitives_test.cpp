#include "stridemap/sim/primitives.hpp"

#include <cmath>
#include <numbers>

#include <gtest/gtest.h>

namespace stridemap {
namespace primitives_test {
namespace {

Eigen::Vector3d unit(double x, double y, double z) { return Eigen::Vector3d(x, y, z).normalized(); }

BoxObject box_at(double x, double y, double length, double width, double height, double yaw = 0.0) {
  BoxObject box;
  box.name = "b";
  box.center_x_m = x;
  box.center_y_m = y;
  box.length_m = length;
  box.width_m = width;
  box.height_m = height;
  box.yaw_rad = yaw;
  box.reflectance = 0.7;
  return box;
}

CylinderObject can_at(double x, double y, double radius, double height, double base = 0.0) {
  CylinderObject can;
  can.name = "c";
  can.center_x_m = x;
  can.center_y_m = y;
  can.radius_m = radius;
  can.height_m = height;
  can.base_elevation_m = base;
  can.reflectance = 0.3;
  return can;
}

TEST(BoxRay, EveryFaceOfAnAxisAlignedBox) {
  const BoxObject box = box_at(1.0, 0.0, 0.2, 0.1, 0.1);
  struct Case {
    Eigen::Vector3d origin, dir;
    double range;
    Eigen::Vector3d normal;
  };
  const Case cases[] = {
      {{0.0, 0.0, 0.05}, Eigen::Vector3d::UnitX(), 0.9, -Eigen::Vector3d::UnitX()},
      {{2.0, 0.01, 0.05}, -Eigen::Vector3d::UnitX(), 0.9, Eigen::Vector3d::UnitX()},
      {{1.05, -1.0, 0.02}, Eigen::Vector3d::UnitY(), 0.95, -Eigen::Vector3d::UnitY()},
      {{0.95, 1.0, 0.08}, -Eigen::Vector3d::UnitY(), 0.95, Eigen::Vector3d::UnitY()},
      {{1.0, 0.0, 1.0}, -Eigen::Vector3d::UnitZ(), 0.9, Eigen::Vector3d::UnitZ()},
      {{1.0, 0.0, -1.0}, Eigen::Vector3d::UnitZ(), 1.0, -Eigen::Vector3d::UnitZ()},
  };
  for (const Case& c : cases) {
    const auto hit = intersect_box(box, c.origin, c.dir, 5.0);
    ASSERT_TRUE(hit) << c.origin.transpose();
    EXPECT_NEAR(hit->range_m, c.range, 1e-12) << c.origin.transpose();
    EXPECT_TRUE(hit->normal.isApprox(c.normal)) << hit->normal.transpose();
    EXPECT_EQ(hit->reflectance, 0.7);
  }
  // Slanted onto the top: from (0.5, 0, 0.35) towards (1.0, 0, 0.1).
  const Eigen::Vector3d origin(0.5, 0.0, 0.35), target(1.0, 0.0, 0.1);
  const auto hit = intersect_box(box, origin, (target - origin).normalized(), 5.0);
  ASSERT_TRUE(hit);
  EXPECT_TRUE(hit->point_m.isApprox(target, 1e-12));
  EXPECT_TRUE(hit->normal.isApprox(Eigen::Vector3d::UnitZ()));
}

TEST(BoxRay, YawedBoxes) {
  // A 0.2 m square turned by 45 deg is a diamond |x| + |y| <= 0.1 sqrt(2).
  const BoxObject diamond = box_at(0.0, 0.0, 0.2, 0.2, 0.1, std::numbers::pi / 4.0);
  auto hit = intersect_box(diamond, {1.0, 0.05, 0.05}, -Eigen::Vector3d::UnitX(), 5.0);
  ASSERT_TRUE(hit);
  EXPECT_NEAR(hit->point_m.x(), 0.1 * std::sqrt(2.0) - 0.05, 1e-12);
  EXPECT_TRUE(hit->normal.isApprox(unit(1.0, 1.0, 0.0)));
  hit = intersect_box(diamond, {1.0, -0.05, 0.05}, -Eigen::Vector3d::UnitX(), 5.0);
  ASSERT_TRUE(hit);
  EXPECT_TRUE(hit->normal.isApprox(unit(1.0, -1.0, 0.0)));
  // A long thin box turned by 90 deg lies along Y.
  const BoxObject beam = box_at(0.0, 0.0, 0.4, 0.1, 0.1, std::numbers::pi / 2.0);
  hit = intersect_box(beam, {-1.0, 0.15, 0.05}, Eigen::Vector3d::UnitX(), 5.0);
  ASSERT_TRUE(hit);
  EXPECT_NEAR(hit->range_m, 0.95, 1e-12);
  EXPECT_TRUE(hit->normal.isApprox(-Eigen::Vector3d::UnitX()));
  EXPECT_FALSE(intersect_box(beam, {-1.0, 0.25, 0.05}, Eigen::Vector3d::UnitX(), 5.0));
}

TEST(BoxRay, Misses) {
  const BoxObject box = box_at(1.0, 0.0, 0.2, 0.1, 0.1);
  EXPECT_FALSE(intersect_box(box, {0.0, 0.0, 0.15}, Eigen::Vector3d::UnitX(), 5.0));   // above
  EXPECT_FALSE(intersect_box(box, {0.0, 0.0, 0.05}, -Eigen::Vector3d::UnitX(), 5.0));  // away
  EXPECT_FALSE(intersect_box(box, {0.0, 0.0, 0.05}, Eigen::Vector3d::UnitX(), 0.89));  // short
  EXPECT_FALSE(intersect_box(box, {0.0, 0.06, 0.05}, Eigen::Vector3d::UnitX(), 5.0));  // beside
  const auto inside = intersect_box(box, {1.0, 0.0, 0.05}, Eigen::Vector3d::UnitX(), 5.0);
  ASSERT_TRUE(inside);
  EXPECT_EQ(inside->range_m, 0.0);
}

TEST(CylinderRay, SideCapsAndMisses) {
  const CylinderObject can = can_at(1.0, 0.0, 0.05, 0.12);
  auto hit = intersect_cylinder(can, {0.0, 0.0, 0.06}, Eigen::Vector3d::UnitX(), 5.0);
  ASSERT_TRUE(hit);
  EXPECT_NEAR(hit->range_m, 0.95, 1e-12);
  EXPECT_TRUE(hit->normal.isApprox(-Eigen::Vector3d::UnitX()));
  EXPECT_EQ(hit->reflectance, 0.3);
  // Off-centre: enters at x = 1 - sqrt(0.05^2 - 0.03^2) = 0.96.
  hit = intersect_cylinder(can, {0.0, 0.03, 0.06}, Eigen::Vector3d::UnitX(), 5.0);
  ASSERT_TRUE(hit);
  EXPECT_NEAR(hit->range_m, 0.96, 1e-12);
  EXPECT_TRUE(hit->normal.isApprox(Eigen::Vector3d(-0.8, 0.6, 0.0), 1e-12));
  // Top cap from straight above, and slanted (the ray passes over the rim).
  hit = intersect_cylinder(can, {1.02, 0.0, 1.0}, -Eigen::Vector3d::UnitZ(), 5.0);
  ASSERT_TRUE(hit);
  EXPECT_NEAR(hit->range_m, 0.88, 1e-12);
  EXPECT_TRUE(hit->normal.isApprox(Eigen::Vector3d::UnitZ()));
  const Eigen::Vector3d origin(0.5, 0.0, 0.5), target(1.0, 0.0, 0.12);
  hit = intersect_cylinder(can, origin, (target - origin).normalized(), 5.0);
  ASSERT_TRUE(hit);
  EXPECT_TRUE(hit->point_m.isApprox(target, 1e-12));
  EXPECT_TRUE(hit->normal.isApprox(Eigen::Vector3d::UnitZ()));
  // Bottom cap from below (a cylinder standing on a post).
  const CylinderObject raised = can_at(1.0, 0.0, 0.05, 0.12, 0.3);
  hit = intersect_cylinder(raised, {1.0, 0.0, 0.0}, Eigen::Vector3d::UnitZ(), 5.0);
  ASSERT_TRUE(hit);
  EXPECT_NEAR(hit->range_m, 0.3, 1e-12);
  EXPECT_TRUE(hit->normal.isApprox(-Eigen::Vector3d::UnitZ()));
  // Misses: beside, above the top, too short, pointing away.
  EXPECT_FALSE(intersect_cylinder(can, {0.0, 0.06, 0.06}, Eigen::Vector3d::UnitX(), 5.0));
  EXPECT_FALSE(intersect_cylinder(can, {0.0, 0.0, 0.13}, Eigen::Vector3d::UnitX(), 5.0));
  EXPECT_FALSE(intersect_cylinder(can, {0.0, 0.0, 0.06}, Eigen::Vector3d::UnitX(), 0.9));
  EXPECT_FALSE(intersect_cylinder(can, {0.0, 0.0, 0.06}, -Eigen::Vector3d::UnitX(), 5.0));
  // From inside the radius but above: only the cap can be the entry.
  hit = intersect_cylinder(can, {1.0, 0.0, 0.5}, unit(0.1, 0.0, -1.0), 5.0);
  ASSERT_TRUE(hit);
  EXPECT_NEAR(hit->point_m.z(), 0.12, 1e-12);
  EXPECT_NEAR(hit->point_m.x(), 1.038, 1e-12);
  EXPECT_FALSE(intersect_cylinder(can, {1.0, 0.0, 0.5}, unit(1.0, 0.0, -1.0), 5.0));
}

TEST(Footprint, BoxOverlapBySeparatingAxes) {
  const BoxObject box = box_at(1.0, 0.0, 0.2, 0.1, 0.1);
  EXPECT_TRUE(footprint_overlaps(box, {0.85, 0.0, 0.95, 0.01}));   // partial
  EXPECT_TRUE(footprint_overlaps(box, {0.0, -1.0, 2.0, 1.0}));     // contains the box
  EXPECT_TRUE(footprint_overlaps(box, {0.99, -0.01, 1.01, 0.01})); // inside the box
  EXPECT_FALSE(footprint_overlaps(box, {0.85, 0.0, 0.9, 0.01}));   // shares an edge only
  EXPECT_FALSE(footprint_overlaps(box, {0.85, 0.05, 0.9, 0.06}));  // shares a corner only
  EXPECT_TRUE(footprint_overlaps(box, {0.85, 0.0, 0.9001, 0.01}));
  EXPECT_TRUE(footprint_overlaps(box, {0.9, 0.0, 0.9, 0.01}));     // zero width, on the edge
  const BoxObject diamond = box_at(0.0, 0.0, 0.2, 0.2, 0.1, std::numbers::pi / 4.0);
  EXPECT_TRUE(footprint_overlaps(diamond, {0.13, -0.01, 0.15, 0.01}));
  EXPECT_FALSE(footprint_overlaps(diamond, {0.1415, -0.01, 0.16, 0.01}));
  // Bounding boxes overlap, the diamond's edge passes the rectangle's corner.
  EXPECT_FALSE(footprint_overlaps(diamond, {0.08, 0.08, 0.12, 0.12}));
  EXPECT_TRUE(footprint_overlaps(diamond, {0.06, 0.06, 0.12, 0.12}));
  EXPECT_TRUE(footprint_contains(diamond, 0.14, 0.0));
  EXPECT_FALSE(footprint_contains(diamond, 0.09, 0.09));
}

TEST(Footprint, CircleOverlap) {
  const CylinderObject can = can_at(0.0, 0.0, 0.05, 0.1);
  EXPECT_FALSE(footprint_overlaps(can, {0.04, 0.04, 0.06, 0.06}));  // bounding boxes overlap, circle does not
  EXPECT_TRUE(footprint_overlaps(can, {0.03, 0.03, 0.06, 0.06}));
  EXPECT_TRUE(footprint_overlaps(can, {-0.01, -0.01, 0.01, 0.01}));  // inside the circle
  EXPECT_TRUE(footprint_overlaps(can, {-1.0, -1.0, 1.0, 1.0}));      // around it
  EXPECT_FALSE(footprint_overlaps(can, {0.05, -0.01, 0.06, 0.01}));  // tangent
  EXPECT_TRUE(footprint_overlaps(can, {0.049, -0.01, 0.06, 0.01}));
  EXPECT_TRUE(footprint_contains(can, 0.03, 0.04));
  EXPECT_FALSE(footprint_contains(can, 0.04, 0.04));
}

}  // namespace
}  // namespace primitives_test
}  // namespace stridemap
