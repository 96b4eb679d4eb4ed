#include "stridemap/experiments/map_evaluation.hpp"

#include <cmath>

#include <gtest/gtest.h>

#include "stridemap/experiments/object_extents.hpp"

namespace stridemap {
namespace {

// A map that equals the truth of a scene with one box, built cell by cell.
MapSnapshot perfect_snapshot(const Scene& scene, int n, double cell) {
  ElevationMap map({n, cell});
  map.move_to(0.5, 0.0);
  for (int i = 0; i < n; ++i) {
    for (int j = 0; j < n; ++j) {
      const CellIndex c = map.cell_at_local(i, j);
      const double x0 = static_cast<double>(c.x) * cell, y0 = static_cast<double>(c.y) * cell;
      const std::size_t s = map.slot(c);
      map.elevation_data()[s] = static_cast<float>(scene.max_height_in_rect(x0, y0, x0 + cell, y0 + cell));
      map.certainty_data()[s] = 3.0f;
      map.state_data()[s] = static_cast<std::uint8_t>(CellState::measured);
    }
  }
  return snapshot_with_truth(map, scene);
}

Scene one_box_scene() {
  Scene scene;
  BoxObject box;
  box.name = "box";
  box.center_x_m = 0.503;
  box.center_y_m = 0.012;
  box.length_m = 0.20;
  box.width_m = 0.15;
  box.height_m = 0.10;
  scene.boxes.push_back(box);
  return scene;
}

TEST(MapEvaluation, PerfectMapScoresZeroError) {
  const Scene scene = one_box_scene();
  const MapSnapshot s = perfect_snapshot(scene, 80, 0.01);
  const MapScore score = score_map(s, CellMask::Ones(80, 80));
  EXPECT_EQ(score.known_cells, 6400u);
  EXPECT_EQ(score.rms_error_m, 0.0);
  EXPECT_EQ(score.artifact_cells, 0u);
  EXPECT_DOUBLE_EQ(score.coverage, 1.0);
}

TEST(MapEvaluation, ErrorsArtifactsAndCoverageAreCounted) {
  const Scene scene = one_box_scene();
  MapSnapshot s = perfect_snapshot(scene, 10, 0.01);
  s.elevation_m()(2, 3) += 0.03f;  // an artifact
  s.elevation_m()(4, 4) -= 0.01f;  // within the threshold
  s.state()(5, 5) = static_cast<std::uint8_t>(CellState::unknown);
  CellMask area = CellMask::Ones(10, 10);
  area(9, 9) = 0;
  const MapScore score = score_map(s, area);
  EXPECT_EQ(score.scored_area_cells, 99u);
  EXPECT_EQ(score.known_cells, 98u);
  EXPECT_EQ(score.artifact_cells, 1u);
  EXPECT_NEAR(score.max_error_m, 0.03, 1e-6);
  EXPECT_NEAR(score.rms_error_m, std::sqrt((0.03 * 0.03 + 0.01 * 0.01) / 98.0), 1e-6);
  EXPECT_NEAR(score.coverage, 98.0 / 99.0, 1e-12);
}

TEST(ObjectExtents, PerfectMapMeasuresWithinACellAndHeightExactly) {
  const Scene scene = one_box_scene();
  const MapSnapshot s = perfect_snapshot(scene, 80, 0.01);
  const auto objects = measure_objects(s, scene);
  ASSERT_EQ(objects.size(), 1u);
  ASSERT_TRUE(objects[0].found);
  EXPECT_NEAR(objects[0].measured.length_m, 0.20, 0.0101);
  EXPECT_NEAR(objects[0].measured.width_m, 0.15, 0.0101);
  EXPECT_NEAR(objects[0].measured.height_m, 0.10, 1e-6);
}

TEST(ObjectExtents, CentreSpreadIsUnbiasedOverPlacements) {
  // Over many sub-cell placements the mean measured length equals the truth.
  double sum = 0.0;
  const int placements = 20;
  for (int k = 0; k < placements; ++k) {
    Scene scene = one_box_scene();
    scene.boxes[0].center_x_m = 0.5 + 0.01 * k / placements;
    const auto objects = measure_objects(perfect_snapshot(scene, 60, 0.01), scene);
    sum += objects[0].measured.length_m;
  }
  EXPECT_NEAR(sum / placements, 0.20, 0.001);
}

// The truth names the object only: a turned box is measured along the axes
// its own cells show, and its region is not clipped to the true footprint
// (a map that grew the box by two cells on one side measures it longer).
TEST(ObjectExtents, TurnedBoxAxesComeFromTheMapNotTheTruth) {
  Scene scene = one_box_scene();
  scene.boxes[0].yaw_rad = 0.5;
  const MapSnapshot s = perfect_snapshot(scene, 80, 0.01);
  const auto objects = measure_objects(s, scene);
  ASSERT_TRUE(objects[0].found);
  EXPECT_NEAR(objects[0].measured_yaw_rad, 0.5, 0.03);
  EXPECT_NEAR(objects[0].measured.length_m, 0.20, 0.01);
  EXPECT_NEAR(objects[0].measured.width_m, 0.15, 0.01);
  EXPECT_GT(objects[0].measured_untrimmed.length_m, objects[0].measured.length_m - 1e-9);

  Scene square = one_box_scene();
  MapSnapshot grown = perfect_snapshot(square, 80, 0.01);
  const auto before = measure_objects(grown, square);
  // Two more columns of box beyond its +x face, 30 mm outside the truth's
  // footprint margin of the old method.
  for (Eigen::Index i = 0; i < grown.elevation_m().rows(); ++i)
    for (Eigen::Index j = 0; j < grown.elevation_m().cols(); ++j) {
      const double x = (static_cast<double>(grown.min_cell.x + i) + 0.5) * 0.01;
      const double y = (static_cast<double>(grown.min_cell.y + j) + 0.5) * 0.01;
      if (x > 0.608 && x < 0.628 && std::abs(y - 0.012) < 0.07) grown.elevation_m()(i, j) = 0.1f;
    }
  const auto after = measure_objects(grown, square);
  EXPECT_NEAR(after[0].measured_untrimmed.length_m - before[0].measured_untrimmed.length_m, 0.02, 1e-9);
}

TEST(ObjectExtents, EmptyMapFindsNothing) {
  const Scene scene = one_box_scene();
  MapSnapshot s = perfect_snapshot(scene, 40, 0.01);
  s.state().setConstant(static_cast<std::uint8_t>(CellState::unknown));
  const auto objects = measure_objects(s, scene);
  EXPECT_FALSE(objects[0].found);
}

}  // namespace
}  // namespace stridemap
