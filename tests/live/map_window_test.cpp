// Placing a fixed window (`--window`, live/map_window.hpp): parsing, the
// centre's cell, the fit's size and corner, and its limits.
#include <gtest/gtest.h>

#include <string>

#include "stridemap/core/error.hpp"
#include "stridemap/live/map_window.hpp"

namespace stridemap {
namespace {

TEST(MapWindow, ParsesFollowFitAndACentre) {
  EXPECT_EQ(parse_window_choice("").mode, WindowChoice::Mode::follow);
  EXPECT_EQ(parse_window_choice("fit").mode, WindowChoice::Mode::fit);
  const WindowChoice c = parse_window_choice("1.5,-0.2");
  EXPECT_EQ(c.mode, WindowChoice::Mode::center);
  EXPECT_DOUBLE_EQ(c.center_m.x(), 1.5);
  EXPECT_DOUBLE_EQ(c.center_m.y(), -0.2);
}

TEST(MapWindow, BadTextIsAnErrorNamingTheOptionAndTheValue) {
  for (const std::string bad : {"1.5", "Fit", "a,b", "1,2,3", "inf,0", "2e6,0", "1,", " "}) {
    try {
      parse_window_choice(bad, "--window");
      ADD_FAILURE() << "accepted '" << bad << "'";
    } catch (const InputError& e) {
      const std::string what = e.what();
      EXPECT_EQ(what.rfind("--window: '" + bad + "'", 0), 0u) << what;
    }
  }
}

TEST(MapWindow, CentreLiesInTheWindowsCentreCell) {
  GridOptions grid;  // 100 cells of 10 mm
  const WindowPlacement w = window_centred_at(grid, {1.5, -0.2});
  EXPECT_EQ(w.cells_per_side, 100);
  EXPECT_EQ(w.min_cell, (CellIndex{100, -70}));
  ElevationMap map(grid);
  map.move_to(1.5, -0.2);  // the mapper's own placement agrees
  EXPECT_EQ(map.min_cell(), w.min_cell);
}

TEST(MapWindow, FitKeepsTheConfiguredSizeWhenTheRunFitsAndCentresIt) {
  GridOptions grid;
  FootprintExtent e;
  e.add(0.105, -0.2);
  e.add(0.305, 0.1);
  e.points = 2;
  const WindowPlacement w = window_fitting(grid, e);
  EXPECT_EQ(w.cells_per_side, 100);
  // x cells 10..30 (21 cells) centred: 39 cells of margin below; y -20..10 (31): 34 below.
  EXPECT_EQ(w.min_cell, (CellIndex{10 - 39, -20 - 34}));
}

TEST(MapWindow, FitGrowsTheMapToTheRunsLongerSide) {
  GridOptions grid;
  FootprintExtent e;
  e.add(-0.5, -1.0);
  e.add(4.495, 1.0);
  e.points = 2;
  const WindowPlacement w = window_fitting(grid, e);
  EXPECT_EQ(w.cells_per_side, 500);  // x cells -50..449
  EXPECT_EQ(w.min_cell.x, -50);
  ElevationMap map({w.cells_per_side, grid.cell_size_m});
  map.move_corner_to(w.min_cell);
  for (const auto& [x, y] : {std::pair{-0.5, -1.0}, {4.495, 1.0}, {-0.5, 1.0}, {4.495, -1.0}}) {
    EXPECT_TRUE(map.contains(map.cell_of(x, y))) << x << "," << y;
  }
}

TEST(MapWindow, FitBeyondTheGridLimitOrWithNothingIsAnError) {
  GridOptions grid;
  grid.cell_size_m = 0.001;
  FootprintExtent e;
  e.add(0.0, 0.0);
  e.add(5.0, 0.5);
  e.points = 2;
  try {
    window_fitting(grid, e);
    ADD_FAILURE() << "a 5 m run in 1 mm cells fitted";
  } catch (const GridSizeError& error) {
    const std::string what = error.what();
    EXPECT_NE(what.find("--window fit: the run's points span 5.00 x 0.50 m"), std::string::npos) << what;
    EXPECT_NE(what.find("5001 cells a side"), std::string::npos) << what;
    EXPECT_NE(what.find("beyond the limit of 4096"), std::string::npos) << what;
  }
  EXPECT_THROW(window_fitting(GridOptions{}, FootprintExtent{}), InputError);
}

}  // namespace
}  // namespace stridemap
