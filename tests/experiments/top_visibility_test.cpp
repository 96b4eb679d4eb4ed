// How much of each top the ideal sensor saw, and the per-edge errors the
// cart rail reports beside it.
#include "stridemap/experiments/top_visibility.hpp"

#include <cmath>
#include <string>

#include <gtest/gtest.h>

#include "stridemap/config/scene_yaml.hpp"
#include "stridemap/core/error.hpp"
#include "stridemap/experiments/cart_rail.hpp"
#include "test_paths.hpp"

namespace stridemap {
namespace {

Scene box_and_can() {
  Scene scene;
  BoxObject box;
  box.name = "box";
  box.center_x_m = 0.5;
  box.center_y_m = 0.1;
  box.length_m = 0.2;
  box.width_m = 0.1;
  box.height_m = 0.05;
  box.yaw_rad = 0.3;
  scene.boxes.push_back(box);
  CylinderObject can;
  can.name = "can";
  can.center_x_m = 0.8;
  can.radius_m = 0.04;
  can.height_m = 0.08;
  scene.cylinders.push_back(can);
  return scene;
}

// Hits on a 5 mm grid over the box's top, its local u from u_min to u_max.
void hit_box_top(TopVisibility& visibility, const BoxObject& box, double u_min_m, double u_max_m) {
  const Eigen::Vector2d u(std::cos(box.yaw_rad), std::sin(box.yaw_rad)), v(-u.y(), u.x());
  for (double a = u_min_m; a <= u_max_m + 1e-9; a += 0.005) {
    for (double b = -box.width_m / 2; b <= box.width_m / 2 + 1e-9; b += 0.005) {
      const Eigen::Vector2d p = Eigen::Vector2d(box.center_x_m, box.center_y_m) + a * u + b * v;
      visibility.add_hit(0, Eigen::Vector3d(p.x(), p.y(), box.top_m()));
    }
  }
}

TEST(TopVisibility, AWholeTopIsSeenHalfATopHalfSeenNoHitsUnseen) {
  const Scene scene = box_and_can();
  const BoxObject& box = scene.boxes[0];
  TopVisibility whole(scene, 0.0075);
  hit_box_top(whole, box, -box.length_m / 2, box.length_m / 2);
  EXPECT_DOUBLE_EQ(whole.seen_shares()[0], 1.0);
  EXPECT_DOUBLE_EQ(whole.seen_shares()[1], 0.0);  // the can: no hits

  TopVisibility half(scene, 0.0075);
  hit_box_top(half, box, -box.length_m / 2, 0.0);
  // The reach carries the seen half 7.5 mm on: (100 + 7.5 - 3) / 194 mm.
  EXPECT_NEAR(half.seen_shares()[0], 0.54, 0.02);
}

TEST(TopVisibility, HitsOnTheTerrainOrASideDoNotCount) {
  const Scene scene = box_and_can();
  TopVisibility visibility(scene, 0.0075);
  visibility.add_hit(-1, Eigen::Vector3d(0.5, 0.1, 0.05));
  visibility.add_hit(1, Eigen::Vector3d(0.8, 0.0, 0.04));  // half way up the can's side
  visibility.add_hit(7, Eigen::Vector3d(0.8, 0.0, 0.08));  // no such object
  EXPECT_DOUBLE_EQ(visibility.seen_shares()[0], 0.0);
  EXPECT_DOUBLE_EQ(visibility.seen_shares()[1], 0.0);
  visibility.add_hit(1, Eigen::Vector3d(0.8, 0.0, 0.08));  // the middle of the can's top
  EXPECT_GT(visibility.seen_shares()[1], 0.02);
  EXPECT_LT(visibility.seen_shares()[1], 0.05);
}

TEST(TopVisibility, RefusesAReachOrSpacingThatIsNotPositive) {
  const Scene scene = box_and_can();
  EXPECT_THROW(TopVisibility(scene, 0.0), InputError);
  EXPECT_THROW(TopVisibility(scene, std::nan("")), InputError);
  TopVisibilityOptions options;
  options.sample_spacing_m = -1.0;
  try {
    TopVisibility(scene, 0.01, options);
    FAIL() << "a negative spacing was accepted";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("sample_spacing_m"), std::string::npos) << e.what();
  }
}

// On the rail, the boxes of the shipped scene are seen whole; a box that
// the last scan line cuts in two is seen in part.
TEST(TopVisibility, CartRailTellsFullyFromPartlySeenObjects) {
  Scene scene = load_scene_yaml(std::string(STRIDEMAP_SOURCE_DIR) + "/scenes/cart_rail_boxes.yaml");
  const CartRailOptions options;
  const CartRailResult plain = run_cart_rail(scene, options);
  for (const ObjectMeasurement& m : plain.objects) EXPECT_GT(m.seen_share, 0.99) << m.name;

  // The swath's far end on the rail's line: the last scan's floor line.
  double swath_x_max = -1e9;
  const double s = plain.snapshot.cell_size_m;
  for (Eigen::Index i = 0; i < plain.swept_area.rows(); ++i) {
    for (Eigen::Index j = 0; j < plain.swept_area.cols(); ++j) {
      const double y = (static_cast<double>(plain.snapshot.min_cell.y + j) + 0.5) * s;
      if (plain.swept_area(i, j) && std::abs(y - plain.rail.y_m) < s)
        swath_x_max = std::max(swath_x_max, (static_cast<double>(plain.snapshot.min_cell.x + i) + 0.5) * s);
    }
  }
  BoxObject cut;
  cut.name = "cut_by_the_last_scan";
  cut.center_x_m = swath_x_max;
  cut.center_y_m = plain.rail.y_m;
  cut.length_m = cut.width_m = 0.1;
  cut.height_m = 0.02;
  scene.boxes.push_back(cut);
  const CartRailResult with_cut = run_cart_rail(scene, options);
  const ObjectMeasurement& seen_in_part = with_cut.objects[scene.boxes.size() - 1];
  ASSERT_EQ(seen_in_part.name, "cut_by_the_last_scan");
  EXPECT_GT(seen_in_part.seen_share, 0.2);
  EXPECT_LT(seen_in_part.seen_share, 0.8);
}

// Without mixed pixels a square box's edges come out within a rail step
// and a beam spacing of the truth, and each side is named from the travel.
TEST(EdgeErrors, CartRailNamesTheSidesAndStaysNearTheTruth) {
  const Scene scene = load_scene_yaml(std::string(STRIDEMAP_SOURCE_DIR) + "/scenes/cart_rail_boxes.yaml");
  const CartRailResult result = run_cart_rail(scene, CartRailOptions{});
  std::size_t boxes = 0;
  for (const ObjectMeasurement& m : result.objects) {
    if (m.kind != "box") {
      for (double e : m.edge_errors_m) EXPECT_TRUE(std::isnan(e)) << m.name;
      continue;
    }
    ++boxes;
    for (std::size_t side = 0; side < 4; ++side) {
      EXPECT_LT(std::abs(m.edge_errors_m[side]), 0.012) << m.name << " " << to_string(static_cast<EdgeSide>(side));
    }
    // The widths are the left and right edges' sum, the lengths near and far's.
    EXPECT_NEAR(m.edges_trimmed.width_m - m.truth.width_m, m.edge_errors_m[2] + m.edge_errors_m[3], 1e-3) << m.name;
    EXPECT_NEAR(m.edges_trimmed.length_m - m.truth.length_m, m.edge_errors_m[0] + m.edge_errors_m[1], 1e-3) << m.name;
  }
  EXPECT_GT(boxes, 0u);
}

}  // namespace
}  // namespace stridemap
