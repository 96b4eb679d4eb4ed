#include "stridemap/mapfile/tile_store.hpp"

#include <bit>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <memory>
#include <random>

#include <gtest/gtest.h>

#include "cli/cli_runner.hpp"
#include "live/test_folder.hpp"
#include "stridemap/config/mapper_config.hpp"
#include "stridemap/core/error.hpp"
#include "stridemap/core/terrain_mapper.hpp"

namespace stridemap {
namespace {

using test::TestFolder;

constexpr int kWindowCells = 20;
constexpr double kCellM = 0.1;

MapperOptions mapper_options() {
  MapperOptions o;
  o.grid.cells_per_side = kWindowCells;
  o.grid.cell_size_m = kCellM;
  // A user's layer goes along like the built-in ones.
  o.grid.extra_layers.push_back(LayerSpec{"hit_count", LayerType::u16, 0.0, "", "hits", true});
  o.reject_stale_scans = false;
  return o;
}

// Every layer of every cell of the window set to something different, NaN
// payloads included: what must come back byte for byte.
void scramble_window(ElevationMap& map, std::uint32_t seed) {
  std::mt19937 random(seed);
  const std::size_t cells = static_cast<std::size_t>(kWindowCells) * kWindowCells;
  for (std::size_t l = 0; l < map.layer_count(); ++l) {
    auto* bytes = static_cast<unsigned char*>(map.layer_bytes(l));
    const std::size_t size = cells * layer_type_bytes(map.layer_spec(l).type);
    for (std::size_t b = 0; b < size; ++b) bytes[b] = static_cast<unsigned char>(random());
  }
  // The built-in layers within what a valid cell may hold, since the map
  // file's reader refuses anything else: unknown cells a NaN (payload kept)
  // and no certainty, measured ones a finite elevation and certainty > 0.
  for (std::size_t s = 0; s < cells; ++s) {
    const auto state = static_cast<std::uint8_t>(s % 3);
    map.state_data()[s] = state;
    float& elevation = map.elevation_data()[s];
    float& certainty = map.certainty_data()[s];
    if (state == static_cast<std::uint8_t>(CellState::unknown)) {
      elevation = std::bit_cast<float>(std::bit_cast<std::uint32_t>(elevation) | 0x7fc00000u);
      certainty = 0.0f;
      continue;
    }
    if (!std::isfinite(elevation)) elevation = 0.5f;
    certainty = state == static_cast<std::uint8_t>(CellState::measured)
                    ? (std::isfinite(certainty) && certainty != 0.0f ? std::fabs(certainty) : 1.0f)
                    : 0.0f;
  }
}

// Cells of `a`'s window whose bytes differ from `b`'s in any layer; a cell
// `b` does not cover counts as differing unless `a` holds nothing there.
std::size_t differing_cells(const ElevationMap& a, const ElevationMap& b) {
  std::size_t differ = 0;
  for (int i = 0; i < a.cells_per_side(); ++i) {
    for (int j = 0; j < a.cells_per_side(); ++j) {
      const CellIndex c = a.cell_at_local(i, j);
      if (!b.contains(c)) {
        differ += a.state(c) != CellState::unknown || !std::isnan(a.elevation(c));
        continue;
      }
      for (std::size_t l = 0; l < a.layer_count(); ++l) {
        const std::size_t size = layer_type_bytes(a.layer_spec(l).type);
        if (std::memcmp(static_cast<const unsigned char*>(a.layer_bytes(l)) + a.slot(c) * size,
                        static_cast<const unsigned char*>(b.layer_bytes(l)) + b.slot(c) * size, size) != 0) {
          ++differ;
          break;
        }
      }
    }
  }
  return differ;
}

TrunkPose at(double x_m, double y_m) {
  TrunkPose p;
  p.x_m = x_m;
  p.y_m = y_m;
  return p;
}

void drive_to(TerrainMapper& mapper, double x_m, double y_m) { mapper.integrate_points({}, at(x_m, y_m)); }

GlobalMapOptions tiles_in(const std::string& folder, int tile_cells, int cached_tiles) {
  GlobalMapOptions o;
  o.folder = folder;
  o.tile_cells = tile_cells;
  o.cached_tiles = cached_tiles;
  return o;
}

// Drives from the start along a random walk of small steps (each move keeps
// part of the window) far beyond the window and tiles, then straight back.
void drive_away_and_back(TerrainMapper& mapper, std::uint32_t seed, double start_x, double start_y) {
  std::mt19937 random(seed);
  std::uniform_real_distribution<double> step(-0.35, 0.6);
  double x = start_x, y = start_y;
  for (int k = 0; k < 60; ++k) {
    x += step(random);
    y += step(random) * 0.7;
    drive_to(mapper, x, y);
  }
  for (int k = 1; k <= 40; ++k) {
    const double f = static_cast<double>(k) / 40.0;
    drive_to(mapper, x + f * (start_x - x), y + f * (start_y - y));
  }
}

TEST(TileStore, ARobotDrivingAwayAndBackGetsItsCellsBackBitForBit) {
  for (const auto& [tile_cells, cached] : {std::pair{8, 1}, std::pair{8, 16}, std::pair{7, 3}, std::pair{50, 2}}) {
    for (std::uint32_t seed : {1u, 2u, 3u}) {
      TestFolder folder;
      TerrainMapper mapper(mapper_options(), SensorMount{});
      const double start_x = -0.37 * seed, start_y = 0.21 * seed;
      drive_to(mapper, start_x, start_y);
      io::TileStore store(tiles_in(folder / "tiles", tile_cells, cached), mapper.map(), {});
      mapper.set_window_listener(&store);
      scramble_window(mapper.map(), seed);
      const ElevationMap before = mapper.map();
      drive_away_and_back(mapper, seed, start_x, start_y);
      ASSERT_EQ(mapper.map().min_cell(), before.min_cell());
      EXPECT_EQ(differing_cells(before, mapper.map()), 0u) << "tile_cells " << tile_cells << ", seed " << seed;
      EXPECT_GT(store.stats().cells_restored, 0u);
      // Tiles are made only for ground seen, all near the start: a cache
      // smaller than the tiles the start window spans sends some to disk.
      if (cached < 4 && tile_cells < 10) {
        EXPECT_GT(store.tiles_on_disk().size(), 0u);
        EXPECT_GT(store.stats().tiles_read, 0u) << "the small cache must have sent tiles to disk";
      }
    }
  }
}

TEST(TileStore, AfterAFlushTheTilesOnDiskHoldTheWindowAndEverythingThatLeftIt) {
  TestFolder folder;
  TerrainMapper mapper(mapper_options(), SensorMount{});
  io::TileStore store(tiles_in(folder / "tiles", 8, 2), mapper.map(), {});
  mapper.set_window_listener(&store);
  scramble_window(mapper.map(), 7);
  const ElevationMap first = mapper.map();
  drive_to(mapper, 3.3, -1.7);  // no overlap: the whole first window leaves
  scramble_window(mapper.map(), 8);
  drive_to(mapper, 4.1, -1.2);  // overlapping: some cells leave, some stay
  store.flush(mapper.map());
  const ElevationMap& window = mapper.map();
  // Each cell of the window, read from its own tile file; where no tile
  // was made, the window holds nothing there.
  ElevationMap blank(mapper_options().grid);
  blank.move_corner_to(window.min_cell());
  std::size_t differ = 0, from_files = 0;
  for (int i = 0; i < kWindowCells; ++i) {
    for (int j = 0; j < kWindowCells; ++j) {
      const CellIndex c = window.cell_at_local(i, j);
      const std::string path = store.tile_path(store.tile_of(c));
      const bool made = std::filesystem::exists(path);
      const io::MapFile tile = made ? io::load_map_file(path) : io::MapFile{blank, {}};
      from_files += made;
      ASSERT_TRUE(tile.map.contains(c));
      for (std::size_t l = 0; l < window.layer_count(); ++l) {
        const std::size_t size = layer_type_bytes(window.layer_spec(l).type);
        differ += std::memcmp(static_cast<const unsigned char*>(window.layer_bytes(l)) + window.slot(c) * size,
                              static_cast<const unsigned char*>(tile.map.layer_bytes(l)) + tile.map.slot(c) * size,
                              size) != 0;
      }
    }
  }
  EXPECT_EQ(differ, 0u);
  EXPECT_GT(from_files, static_cast<std::size_t>(kWindowCells * kWindowCells / 4));
  // One map of all tiles: the first window and the last, and nothing that
  // was never seen in between.
  const io::MergedTiles merged_tiles = io::merge_tiles(folder / "tiles");
  EXPECT_TRUE(merged_tiles.holes.empty());
  const ElevationMap& merged = merged_tiles.map;
  EXPECT_EQ(differing_cells(window, merged), 0u);
  // The first window's cells that the last one did not cover come back from the tiles.
  std::size_t first_differ = 0, compared = 0;
  for (int i = 0; i < kWindowCells; ++i) {
    for (int j = 0; j < kWindowCells; ++j) {
      const CellIndex c = first.cell_at_local(i, j);
      if (window.contains(c)) continue;
      ++compared;
      first_differ += merged.elevation(c) != first.elevation(c) &&
                      !(std::isnan(merged.elevation(c)) && std::isnan(first.elevation(c)));
      first_differ += merged.state(c) != first.state(c);
    }
  }
  EXPECT_GT(compared, 0u);
  EXPECT_EQ(first_differ, 0u);
  EXPECT_EQ(merged.layer_count(), window.layer_count());
}

// A walk far from the start, the window scrambled on the way so that
// every tile it crosses holds something; the same on every call.
void walk_and_scramble(TerrainMapper& mapper, std::uint32_t seed) {
  std::mt19937 random(seed);
  std::uniform_real_distribution<double> step(-0.2, 0.6);
  double x = 0.0, y = 0.0;
  for (int k = 0; k < 80; ++k) {
    if (k % 4 == 0) scramble_window(mapper.map(), seed * 1000 + static_cast<std::uint32_t>(k));
    x += step(random);
    y += step(random) * 0.5;
    drive_to(mapper, x, y);
  }
}

TEST(TileStore, ARunKilledWithoutFlushKeepsEveryTileTheWindowLeft) {
  // A cache large enough that nothing is ever pushed out of memory: only
  // writing the tiles the window leaves puts them on disk before the end.
  for (std::uint32_t seed : {1u, 2u, 3u}) {
    TestFolder folder;
    {  // The reference: the same walk, flushed at the end.
      TerrainMapper mapper(mapper_options(), SensorMount{});
      io::TileStore store(tiles_in(folder / "flushed", 8, 1024), mapper.map(), {});
      mapper.set_window_listener(&store);
      walk_and_scramble(mapper, seed);
      store.flush(mapper.map());
    }
    CellIndex last_min;
    {  // Stopped abruptly: no flush, the store and mapper simply gone.
      TerrainMapper mapper(mapper_options(), SensorMount{});
      auto store = std::make_unique<io::TileStore>(tiles_in(folder / "killed", 8, 1024), mapper.map(),
                                                   io::MapFileMetadata{});
      mapper.set_window_listener(store.get());
      walk_and_scramble(mapper, seed);
      last_min = mapper.map().min_cell();
      EXPECT_EQ(store->stats().tiles_read, 0u) << "nothing was pushed out of memory";
    }
    // Every tile the last window does not reach is on disk as in the
    // flushed run; only those it touches (at most 4 x 4 here) may be missing or old.
    const auto touched = [&](const io::TileIndex& t) {
      return t.x * 8 < last_min.x + kWindowCells && (t.x + 1) * 8 > last_min.x && t.y * 8 < last_min.y + kWindowCells &&
             (t.y + 1) * 8 > last_min.y;
    };
    std::size_t kept = 0, lost = 0;
    for (const auto& e : std::filesystem::directory_iterator(folder / "flushed")) {
      const std::string name = e.path().filename().string();
      if (name == io::kGlobalMapManifest) continue;
      long long tx = 0, ty = 0;
      ASSERT_EQ(std::sscanf(name.c_str(), "tile_%lld_%lld", &tx, &ty), 2) << name;
      const io::TileIndex t{tx, ty};
      const std::filesystem::path killed = std::filesystem::path(folder / "killed") / name;
      if (touched(t)) {
        lost += !std::filesystem::exists(killed);
        continue;
      }
      ASSERT_TRUE(std::filesystem::exists(killed)) << name << " was left by the window but not written";
      const io::MapFile a = io::load_map_file(e.path().string());
      const io::MapFile b = io::load_map_file(killed.string());
      EXPECT_EQ(differing_cells(a.map, b.map), 0u) << name;
      ++kept;
    }
    EXPECT_GT(kept, 20u) << "seed " << seed;
    EXPECT_LE(lost, 16u);
  }
}

TEST(TileStore, UnseenGroundLeavesNoTiles) {
  TestFolder folder;
  TerrainMapper mapper(mapper_options(), SensorMount{});
  io::TileStore store(tiles_in(folder / "tiles", 8, 4), mapper.map(), {});
  mapper.set_window_listener(&store);
  for (int k = 0; k < 50; ++k) drive_to(mapper, 0.3 * k, 0.0);
  store.flush(mapper.map());
  EXPECT_EQ(store.tiles_on_disk().size(), 0u);
  std::size_t files = 0;
  for (const auto& e : std::filesystem::directory_iterator(folder / "tiles")) files += e.is_regular_file();
  EXPECT_EQ(files, 1u) << "only the manifest";
}

TEST(TileStore, RefusesAFolderThatHoldsAnythingOrIsAFile) {
  TestFolder folder;
  const ElevationMap map(mapper_options().grid);
  std::filesystem::create_directories(folder / "used");
  folder.write("used/notes.txt", "mine");
  try {
    io::TileStore store(tiles_in(folder / "used", 8, 4), map, {});
    FAIL() << "a folder with a file in it was taken";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find(folder / "used"), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find("notes.txt"), std::string::npos) << e.what();
  }
  EXPECT_EQ(folder.read("used/notes.txt"), "mine");
  folder.write("plain", "x");
  EXPECT_THROW(io::TileStore(tiles_in(folder / "plain", 8, 4), map, {}), InputError);
  EXPECT_THROW(io::TileStore(tiles_in(folder / "new", 0, 4), map, {}), InputError);
  EXPECT_THROW(io::TileStore(tiles_in(folder / "new2", 8, 0), map, {}), InputError);
  // An empty folder is taken.
  std::filesystem::create_directories(folder / "empty");
  EXPECT_NO_THROW(io::TileStore(tiles_in(folder / "empty", 8, 4), map, {}));
}

bool any_notice_holds(const std::vector<std::string>& notices, const std::string& a, const std::string& b = "") {
  for (const std::string& n : notices) {
    if (n.find(a) != std::string::npos && n.find(b) != std::string::npos) return true;
  }
  return false;
}

std::string joined(const std::vector<std::string>& lines) {
  std::string all;
  for (const std::string& l : lines) all += l + "\n";
  return all;
}

TEST(TileStore, ADamagedTileIsSetAsideNamedAndMappedAround) {
  TestFolder folder;
  TerrainMapper mapper(mapper_options(), SensorMount{});
  io::TileStore store(tiles_in(folder / "tiles", 8, 1), mapper.map(), {});
  mapper.set_window_listener(&store);
  scramble_window(mapper.map(), 3);
  for (int k = 1; k <= 40; ++k) drive_to(mapper, 0.25 * k, 0.0);  // everything to disk through the one-tile cache
  ASSERT_FALSE(store.tiles_on_disk().empty());
  const std::string damaged = store.tile_path(store.tile_of({0, 0}));
  ASSERT_TRUE(std::filesystem::exists(damaged));
  {
    std::fstream f(damaged, std::ios::in | std::ios::out | std::ios::binary);
    f.seekp(200);
    f.put('\x5a');
  }
  const std::string damaged_bytes = folder.read("tiles/" + std::filesystem::path(damaged).filename().string());
  ASSERT_NO_THROW(for (int k = 40; k >= 0; --k) drive_to(mapper, 0.25 * k, 0.0));
  const std::vector<std::string> notices = store.take_notices();
  EXPECT_TRUE(any_notice_holds(notices, damaged, "checksum")) << joined(notices);
  EXPECT_TRUE(any_notice_holds(notices, "set aside as " + damaged + ".damaged")) << joined(notices);
  EXPECT_EQ(store.stats().tiles_set_aside, 1u);
  // Kept byte for byte for whoever looks into it; its cells start unknown.
  EXPECT_EQ(folder.read("tiles/" + std::filesystem::path(damaged).filename().string() + ".damaged"), damaged_bytes);
  EXPECT_EQ(mapper.map().state({0, 0}), CellState::unknown);
  EXPECT_TRUE(store.take_notices().empty()) << "each problem is told once";
  // The tile is written anew; the merge has no hole.
  store.flush(mapper.map());
  EXPECT_FALSE(store.failing());
  const io::MergedTiles merged = io::merge_tiles(folder / "tiles");
  EXPECT_TRUE(merged.holes.empty()) << joined(merged.holes);
}

TEST(TileStore, AMissingTileIsNamedAndMappedAround) {
  TestFolder folder;
  TerrainMapper mapper(mapper_options(), SensorMount{});
  io::TileStore store(tiles_in(folder / "tiles", 8, 1), mapper.map(), {});
  mapper.set_window_listener(&store);
  scramble_window(mapper.map(), 5);
  for (int k = 1; k <= 40; ++k) drive_to(mapper, 0.25 * k, 0.0);
  const std::string gone = store.tile_path(store.tile_of({0, 0}));
  ASSERT_TRUE(std::filesystem::remove(gone));
  ASSERT_NO_THROW(for (int k = 40; k >= 0; --k) drive_to(mapper, 0.25 * k, 0.0));
  const std::vector<std::string> notices = store.take_notices();
  EXPECT_TRUE(any_notice_holds(notices, gone, "mapped anew")) << joined(notices);
  EXPECT_EQ(store.stats().tiles_set_aside, 1u);
}

// The folder replaced by a file fails every write, even for root (CI's user).
TEST(TileStore, AFailedWriteKeepsTheTilesInMemoryUntilASaveWritesThemBitForBit) {
  TestFolder folder;
  TerrainMapper faulty(mapper_options(), SensorMount{});
  TerrainMapper reference(mapper_options(), SensorMount{});
  io::TileStore store(tiles_in(folder / "tiles", 8, 1), faulty.map(), {});
  io::TileStore reference_store(tiles_in(folder / "reference", 8, 1), reference.map(), {});
  faulty.set_window_listener(&store);
  reference.set_window_listener(&reference_store);
  scramble_window(faulty.map(), 8);
  scramble_window(reference.map(), 8);
  std::filesystem::rename(folder / "tiles", folder / "tiles.away");
  folder.write("tiles", "not a folder");
  for (int k = 1; k <= 40; ++k) {
    ASSERT_NO_THROW(drive_to(faulty, 0.25 * k, 0.1 * k));
    drive_to(reference, 0.25 * k, 0.1 * k);
  }
  EXPECT_TRUE(store.failing());
  EXPECT_GT(store.unsaved(), 1u);
  const std::vector<std::string> told = store.take_notices();
  ASSERT_EQ(told.size(), 1u) << "told once per outage, not per try:\n" << joined(told);
  EXPECT_NE(told[0].find("written again at the next save"), std::string::npos) << told[0];
  store.flush(faulty.map());  // the disk still fails: nothing lost, nothing told again
  EXPECT_TRUE(store.failing());
  EXPECT_TRUE(store.take_notices().empty());
  // Back and forth while failing: tiles held in memory come back from there.
  for (int k = 40; k >= 20; --k) {
    drive_to(faulty, 0.25 * k, 0.1 * k);
    drive_to(reference, 0.25 * k, 0.1 * k);
  }
  EXPECT_EQ(differing_cells(reference.map(), faulty.map()), 0u);
  std::filesystem::remove(folder / "tiles");
  std::filesystem::rename(folder / "tiles.away", folder / "tiles");
  store.flush(faulty.map());
  reference_store.flush(reference.map());
  EXPECT_FALSE(store.failing());
  EXPECT_EQ(store.unsaved(), 0u);
  EXPECT_TRUE(any_notice_holds(store.take_notices(), "written again"));
  const io::MergedTiles merged = io::merge_tiles(folder / "tiles");
  const io::MergedTiles expected = io::merge_tiles(folder / "reference");
  EXPECT_TRUE(merged.holes.empty()) << joined(merged.holes);
  ASSERT_EQ(merged.map.min_cell(), expected.map.min_cell());
  EXPECT_EQ(differing_cells(expected.map, merged.map), 0u);
  EXPECT_EQ(store.tiles_on_disk(), reference_store.tiles_on_disk());
}

TEST(TileStore, ATileThatAppearedDuringTheRunIsNotReplaced) {
  TestFolder folder;
  TerrainMapper mapper(mapper_options(), SensorMount{});
  io::TileStore store(tiles_in(folder / "tiles", 8, 1), mapper.map(), {});
  mapper.set_window_listener(&store);
  scramble_window(mapper.map(), 4);
  const std::string intruder = store.tile_path(store.tile_of(mapper.map().min_cell()));
  folder.write("tiles/" + std::filesystem::path(intruder).filename().string(), "someone else's");
  store.flush(mapper.map());
  EXPECT_TRUE(store.failing());
  EXPECT_GE(store.unsaved(), 1u);
  EXPECT_TRUE(any_notice_holds(store.take_notices(), intruder, "appeared during the run"));
  EXPECT_EQ(folder.read("tiles/" + std::filesystem::path(intruder).filename().string()), "someone else's");
}

TEST(TileStore, MergeTilesNamesAMissingOrDamagedTileAsAHole) {
  TestFolder folder;
  TerrainMapper mapper(mapper_options(), SensorMount{});
  io::TileStore store(tiles_in(folder / "tiles", 8, 2), mapper.map(), {});
  mapper.set_window_listener(&store);
  scramble_window(mapper.map(), 12);
  store.flush(mapper.map());
  ASSERT_GE(store.tiles_on_disk().size(), 3u);
  const auto first = store.tiles_on_disk().begin();
  const std::string gone = store.tile_path(*first);
  const std::string broken = store.tile_path(*std::next(first));
  std::filesystem::remove(gone);
  folder.write("tiles/" + std::filesystem::path(broken).filename().string(), "not a map file");
  const io::MergedTiles merged = io::merge_tiles(folder / "tiles");
  ASSERT_EQ(merged.holes.size(), 2u) << joined(merged.holes);
  EXPECT_TRUE(any_notice_holds(merged.holes, gone, "missing")) << joined(merged.holes);
  EXPECT_TRUE(any_notice_holds(merged.holes, broken)) << joined(merged.holes);
  // The command writes what it could and fails, naming both.
  const std::string out = folder / "all.smap";
  const test::CommandResult run =
      test::run_cli("merge-tiles " + test::shell_quoted(folder / "tiles") + " --out " + test::shell_quoted(out));
  EXPECT_EQ(run.exit_code, 1) << run.output;
  EXPECT_NE(run.output.find(gone), std::string::npos) << run.output;
  EXPECT_NE(run.output.find(broken), std::string::npos) << run.output;
  EXPECT_NE(run.output.find("holes"), std::string::npos) << run.output;
  EXPECT_NO_THROW(io::load_map_file(out));
}

TEST(TileStore, TheMergeTilesCommandWritesTheMergedMapAndNoFileOverAnother) {
  TestFolder folder;
  TerrainMapper mapper(mapper_options(), SensorMount{});
  io::TileStore store(tiles_in(folder / "tiles", 8, 2), mapper.map(), {});
  mapper.set_window_listener(&store);
  scramble_window(mapper.map(), 11);
  drive_to(mapper, 1.3, 0.4);
  store.flush(mapper.map());
  const std::string out = folder / "all.smap";
  const test::CommandResult made =
      test::run_cli("merge-tiles " + test::shell_quoted(folder / "tiles") + " --out " + test::shell_quoted(out));
  ASSERT_EQ(made.exit_code, 0) << made.output;
  const io::MapFile merged = io::load_map_file(out);
  EXPECT_EQ(differing_cells(mapper.map(), merged.map), 0u);
  const io::MergedTiles direct = io::merge_tiles(folder / "tiles");
  EXPECT_TRUE(direct.holes.empty());
  EXPECT_EQ(merged.map.min_cell(), direct.map.min_cell());
  EXPECT_EQ(differing_cells(direct.map, merged.map), 0u);
  const std::string before = folder.read("all.smap");
  const test::CommandResult again =
      test::run_cli("merge-tiles " + test::shell_quoted(folder / "tiles") + " --out " + test::shell_quoted(out));
  EXPECT_NE(again.exit_code, 0);
  EXPECT_NE(again.output.find("exists"), std::string::npos) << again.output;
  EXPECT_EQ(folder.read("all.smap"), before);
}

TEST(TileStore, MergeTilesRefusesAFolderWithoutManifest) {
  TestFolder folder;
  std::filesystem::create_directories(folder / "nothing");
  EXPECT_THROW(io::merge_tiles(folder / "nothing"), InputError);
}

TEST(TileStore, TileIndicesFollowTheCellGridBelowZeroToo) {
  TestFolder folder;
  const ElevationMap map(mapper_options().grid);
  const io::TileStore store(tiles_in(folder / "t", 8, 4), map, {});
  EXPECT_EQ(store.tile_of({0, 7}), (io::TileIndex{0, 0}));
  EXPECT_EQ(store.tile_of({-1, 8}), (io::TileIndex{-1, 1}));
  EXPECT_EQ(store.tile_of({-8, -9}), (io::TileIndex{-1, -2}));
  EXPECT_EQ(io::tile_file_name({-3, 12}), "tile_-3_12.smap");
}

TEST(TileStore, TheConfigSectionIsReadAndChecked) {
  const MapperConfig c =
      parse_mapper_config("global_map:\n  folder: tiles\n  tile_cells: 64\n  cached_tiles: 9\n  save_interval_s: 12.5\n",
                          "c.yaml");
  EXPECT_EQ(c.global_map.folder, "tiles");
  EXPECT_EQ(c.global_map.tile_cells, 64);
  EXPECT_EQ(c.global_map.cached_tiles, 9);
  EXPECT_EQ(c.global_map.save_interval_s, 12.5);
  EXPECT_EQ(parse_mapper_config("", "c.yaml").global_map.save_interval_s, 60.0);
  try {
    parse_mapper_config("global_map:\n  save_interval_s: -1\n", "c.yaml");
    FAIL();
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("global_map.save_interval_s"), std::string::npos) << e.what();
  }
  EXPECT_TRUE(parse_mapper_config("", "c.yaml").global_map.folder.empty());
  try {
    parse_mapper_config("global_map:\n  tile_cells: 0\n", "c.yaml");
    FAIL();
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("global_map.tile_cells"), std::string::npos) << e.what();
  }
  EXPECT_THROW(parse_mapper_config("global_map:\n  tiles: 3\n", "c.yaml"), InputError);
}

}  // namespace
}  // namespace stridemap
