#include "stridemap/core/grid_map.hpp"

#include <algorithm>
#include <cmath>
#include <cstring>
#include <functional>
#include <string>
#include <map>
#include <random>

#include <gtest/gtest.h>

#include "stridemap/core/error.hpp"
#include "stridemap/core/exported_map.hpp"

namespace stridemap {
namespace {

// Writes a value derived from each cell's global index, so that after any
// move a surviving cell can be checked for keeping exactly its own value.
float tag(CellIndex c) { return static_cast<float>(c.x * 1000 + c.y); }

void tag_all(ElevationMap& map) {
  for (int i = 0; i < map.cells_per_side(); ++i) {
    for (int j = 0; j < map.cells_per_side(); ++j) {
      const CellIndex c = map.cell_at_local(i, j);
      const std::size_t s = map.slot(c);
      map.elevation_data()[s] = tag(c);
      map.certainty_data()[s] = 1.0f;
      map.state_data()[s] = static_cast<std::uint8_t>(CellState::measured);
    }
  }
}

// Every cell in both windows keeps its tag; every newly exposed cell is unknown.
void expect_consistent_after_move(const ElevationMap& map, CellIndex old_min, int n) {
  for (int i = 0; i < n; ++i) {
    for (int j = 0; j < n; ++j) {
      const CellIndex c = map.cell_at_local(i, j);
      const bool was_inside = c.x >= old_min.x && c.x < old_min.x + n && c.y >= old_min.y && c.y < old_min.y + n;
      if (was_inside) {
        ASSERT_EQ(map.state(c), CellState::measured) << c.x << "," << c.y;
        ASSERT_EQ(map.elevation(c), tag(c));
      } else {
        ASSERT_EQ(map.state(c), CellState::unknown) << c.x << "," << c.y;
        ASSERT_TRUE(std::isnan(map.elevation(c)));
        ASSERT_EQ(map.certainty(c), 0.0f);
      }
    }
  }
}

TEST(ElevationMap, StartsUnknownAndCentred) {
  ElevationMap map;
  EXPECT_EQ(map.cells_per_side(), 100);
  EXPECT_DOUBLE_EQ(map.cell_size_m(), 0.01);
  EXPECT_TRUE(map.contains(map.cell_of(0.0, 0.0)));
  EXPECT_TRUE(map.contains(map.cell_of(-0.499, 0.499)));
  EXPECT_FALSE(map.contains(map.cell_of(0.501, 0.0)));
  EXPECT_EQ(map.state(map.cell_of(0.1, 0.1)), CellState::unknown);
  EXPECT_TRUE(std::isnan(map.elevation(map.cell_of(0.1, 0.1))));
}

TEST(ElevationMap, CellOfUsesFloorForNegativeCoordinates) {
  ElevationMap map;
  EXPECT_EQ(map.cell_of(-0.001, 0.0), (CellIndex{-1, 0}));
  EXPECT_EQ(map.cell_of(0.0199, -0.0201), (CellIndex{1, -3}));
  const Eigen::Vector2d c = map.cell_center({-1, 2});
  EXPECT_NEAR(c.x(), -0.005, 1e-12);
  EXPECT_NEAR(c.y(), 0.025, 1e-12);
}

TEST(ElevationMap, MovesInEveryDirectionKeepingSurvivingCells) {
  const int n = 12;
  const std::vector<std::pair<int, int>> moves = {{1, 0},  {-1, 0}, {0, 1},  {0, -1}, {3, 2},  {-3, 5},
                                                  {4, -7}, {-5, -5}, {11, 0}, {0, -11}, {11, 11}, {-11, 6}};
  for (const auto& [dx, dy] : moves) {
    ElevationMap map({n, 0.05});
    tag_all(map);
    const CellIndex old_min = map.min_cell();
    const std::size_t reset = map.move_corner_to({old_min.x + dx, old_min.y + dy});
    const std::size_t expected =
        static_cast<std::size_t>(n * n - (n - std::abs(dx)) * (n - std::abs(dy)));
    EXPECT_EQ(reset, expected) << dx << "," << dy;
    expect_consistent_after_move(map, old_min, n);
  }
}

TEST(ElevationMap, MoveLargerThanTheMapForgetsEverything) {
  ElevationMap map({10, 0.01});
  tag_all(map);
  EXPECT_EQ(map.move_corner_to({map.min_cell().x + 10, map.min_cell().y}), 100u);
  EXPECT_EQ(map.move_corner_to({map.min_cell().x - 1000, map.min_cell().y + 3}), 100u);
  tag_all(map);
  const CellIndex old_min = map.min_cell();
  map.move_corner_to({old_min.x + 25, old_min.y - 40});
  expect_consistent_after_move(map, old_min, 10);
}

TEST(ElevationMap, RandomWalkKeepsEveryCellConsistent) {
  const int n = 9;
  ElevationMap map({n, 0.02});
  std::mt19937_64 rng(3);
  std::uniform_int_distribution<int> step(-4, 4);
  // Reference: what each global cell should hold, tracked independently.
  std::map<std::pair<std::int64_t, std::int64_t>, float> truth;
  for (int k = 0; k < 300; ++k) {
    for (int i = 0; i < n; ++i) {
      for (int j = 0; j < n; ++j) {
        const CellIndex c = map.cell_at_local(i, j);
        if ((i + j + k) % 7 == 0) {
          const std::size_t s = map.slot(c);
          map.elevation_data()[s] = static_cast<float>(k);
          map.certainty_data()[s] = 1.0f;
          map.state_data()[s] = static_cast<std::uint8_t>(CellState::measured);
          truth[{c.x, c.y}] = static_cast<float>(k);
        }
      }
    }
    const CellIndex target{map.min_cell().x + step(rng), map.min_cell().y + step(rng)};
    map.move_corner_to(target);
    for (auto it = truth.begin(); it != truth.end();) {
      if (!map.contains({it->first.first, it->first.second})) {
        it = truth.erase(it);
      } else {
        ++it;
      }
    }
    for (int i = 0; i < n; ++i) {
      for (int j = 0; j < n; ++j) {
        const CellIndex c = map.cell_at_local(i, j);
        const auto found = truth.find({c.x, c.y});
        if (found == truth.end()) {
          ASSERT_EQ(map.state(c), CellState::unknown);
        } else {
          ASSERT_EQ(map.elevation(c), found->second);
        }
      }
    }
  }
}

// Every layer's bytes of `map` equal those of a map built at its corner and
// given, cell by cell, what `before` held there (cells outside `before`'s
// window keep their reset values): a move is a rebuild, on every layer.
void expect_move_equals_rebuild(const ElevationMap& map, const ElevationMap& before, const GridOptions& options,
                                const std::string& what) {
  ElevationMap rebuilt(options);
  rebuilt.move_corner_to(map.min_cell());
  const int n = map.cells_per_side();
  for (std::size_t l = 0; l < map.layer_count(); ++l) {
    const std::size_t bytes = layer_type_bytes(map.layer_spec(l).type);
    for (int i = 0; i < n; ++i) {
      for (int j = 0; j < n; ++j) {
        const CellIndex c = map.cell_at_local(i, j);
        if (!before.contains(c)) continue;
        std::memcpy(static_cast<char*>(rebuilt.layer_bytes(l)) + rebuilt.slot(c) * bytes,
                    static_cast<const char*>(before.layer_bytes(l)) + before.slot(c) * bytes, bytes);
      }
    }
    for (int i = 0; i < n; ++i) {
      for (int j = 0; j < n; ++j) {
        const CellIndex c = map.cell_at_local(i, j);
        ASSERT_EQ(0, std::memcmp(static_cast<const char*>(map.layer_bytes(l)) + map.slot(c) * bytes,
                                 static_cast<const char*>(rebuilt.layer_bytes(l)) + rebuilt.slot(c) * bytes, bytes))
            << what << ": layer " << map.layer_spec(l).name << ", cell " << c.x << "," << c.y;
      }
    }
  }
}

// Random contents in every layer (the built-in ones and extra layers of each
// type with reset values other than 0), then moves along x only, along y
// only and along both, by 1 cell up to more than the window, from corners on
// either side of the circular buffer's seam: each result is a rebuild.
TEST(ElevationMap, MoveOnEitherAxisEqualsARebuildOnEveryLayer) {
  std::mt19937_64 rng(17);
  std::uniform_real_distribution<float> value(-1.0f, 1.0f);
  std::uniform_int_distribution<int> byte(0, 255);
  for (const int n : {1, 2, 7, 16, 33}) {
    GridOptions options{n, 0.01, {}};
    options.extra_layers = {{"height_a", LayerType::f32, -2.5, "m", "test", true},
                            {"count_b", LayerType::u16, 9.0, "", "test", true},
                            {"flag_c", LayerType::u8, 255.0, "", "test", true}};
    ElevationMap map(options);
    std::uniform_int_distribution<int> step(-n - 1, n + 1);
    for (int k = 0; k < 120; ++k) {
      for (std::size_t l = 0; l < map.layer_count(); ++l) {
        auto* bytes = static_cast<unsigned char*>(map.layer_bytes(l));
        const std::size_t size = static_cast<std::size_t>(n) * static_cast<std::size_t>(n) *
                                 layer_type_bytes(map.layer_spec(l).type);
        if (map.layer_spec(l).type == LayerType::f32) {
          float* f = map.data(LayerId<float>{l});
          for (std::size_t s = 0; s < size / 4; ++s) f[s] = value(rng);
        } else {
          for (std::size_t s = 0; s < size; ++s) bytes[s] = static_cast<unsigned char>(byte(rng));
        }
      }
      const ElevationMap before = map;
      const int axis = k % 3;  // x only, y only, both
      const int dx = axis == 1 ? 0 : step(rng), dy = axis == 0 ? 0 : step(rng);
      const CellIndex old_min = map.min_cell();
      const std::size_t reset = map.move_corner_to({old_min.x + dx, old_min.y + dy});
      const int kept_x = std::max(0, n - std::abs(dx)), kept_y = std::max(0, n - std::abs(dy));
      EXPECT_EQ(reset, static_cast<std::size_t>(n * n - kept_x * kept_y));
      expect_move_equals_rebuild(map, before, options,
                                 "n " + std::to_string(n) + ", move " + std::to_string(dx) + "," + std::to_string(dy));
      if (HasFatalFailure()) return;
    }
  }
}

TEST(ElevationMap, ForgettingAMeasurementLeavesTheDerivedLayersOnly) {
  GridOptions options{8, 0.01};
  options.extra_layers = {{"visits", LayerType::u16, 5.0, "", "a user's counter", true},
                          {"derived_height", LayerType::f32, -1.0, "m", "kept by a keeper", true}};
  ElevationMap map(options);
  tag_all(map);
  const LayerId<std::uint16_t> visits = map.layer<std::uint16_t>("visits");
  const LayerId<float> derived = map.layer<float>("derived_height");
  map.mark_derived(derived.index);
  const CellIndex c = map.cell_at_local(3, 4), other = map.cell_at_local(3, 5);
  map.data(visits)[map.slot(c)] = 42;
  map.data(derived)[map.slot(c)] = 0.25f;
  map.mean_count_data()[map.slot(c)] = 3;
  ElevationMap copy = map;
  EXPECT_TRUE(copy.derived(derived.index));
  EXPECT_FALSE(copy.derived(visits.index));
  map.forget_measurement(map.slot(c));
  EXPECT_EQ(map.state(c), CellState::unknown);
  EXPECT_TRUE(std::isnan(map.elevation(c)));
  EXPECT_EQ(map.certainty(c), 0.0f);
  EXPECT_EQ(map.mean_count_data()[map.slot(c)], 0);
  EXPECT_EQ(map.data(visits)[map.slot(c)], 5);
  EXPECT_EQ(map.data(derived)[map.slot(c)], 0.25f);  // its keeper's to redo
  EXPECT_EQ(map.elevation(other), tag(other));
  map.reset_slot(map.slot(c));
  EXPECT_EQ(map.data(derived)[map.slot(c)], -1.0f);
}

TEST(ElevationMap, MoveToCentresTheRobotCell) {
  ElevationMap map({100, 0.01});
  map.move_to(1.234, -0.567);
  const CellIndex robot = map.cell_of(1.234, -0.567);
  EXPECT_EQ(robot.x - map.min_cell().x, 50);
  EXPECT_EQ(robot.y - map.min_cell().y, 50);
  EXPECT_EQ(map.move_to(std::nan(""), 0.0), 0u);
  EXPECT_EQ(map.move_to(1e300, 0.0), 0u);
  EXPECT_EQ(map.cell_of(1.234, -0.567), robot);
}

TEST(ElevationMap, FastSlotLookupAgreesWithCellIndexing) {
  ElevationMap map({37, 0.013});
  std::mt19937_64 rng(5);
  std::uniform_real_distribution<double> xy(-2.0, 2.0);
  std::uniform_int_distribution<int> step(-50, 50);
  for (int k = 0; k < 50; ++k) {
    map.move_corner_to({step(rng), step(rng)});
    for (int p = 0; p < 200; ++p) {
      const double x = xy(rng), y = xy(rng);
      std::size_t slot = 0;
      const bool inside = map.slot_at(x, y, slot);
      ASSERT_EQ(inside, map.contains(map.cell_of(x, y)));
      if (inside) ASSERT_EQ(slot, map.slot(map.cell_of(x, y)));
    }
  }
  // Points exactly on cell boundaries, both signs.
  for (int k = -300; k <= 300; ++k) {
    const double x = k * 0.013, y = -k * 0.013;
    std::size_t slot = 0;
    const bool inside = map.slot_at(x, y, slot);
    ASSERT_EQ(inside, map.contains(map.cell_of(x, y))) << k;
    if (inside) ASSERT_EQ(slot, map.slot(map.cell_of(x, y))) << k;
  }
  std::size_t slot = 0;
  EXPECT_FALSE(map.slot_at(std::nan(""), 0.0, slot));
  EXPECT_FALSE(map.slot_at(0.0, 1e300, slot));
}

TEST(ElevationMap, ExportUsesWindowOrder) {
  ElevationMap map({4, 0.1});
  const CellIndex c = map.cell_at_local(1, 2);
  map.elevation_data()[map.slot(c)] = 5.0f;
  map.move_corner_to({map.min_cell().x + 1, map.min_cell().y});
  EXPECT_EQ(export_map(map).elevation_m()(0, 2), 5.0f);
}

TEST(ElevationMap, RejectsUnusableOptions) {
  EXPECT_THROW(ElevationMap({0, 0.01}), InputError);
  EXPECT_THROW(ElevationMap({100, 0.0}), InputError);
  EXPECT_THROW(ElevationMap({100, -0.01}), InputError);
  EXPECT_THROW(ElevationMap({100, std::nan("")}), InputError);
  try {
    ElevationMap({100, -1.0});
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("cell_size_m"), std::string::npos);
  }
}

}  // namespace
}  // namespace stridemap

namespace stridemap {
namespace {

std::string grid_error(const std::function<void()>& run) {
  try {
    run();
  } catch (const GridSizeError& e) {
    return e.what();
  }
  ADD_FAILURE() << "no GridSizeError";
  return {};
}

TEST(GridSize, AbsurdGridsAreRefusedBeforeAllocatingWithTheMemoryTheyWouldTake) {
  EXPECT_NE(grid_error([] { ElevationMap map(GridOptions{20000, 0.01}); })
                .find("cells_per_side must be between 1 and 4096, got 20000: 20000 x 20000 cells need 8.0 GB; the "
                      "limit is 4096 cells per side (335.5 MB)"),
            std::string::npos);
  EXPECT_NE(grid_error([] { ElevationMap map(GridOptions{-5, 0.01}); }).find("got -5"), std::string::npos);
  for (const double bad : {0.0, -0.01, std::nan(""), 1e300, 1e-5, HUGE_VAL}) {
    EXPECT_NE(grid_error([bad] { ElevationMap map(GridOptions{100, bad}); })
                  .find("cell_size_m must be between 0.0001 and 10 m"),
              std::string::npos)
        << bad;
  }
  // The largest accepted grid is usable.
  EXPECT_NO_THROW(validate_grid_options(GridOptions{kMaxGridCellsPerSide, kMinCellSizeM}));
  EXPECT_EQ(static_cast<double>(kMaxGridCellsPerSide) * kMaxGridCellsPerSide * kGridBytesPerCell, 335544320.0);
}

TEST(GridSize, CoveringAnAreaIsCheckedBeforeTheCountBecomesAnInt) {
  EXPECT_EQ(cells_per_side_to_cover(1.0, 0.01), 100);
  EXPECT_EQ(cells_per_side_to_cover(0.0, 0.01), 1);
  EXPECT_EQ(cells_per_side_to_cover(2.1, 0.05), 42);
  // The case that once passed: 0.1 mm cells over a 2.1 m rail scene.
  EXPECT_NE(grid_error([] { cells_per_side_to_cover(2.1, 1e-4); })
                .find("a 0.1 mm map of this 2.10 m area needs 21000 x 21000 cells, 8.8 GB; the limit is 4096"),
            std::string::npos);
  // Before the fix these converted an out-of-range double to int (UB).
  for (const double bad : {0.0, std::nan(""), -1.0}) {
    EXPECT_NE(grid_error([bad] { cells_per_side_to_cover(2.1, bad); }).find("cell_size_m must be between"),
              std::string::npos);
  }
  EXPECT_NE(grid_error([] { cells_per_side_to_cover(HUGE_VAL, 0.01); }).find("finite size"), std::string::npos);
  EXPECT_NE(grid_error([] { cells_per_side_to_cover(1e300, 10.0); }).find("cells"), std::string::npos);
}

TEST(GridSize, ByteSizesReadAsAPersonWouldWriteThem) {
  EXPECT_EQ(byte_size_text(512), "512 B");
  EXPECT_EQ(byte_size_text(20e3), "20.0 kB");
  EXPECT_EQ(byte_size_text(9.7e9), "9.7 GB");
}

}  // namespace
}  // namespace stridemap
