// The visibility clean-up (core/visibility_clearing.hpp) on cells set by
// hand, with beams whose geometry is worked out by hand: what a beam passes
// below is contradicted, what may hold its hit is not, and neither is a cell
// beside its path.
#include <gtest/gtest.h>

#include <cmath>
#include <string>

#include "stridemap/core/error.hpp"
#include "stridemap/core/visibility_clearing.hpp"

namespace stridemap {
namespace visibility_clearing_test {
namespace {

constexpr double kCell = 0.01;

// A 40 x 40 map of 1 cm cells from (0, 0), every cell measured at 0 m.
ElevationMap flat_map(float certainty = 9.0f) {
  ElevationMap map(GridOptions{40, kCell});
  map.move_corner_to({0, 0});
  const std::size_t cells = 40 * 40;
  for (std::size_t s = 0; s < cells; ++s) {
    map.elevation_data()[s] = 0.0f;
    map.certainty_data()[s] = certainty;
    map.state_data()[s] = static_cast<std::uint8_t>(CellState::measured);
  }
  return map;
}

void set_cell(ElevationMap& map, CellIndex c, float elevation_m, float certainty) {
  const std::size_t s = map.slot(c);
  map.elevation_data()[s] = elevation_m;
  map.certainty_data()[s] = certainty;
  map.state_data()[s] = static_cast<std::uint8_t>(CellState::measured);
}

// Along the row y = 0.105 m (cell row 10), from 0.5 cm at 0.20 m height
// down to the floor at x = 0.305 m: the beam falls 2/3 mm per mm, so over
// the cell from x = 0.15 to 0.16 it is between 0.1033 and 0.0967 m.
VisibilityBeam row_beam(double hit_x_m = 0.305, double range_error_m = 0.0, double height_error_m = 0.005) {
  VisibilityBeam b;
  b.origin_m = {0.005, 0.105, 0.20};
  b.hit_m = {hit_x_m, 0.105, 0.20 - (hit_x_m - 0.005) * (0.20 / 0.30)};
  b.range_error_m = range_error_m;
  b.height_error_m = height_error_m;
  return b;
}

TEST(VisibilityClearing, ABeamBelowATallCellClearsIt) {
  ElevationMap map = flat_map();
  // The beam crosses cell x = 25 (0.25..0.26 m) between 0.0367 and 0.0300 m.
  set_cell(map, {25, 10}, 0.10f, 3.0f);
  VisibilityClearing clearing(map, VisibilityOptions{});
  clearing.begin_scan(map);
  clearing.trace(map, row_beam());
  EXPECT_EQ(map.state({25, 10}), CellState::unknown);
  EXPECT_TRUE(std::isnan(map.elevation({25, 10})));
  EXPECT_EQ(clearing.stats().cells_cleared, 1u);
  ASSERT_EQ(clearing.cleared().size(), 1u);
  EXPECT_EQ(clearing.cleared()[0].cell, (CellIndex{25, 10}));
  EXPECT_FLOAT_EQ(clearing.cleared()[0].elevation_m, 0.10f);
  EXPECT_EQ(clearing.changed().min, (CellIndex{25, 10}));
  // The floor under the beam is left as it was.
  for (int x = 0; x < 40; ++x) {
    if (x != 25) EXPECT_EQ(map.elevation({x, 10}), 0.0f) << x;
  }
}

TEST(VisibilityClearing, CertaintyDecidesHowManyScansItTakes) {
  ElevationMap map = flat_map();
  set_cell(map, {25, 10}, 0.10f, 9.0f);
  VisibilityClearing clearing(map, VisibilityOptions{});
  for (int scan = 1; scan <= 2; ++scan) {
    clearing.begin_scan(map);
    // Two beams of one scan over the same cell count once.
    clearing.trace(map, row_beam(0.305));
    clearing.trace(map, row_beam(0.32));
    EXPECT_EQ(clearing.stats().cells_contradicted, 1u);
    EXPECT_FLOAT_EQ(map.certainty({25, 10}), 9.0f - 3.0f * scan);
    EXPECT_EQ(map.elevation({25, 10}), 0.10f);
  }
  clearing.begin_scan(map);
  clearing.trace(map, row_beam());
  EXPECT_EQ(map.state({25, 10}), CellState::unknown);
}

TEST(VisibilityClearing, TheMarginKeepsACellTheBeamPassesJustBelow) {
  ElevationMap map = flat_map();
  // Over cell 25 the beam reaches 0.0367 m; margin 5 mm + 1 cell = 15 mm.
  set_cell(map, {25, 10}, 0.050f, 3.0f);  // 13.3 mm above: kept
  set_cell(map, {20, 10}, 0.090f, 3.0f);  // beam 0.0700 m there: 20 mm above, cleared
  VisibilityClearing clearing(map, VisibilityOptions{});
  clearing.begin_scan(map);
  clearing.trace(map, row_beam());
  EXPECT_EQ(map.elevation({25, 10}), 0.050f);
  EXPECT_EQ(map.state({20, 10}), CellState::unknown);
}

TEST(VisibilityClearing, ABeamHittingAStepFaceLeavesTheStepAndItsNeighbours) {
  ElevationMap map = flat_map();
  // An 8 cm step from x = 0.25 m on; the beam meets its face at 0.0367 m,
  // measured 8 mm too far (range error 10 mm) inside the step's first cell.
  for (int x = 25; x < 40; ++x) {
    for (int y = 0; y < 40; ++y) set_cell(map, {x, y}, 0.08f, 3.0f);
  }
  const ElevationMap before = map;
  VisibilityClearing clearing(map, VisibilityOptions{});
  clearing.begin_scan(map);
  clearing.trace(map, row_beam(0.258, 0.010));
  for (int x = 0; x < 40; ++x) {
    for (int y = 0; y < 40; ++y) {
      EXPECT_EQ(map.elevation({x, y}), before.elevation({x, y})) << x << ", " << y;
      EXPECT_EQ(map.certainty({x, y}), before.certainty({x, y})) << x << ", " << y;
    }
  }
  EXPECT_EQ(clearing.stats().cells_contradicted, 0u);
  // Without the range error the same beam would have passed below the
  // step's first cell: the exclusion is what keeps it.
  clearing.begin_scan(map);
  clearing.trace(map, row_beam(0.268, 0.0));
  EXPECT_EQ(map.state({25, 10}), CellState::unknown);
}

TEST(VisibilityClearing, ACellBesideThePathIsNotTouched) {
  ElevationMap map = flat_map();
  set_cell(map, {25, 9}, 0.10f, 3.0f);
  set_cell(map, {25, 11}, 0.10f, 3.0f);
  VisibilityClearing clearing(map, VisibilityOptions{});
  clearing.begin_scan(map);
  clearing.trace(map, row_beam());
  EXPECT_EQ(map.elevation({25, 9}), 0.10f);
  EXPECT_EQ(map.elevation({25, 11}), 0.10f);
  // Cells 0..29 of row 10 lie before the hit (30 holds it), but no cell of
  // the rows and columns the beam crosses is above 0.10 m, which the beam
  // (0.20 m at t = 0, falling 0.20 m to the hit) comes down to within the
  // 15 mm margin at t = 0.575, x = 0.1775 m: the walk starts at cell 17.
  EXPECT_EQ(clearing.stats().cells_crossed, 13u);
}

TEST(VisibilityClearing, AFilledCellIsClearedAtOnceAndUnknownCellsStay) {
  ElevationMap map = flat_map();
  const std::size_t filled = map.slot({25, 10});
  map.elevation_data()[filled] = 0.10f;
  map.certainty_data()[filled] = 0.0f;
  map.state_data()[filled] = static_cast<std::uint8_t>(CellState::filled);
  map.reset_slot(map.slot({20, 10}));
  VisibilityClearing clearing(map, VisibilityOptions{});
  clearing.begin_scan(map);
  clearing.trace(map, row_beam());
  EXPECT_EQ(map.state({25, 10}), CellState::unknown);
  EXPECT_EQ(map.state({20, 10}), CellState::unknown);
  EXPECT_EQ(clearing.stats().cells_cleared, 1u);
}

TEST(VisibilityClearing, NeighbouringBeamsAreThinnedToOnePerCell) {
  ElevationMap map = flat_map();
  VisibilityOptions options;
  options.beam_spacing_cells = 1.0;
  VisibilityClearing clearing(map, options);
  clearing.begin_scan(map);
  VisibilityBeam beam = row_beam();
  for (int k = 0; k < 10; ++k) {
    beam.hit_m.y() = 0.105 + 0.002 * k;  // hits 2 mm apart: about every fifth is traced
    clearing.trace(map, beam);
  }
  EXPECT_EQ(clearing.stats().beams_traced, 2u);
}

TEST(VisibilityClearing, ThinnedTellsWhichBeamsTraceLeavesOut) {
  ElevationMap map = flat_map();
  VisibilityOptions options;
  options.beam_spacing_cells = 1.0;
  VisibilityClearing clearing(map, options);
  clearing.begin_scan(map);
  const VisibilityBeam first = row_beam();
  EXPECT_FALSE(clearing.thinned(first.hit_m.head<2>(), kCell));  // nothing traced yet this scan
  clearing.trace(map, first);
  VisibilityBeam near = first, far = first;
  near.hit_m.y() += 0.005;  // half a cell from the last traced hit
  far.hit_m.y() += 0.015;
  EXPECT_TRUE(clearing.thinned(near.hit_m.head<2>(), kCell));
  EXPECT_FALSE(clearing.thinned(far.hit_m.head<2>(), kCell));
  clearing.trace(map, near);
  EXPECT_EQ(clearing.stats().beams_traced, 1u);
  clearing.trace(map, far);
  EXPECT_EQ(clearing.stats().beams_traced, 2u);
  clearing.begin_scan(map);
  EXPECT_FALSE(clearing.thinned(near.hit_m.head<2>(), kCell));
}

TEST(VisibilityClearing, ARisingBeamStopsWhereItIsAboveEveryCell) {
  ElevationMap map = flat_map();
  // From 1 cm up along row 10 to 0.21 m at x = 0.305 m: over cell 2 it is
  // at most 0.0267 m, 7 cm below a 10 cm cell there.
  set_cell(map, {2, 10}, 0.10f, 3.0f);
  VisibilityBeam beam = row_beam();
  beam.origin_m.z() = 0.01;
  beam.hit_m.z() = 0.21;
  VisibilityClearing clearing(map, VisibilityOptions{});
  clearing.begin_scan(map);
  clearing.trace(map, beam);
  EXPECT_EQ(map.state({2, 10}), CellState::unknown);
  // The walk ends where the beam has risen to within the 15 mm margin of
  // the highest cell of its rows and columns, 0.10 m: at x = 0.1175 m, so
  // cells 0..10 are walked, not the 30 before the hit.
  EXPECT_EQ(clearing.stats().cells_crossed, 11u);
}

TEST(VisibilityClearing, BeginScanRefusesAMapOfAnotherSize) {
  ElevationMap map = flat_map();
  VisibilityClearing clearing(map, VisibilityOptions{});
  const ElevationMap other(GridOptions{20, kCell});
  try {
    clearing.begin_scan(other);
    FAIL() << "no error";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("20 cells a side"), std::string::npos) << e.what();
  }
}

TEST(VisibilityClearing, BadOptionsAreNamed) {
  const auto message = [](VisibilityOptions o) {
    try {
      validate_visibility_options(o);
    } catch (const InputError& e) {
      return std::string(e.what());
    }
    return std::string();
  };
  VisibilityOptions o;
  o.relief_factor = -1.0;
  EXPECT_NE(message(o).find("visibility: relief_factor"), std::string::npos) << message(o);
  o = {};
  o.certainty_decrement = 0.0;
  EXPECT_NE(message(o).find("certainty_decrement"), std::string::npos);
  o = {};
  o.uncertainty_factor = std::nan("");
  EXPECT_NE(message(o).find("uncertainty_factor"), std::string::npos);
  o = {};
  o.beam_spacing_cells = 1e9;
  EXPECT_NE(message(o).find("beam_spacing_cells"), std::string::npos);
  EXPECT_EQ(message(VisibilityOptions{}), "");
  o = {};
  o.relief_factor = -1.0;
  EXPECT_THROW(VisibilityClearing(ElevationMap(GridOptions{4, kCell}), o), InputError);
}

}  // namespace
}  // namespace visibility_clearing_test
}  // namespace stridemap
