#include "stridemap/experiments/map_evaluation.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>
#include <random>
#include <string>

#include <gtest/gtest.h>

#include "stridemap/core/error.hpp"
#include "stridemap/core/exported_map.hpp"
#include "stridemap/core/top_point.hpp"
#include "stridemap/experiments/object_extents.hpp"

namespace stridemap {
namespace map_evaluation_test {
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

// Cells within the object margin (10 mm) of the box's edge may hold the
// top, the face or the floor, whichever reading fell there: not level, and
// a floor reading there is within the span. A phantom on the floor and a
// spike on the top are beyond it, and count in the level cells' RMS.
TEST(MapEvaluation, EdgeCellsAreKeptApartFromLevelCellsAndTheSpan) {
  const Scene scene = one_box_scene();  // x 0.403..0.603, y -0.063..0.087, 0.1 high
  MapSnapshot s = perfect_snapshot(scene, 80, 0.01);
  const CellMask all = CellMask::Ones(80, 80);
  const MapScore perfect = score_map(s, all);
  EXPECT_EQ(perfect.rms_beyond_span_m, 0.0);
  EXPECT_EQ(perfect.rms_error_level_m, 0.0);
  // Grown by the margin, a cell reaching 4 mm (more than the sampling's
  // 3.3 mm) onto both floor and top is an edge cell; one on a single
  // surface is level.
  const double m = kObjectMarginM, x0 = 0.403, x1 = 0.603, y0 = -0.063, y1 = 0.087;
  Eigen::Index edge_i = -1, edge_j = -1, floor_i = -1, floor_j = -1, top_i = -1, top_j = -1, beside_i = -1,
               beside_j = -1;
  for (Eigen::Index i = 0; i < 80; ++i) {
    for (Eigen::Index j = 0; j < 80; ++j) {
      const double gx0 = (static_cast<double>(s.min_cell.x + i)) * 0.01 - m, gx1 = gx0 + 0.01 + 2 * m;
      const double gy0 = (static_cast<double>(s.min_cell.y + j)) * 0.01 - m, gy1 = gy0 + 0.01 + 2 * m;
      const double on_box = std::min(gx1, x1) - std::max(gx0, x0), on_box_y = std::min(gy1, y1) - std::max(gy0, y0);
      const bool touches_box = on_box > 0.0 && on_box_y > 0.0;
      const bool inside_box = gx0 >= x0 && gx1 <= x1 && gy0 >= y0 && gy1 <= y1;
      const bool clearly_both = on_box >= 0.004 && on_box_y >= 0.004 &&
                                (gx0 <= x0 - 0.004 || gx1 >= x1 + 0.004 || gy0 <= y0 - 0.004 || gy1 >= y1 + 0.004);
      const bool level = s.span_high_m(i, j) - s.span_low_m(i, j) <= 0.005f;
      if (!touches_box || inside_box) EXPECT_TRUE(level) << i << "," << j;
      if (clearly_both) EXPECT_FALSE(level) << i << "," << j;
      if (clearly_both && s.truth_m(i, j) > 0.05f && edge_i < 0) edge_i = i, edge_j = j;
      if (clearly_both && s.truth_m(i, j) == 0.0f && beside_i < 0) beside_i = i, beside_j = j;
      if (!touches_box && floor_i < 0) floor_i = i, floor_j = j;
      if (inside_box && top_i < 0) top_i = i, top_j = j;
    }
  }
  ASSERT_GE(edge_i, 0);
  ASSERT_GE(beside_i, 0);
  ASSERT_GE(floor_i, 0);
  ASSERT_GE(top_i, 0);
  s.elevation_m()(edge_i, edge_j) = 0.0f;       // the box's edge cell holds a floor reading
  s.elevation_m()(beside_i, beside_j) = 0.1f;   // the floor beside it, a top reading a few mm off
  const MapScore sampled = score_map(s, all);
  EXPECT_NEAR(sampled.max_error_m, 0.10, 1e-6);
  EXPECT_EQ(sampled.artifact_cells, 2u);
  EXPECT_EQ(sampled.rms_beyond_span_m, 0.0);
  EXPECT_EQ(sampled.beyond_span_artifact_cells, 0u);
  EXPECT_EQ(sampled.rms_error_level_m, 0.0);

  s.elevation_m()(floor_i, floor_j) = 0.03f;      // a phantom on the floor
  s.elevation_m()(top_i, top_j) = 0.10f + 0.04f;  // a spike on the top
  const MapScore wrong = score_map(s, all);
  EXPECT_EQ(wrong.beyond_span_artifact_cells, 2u);
  EXPECT_NEAR(wrong.max_beyond_span_m, 0.04, 1e-6);
  EXPECT_NEAR(wrong.rms_beyond_span_m, std::sqrt((0.03 * 0.03 + 0.04 * 0.04) / 6400.0), 1e-7);
  EXPECT_NEAR(wrong.rms_error_level_m,
              std::sqrt((0.03 * 0.03 + 0.04 * 0.04) / static_cast<double>(wrong.level_cells)), 1e-7);

  MapScoreOptions bad;
  bad.level_relief_m = -0.001;
  EXPECT_THROW(score_map(s, all, bad), InputError);
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

// The fill spans the shadowed gap between a box and a taller neighbour at
// their height; a region grown through filled cells would join the two.
TEST(ObjectExtents, AFilledGapDoesNotJoinTwoObjects) {
  Scene scene = one_box_scene();
  BoxObject neighbour = scene.boxes[0];
  neighbour.name = "neighbour";
  neighbour.center_y_m = scene.boxes[0].center_y_m + 0.5 * (0.15 + 0.10) + 0.03;  // a 3 cm gap
  neighbour.width_m = 0.10;
  neighbour.height_m = 0.15;
  scene.boxes.push_back(neighbour);
  const int n = 80;
  const double cell = 0.01;
  ElevationMap map({n, cell});
  map.move_to(0.5, 0.0);
  const double gap_lo_m = scene.boxes[0].center_y_m + 0.075, gap_hi_m = neighbour.center_y_m - 0.05;
  std::size_t filled = 0;
  for (int i = 0; i < n; ++i) {
    for (int j = 0; j < n; ++j) {
      const CellIndex c = map.cell_at_local(i, j);
      const double x0 = static_cast<double>(c.x) * cell, y0 = static_cast<double>(c.y) * cell;
      const std::size_t slot = map.slot(c);
      const double truth = scene.max_height_in_rect(x0, y0, x0 + cell, y0 + cell);
      const bool in_gap = y0 >= gap_lo_m && y0 + cell <= gap_hi_m && x0 >= 0.41 && x0 + cell <= 0.59;
      map.elevation_data()[slot] = static_cast<float>(in_gap ? 0.12 : truth);
      map.certainty_data()[slot] = in_gap ? 0.0f : 3.0f;
      map.state_data()[slot] = static_cast<std::uint8_t>(in_gap ? CellState::filled : CellState::measured);
      filled += in_gap ? 1 : 0;
    }
  }
  ASSERT_GT(filled, 20u);
  const MapSnapshot snapshot = snapshot_with_truth(map, scene);
  ObjectMeasureOptions options;
  options.region_measured_only = true;
  const auto objects = measure_objects(snapshot, scene, options);
  ASSERT_EQ(objects.size(), 2u);
  ASSERT_TRUE(objects[0].found);
  EXPECT_NEAR(objects[0].measured.width_m, 0.15, 0.0101);
  EXPECT_NEAR(objects[0].measured.length_m, 0.20, 0.0101);
  // Through the filled cells the two are one region.
  const auto joined = measure_objects(snapshot, scene);
  EXPECT_GT(joined[0].measured.width_m, 0.25);
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

constexpr double kSensorHeightM = 0.26, kTopM = 0.10;
const double kPitchRad = 35.0 * std::numbers::pi / 180.0;

// One box's map with 1 cm cells and its border cells' readings, the track
// along x through y = 0, beams every 2 mm across. Raised, a border cell
// keeps a reading 2-6 mm above the top, up its beam from where the beam met
// the top: on the sides along the track (`raise_sides`) inwards by the
// beam's across-track run, on the far side (`raise_far`) back towards the
// sensor by cot(pitch) per unit of height.
MapSnapshot border_reading_map(const Scene& scene, bool raise_sides, bool raise_far) {
  const BoxObject& box = scene.boxes[0];
  constexpr double cell = 0.01, spacing_m = 0.002;
  const double x0 = box.center_x_m - box.length_m / 2, x1 = box.center_x_m + box.length_m / 2;
  const double y0 = box.center_y_m - box.width_m / 2, y1 = box.center_y_m + box.width_m / 2;
  ElevationMap map({80, cell, {top_point_x_layer(), top_point_y_layer()}});
  map.move_to(0.5, 0.0);
  const TopPoints top_points(map);
  std::mt19937_64 rng(5);
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  for (int i = 0; i < 80; ++i) {
    for (int j = 0; j < 80; ++j) {
      const CellIndex c = map.cell_at_local(i, j);
      const double lo_x = static_cast<double>(c.x) * cell, lo_y = static_cast<double>(c.y) * cell;
      const std::size_t slot = map.slot(c);
      map.certainty_data()[slot] = 3.0f;
      map.state_data()[slot] = static_cast<std::uint8_t>(CellState::measured);
      const double cover_x0 = std::max(lo_x, x0), cover_x1 = std::min(lo_x + cell, x1);
      const double cover_y0 = std::max(lo_y, y0), cover_y1 = std::min(lo_y + cell, y1);
      double h = 0.0, x = lo_x + cell / 2, y = lo_y + cell / 2;
      if (cover_x0 < cover_x1 && cover_y0 < cover_y1) {
        h = kTopM;
        const bool side_border = cover_y1 - cover_y0 < cell;
        const bool far_border = cover_x1 < lo_x + cell;
        if (side_border || cover_x1 - cover_x0 < cell) {
          // The outermost beam on the covered part.
          const bool outward_up = y > box.center_y_m;
          y = outward_up ? spacing_m * std::floor(cover_y1 / spacing_m) : spacing_m * std::ceil(cover_y0 / spacing_m);
          x = std::clamp(x, cover_x0 + 0.001, cover_x1 - 0.001);
          const double dz = 0.002 + 0.004 * unit(rng);
          if (raise_sides && side_border) {
            y *= (kSensorHeightM - kTopM - dz) / (kSensorHeightM - kTopM);
            h += dz;
          } else if (raise_far && far_border) {
            x -= dz / std::tan(kPitchRad);
            h += dz;
          }
        }
      }
      map.elevation_data()[slot] = static_cast<float>(h);
      map.data(top_points.x_layer())[slot] = static_cast<float>(x);
      map.data(top_points.y_layer())[slot] = static_cast<float>(y);
    }
  }
  MapSnapshot snapshot = snapshot_with_truth(map, scene);
  const std::string layers[] = {"top_point_x", "top_point_y"};
  for (ExportedLayer& layer : export_map(map, layers).layers) snapshot.layers.push_back(std::move(layer));
  return snapshot;
}

ObjectMeasureOptions along_x_through_origin() {
  ObjectMeasureOptions options;
  options.travel_heading_rad = 0.0;
  options.travel_point_m = {0.0, 0.0};
  options.edges.view_heading_rad = 0.0;
  return options;
}

// A cell keeps its highest reading (eq. (10)), one whose range came short:
// it stands above the top and lies up its beam, towards the sensor, which
// at a side running along the track is inwards. With the scanner's height
// known the widths come out as from the readings where their beams meet the
// top; without it, millimetres short. The scan's pitch unknown, the near
// and far sides, and with them the lengths, keep their readings either way.
TEST(ObjectExtents, SidesAlongTheTrackTakeTheirReadingsBackDownTheirBeams) {
  const Scene scene = one_box_scene();
  ObjectMeasureOptions options = along_x_through_origin();
  const ObjectMeasurement on_the_top = measure_objects(border_reading_map(scene, false, false), scene, options)[0];
  const MapSnapshot raised = border_reading_map(scene, true, false);
  const ObjectMeasurement unknown = measure_objects(raised, scene, options)[0];
  options.sensor_height_m = kSensorHeightM;
  const ObjectMeasurement known = measure_objects(raised, scene, options)[0];
  ASSERT_TRUE(on_the_top.found && unknown.found && known.found);
  ASSERT_TRUE(std::isfinite(on_the_top.edges_trimmed.width_m) && std::isfinite(known.edges_trimmed.width_m));
  EXPECT_NEAR(known.measured.width_m, on_the_top.measured.width_m, 0.0005);
  EXPECT_LT(unknown.measured.width_m, on_the_top.measured.width_m - 0.0015);
  EXPECT_EQ(known.measured.length_m, unknown.measured.length_m);
}

// The far side's readings lie on the last scans over the top, the ones
// kept up their beams back towards the sensor, by cot(pitch) per unit of
// height: with the scan plane's pitch known the length comes out as from
// where the beams met the top; without it, millimetres short. The widths
// keep their readings.
TEST(ObjectExtents, FarSideTakesItsReadingsBackDownTheirBeamsWithThePitchKnown) {
  const Scene scene = one_box_scene();
  ObjectMeasureOptions options = along_x_through_origin();
  options.sensor_height_m = kSensorHeightM;
  options.sensor_pitch_rad = kPitchRad;
  const ObjectMeasurement on_the_top = measure_objects(border_reading_map(scene, false, false), scene, options)[0];
  const MapSnapshot raised = border_reading_map(scene, false, true);
  const ObjectMeasurement known = measure_objects(raised, scene, options)[0];
  options.sensor_pitch_rad = std::numeric_limits<double>::quiet_NaN();
  const ObjectMeasurement unknown = measure_objects(raised, scene, options)[0];
  ASSERT_TRUE(on_the_top.found && unknown.found && known.found);
  ASSERT_TRUE(std::isfinite(on_the_top.edges_trimmed.length_m) && std::isfinite(known.edges_trimmed.length_m));
  EXPECT_NEAR(known.measured.length_m, on_the_top.measured.length_m, 0.0005);
  EXPECT_LT(unknown.measured.length_m, on_the_top.measured.length_m - 0.002);
  EXPECT_NEAR(known.edge_errors_m[static_cast<int>(EdgeSide::far)],
              on_the_top.edge_errors_m[static_cast<int>(EdgeSide::far)], 0.0005);
  EXPECT_EQ(known.edge_errors_m[static_cast<int>(EdgeSide::near)], unknown.edge_errors_m[static_cast<int>(EdgeSide::near)]);
  EXPECT_EQ(known.measured.width_m, unknown.measured.width_m);
}

// A sensor that never lights a far side reads a top up to its last
// frame's stripe, up to a step before the edge: a far side square to the
// travel direction is placed half a step out, one turned far enough to
// meet many frames is left as read, and the other sides never move.
TEST(ObjectExtents, AnUnlitFarSideSquareToTheTravelIsPlacedHalfAStepOut) {
  const Scene scene = one_box_scene();
  const MapSnapshot map = border_reading_map(scene, false, false);
  ObjectMeasureOptions as_read = along_x_through_origin();
  ObjectMeasureOptions unlit = as_read;
  unlit.unlit_far_side_step_m = 0.01;
  const auto far = static_cast<int>(EdgeSide::far), near = static_cast<int>(EdgeSide::near);
  const ObjectMeasurement square_read = measure_objects(map, scene, as_read)[0];
  const ObjectMeasurement square_placed = measure_objects(map, scene, unlit)[0];
  ASSERT_TRUE(square_read.found && square_placed.found);
  ASSERT_TRUE(std::isfinite(square_read.edge_errors_m[far]));
  EXPECT_NEAR(square_placed.edge_errors_m[far] - square_read.edge_errors_m[far], 0.005, 1e-4);
  EXPECT_EQ(square_placed.edge_errors_m[near], square_read.edge_errors_m[near]);
  EXPECT_NEAR(square_placed.measured.length_m - square_read.measured.length_m, 0.005, 1e-4);
  EXPECT_EQ(square_placed.measured.width_m, square_read.measured.width_m);

  // Travelling 0.3 rad off the box's axis, its far side runs 15 cm x
  // sin(0.3) = 44 mm along the travel: more than a step.
  as_read.travel_heading_rad = unlit.travel_heading_rad = 0.3;
  const ObjectMeasurement turned_read = measure_objects(map, scene, as_read)[0];
  const ObjectMeasurement turned_placed = measure_objects(map, scene, unlit)[0];
  ASSERT_TRUE(turned_read.found && turned_placed.found);
  EXPECT_EQ(turned_placed.measured.length_m, turned_read.measured.length_m);
  EXPECT_EQ(turned_placed.measured.width_m, turned_read.measured.width_m);
}

TEST(ObjectExtents, OutOfRangeLevelOptionsAreInputErrors) {
  const Scene scene = one_box_scene();
  const MapSnapshot map = border_reading_map(scene, false, false);
  for (const double pitch : {0.0, -0.1, std::numbers::pi / 2, 2.0, std::numeric_limits<double>::infinity()}) {
    ObjectMeasureOptions options = along_x_through_origin();
    options.sensor_pitch_rad = pitch;
    EXPECT_THROW(measure_objects(map, scene, options), InputError) << pitch;
  }
  for (const double sds : {-0.5, std::numeric_limits<double>::quiet_NaN()}) {
    ObjectMeasureOptions options = along_x_through_origin();
    options.level_below_top_sds = sds;
    EXPECT_THROW(measure_objects(map, scene, options), InputError) << sds;
  }
  for (const double step : {0.0, -0.01, 1.0, std::numeric_limits<double>::infinity()}) {
    ObjectMeasureOptions options = along_x_through_origin();
    options.unlit_far_side_step_m = step;
    EXPECT_THROW(measure_objects(map, scene, options), InputError) << step;
  }
  ObjectMeasureOptions options = along_x_through_origin();
  options.sensor_pitch_rad = 0.6;
  options.unlit_far_side_step_m = 0.01;
  EXPECT_NO_THROW(measure_objects(map, scene, options));
}

TEST(ObjectExtents, EmptyMapFindsNothing) {
  const Scene scene = one_box_scene();
  MapSnapshot s = perfect_snapshot(scene, 40, 0.01);
  s.state().setConstant(static_cast<std::uint8_t>(CellState::unknown));
  const auto objects = measure_objects(s, scene);
  EXPECT_FALSE(objects[0].found);
}

}  // namespace
}  // namespace map_evaluation_test
}  // namespace stridemap
