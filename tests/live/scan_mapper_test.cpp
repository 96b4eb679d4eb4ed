// The decisions live mapping and replay share: which scans wait for their
// poses, which are skipped and why, and that saving does not change the map.
#include <gtest/gtest.h>

#include <cstring>
#include <filesystem>

#include "live/test_folder.hpp"
#include "stridemap/live/scan_mapper.hpp"

namespace stridemap {
namespace {

UrgRawScan flat_scan(double time_s) {
  UrgRawScan raw;
  raw.time_s = time_s;
  raw.values_mm.assign(682, 450);  // the ground ahead of the Messor mount
  return raw;
}

TimedPose pose_at(double t, double x) {
  TimedPose p;
  p.time_s = t;
  p.pose.x_m = x;
  return p;
}

TEST(ScanMapper, ScansWaitForTheirPosesAndAreSkippedOnlyForAReason) {
  ScanMapper mapper({}, UrgParameters{});
  PoseTrack poses(0.5);
  poses.append(pose_at(1.0, 0.0));
  mapper.add(flat_scan(0.9));   // before every pose
  mapper.add(flat_scan(1.05));  // needs a later pose
  EXPECT_EQ(mapper.process(poses, false), 0u);
  EXPECT_EQ(mapper.stats().before_first_pose, 1u);
  EXPECT_EQ(mapper.waiting(), 1u);
  poses.append(pose_at(1.1, 0.01));
  mapper.add(flat_scan(1.1));
  EXPECT_EQ(mapper.process(poses, false), 2u);
  poses.append(pose_at(2.0, 0.1));  // 0.9 s after the previous: a gap
  mapper.add(flat_scan(1.5));
  mapper.add(flat_scan(2.5));
  EXPECT_EQ(mapper.process(poses, false), 0u);
  EXPECT_EQ(mapper.stats().pose_gap, 1u);
  EXPECT_EQ(mapper.waiting(), 1u);  // 2.5 s may still get its pose
  EXPECT_EQ(mapper.expire(5.0), 1u);  // ... but live mapping gives up on it
  EXPECT_EQ(mapper.stats().after_last_pose, 1u);
  mapper.add(flat_scan(3.0));
  EXPECT_EQ(mapper.process(poses, true), 0u);  // replay: no more poses will come
  EXPECT_EQ(mapper.stats().after_last_pose, 2u);
  EXPECT_EQ(mapper.stats().integrated, 2u);
  EXPECT_EQ(mapper.stats().scans, 6u);
  EXPECT_GT(mapper.mapper().totals().integrated, 0u);
}

TEST(ScanMapper, ScansThatDoNotFitTheSensorAreRejectedAndCounted) {
  ScanMapper mapper({}, UrgParameters{});
  PoseTrack poses;
  poses.append(pose_at(0.0, 0.0));
  poses.append(pose_at(1.0, 0.0));
  UrgRawScan raw = flat_scan(0.5);
  raw.values_mm.resize(700);  // past AMAX
  mapper.add(raw);
  mapper.process(poses, true);
  EXPECT_EQ(mapper.stats().rejected, 1u);
  EXPECT_EQ(mapper.stats().integrated, 0u);
}

TEST(ScanMapper, ScanSequenceLagsOneScanUntilFinish) {
  ScanMapperOptions options;
  options.filters = parse_scan_filter_list("paper");
  ScanMapper mapper(options, UrgParameters{});
  PoseTrack poses;
  for (int k = 0; k <= 5; ++k) poses.append(pose_at(0.1 * k, 0.01 * k));
  for (int k = 0; k < 5; ++k) mapper.add(flat_scan(0.1 * k));
  mapper.process(poses, true);
  EXPECT_EQ(mapper.stats().integrated, 4u);
  mapper.finish();
  EXPECT_EQ(mapper.stats().integrated, 5u);
}

// Measured cells of a map.
std::size_t measured_cells(const ElevationMap& map) {
  std::size_t n = 0;
  for (int i = 0; i < map.cells_per_side(); ++i)
    for (int j = 0; j < map.cells_per_side(); ++j) n += map.state(map.cell_at_local(i, j)) == CellState::measured;
  return n;
}

TEST(ScanMapper, ARunKilledOnTheSameTilesKeepsWhatItMappedUpToTheLastSaveInterval) {
  // The robot never leaves its first tiles, so only the periodic save puts
  // them on disk; the run is then stopped without finish(), as by a kill.
  for (const double interval_s : {0.0, 30.0}) {
    test::TestFolder folder;
    ScanMapperOptions options;
    options.config.global_map.folder = folder / "tiles";
    options.config.global_map.save_interval_s = interval_s;
    std::size_t window_measured = 0;
    {
      ScanMapper mapper(options, UrgParameters{});
      PoseTrack poses;
      for (int k = 0; k <= 200; ++k) poses.append(pose_at(0.5 * k, 0.0));
      for (int k = 0; k < 200; ++k) {  // 100 s of scans, each integrated as it comes
        mapper.add(flat_scan(0.5 * k));
        mapper.process(poses, true);
      }
      window_measured = measured_cells(mapper.mapper().map());
    }
    ASSERT_GT(window_measured, 100u);
    std::size_t tiles = 0;
    for (const auto& e : std::filesystem::directory_iterator(folder / "tiles")) {
      tiles += e.path().extension() == ".smap";
    }
    if (interval_s == 0.0) {
      EXPECT_EQ(tiles, 0u) << "nothing left the window: without the periodic save nothing is on disk";
      continue;
    }
    ASSERT_GT(tiles, 0u);
    // Standing still, the ground was all measured long before the last save (at 90 s).
    EXPECT_EQ(measured_cells(io::merge_tiles(folder / "tiles").map), window_measured);
  }
}

bool holds(const std::vector<std::string>& lines, const std::string& part) {
  for (const std::string& l : lines) {
    if (l.find(part) != std::string::npos) return true;
  }
  return false;
}

// A full disk must not end a run: the tiles wait in memory, the writes are
// tried again after a second of scans, and the run ends with them on disk.
TEST(ScanMapper, TileWritesThatFailAreToldOnceAndTriedAgainWhileMappingGoesOn) {
  test::TestFolder folder;
  ScanMapperOptions options;
  options.config.global_map.folder = folder / "tiles";
  options.config.global_map.cached_tiles = 1;
  ScanMapper mapper(options, UrgParameters{});
  PoseTrack poses;
  for (int k = 0; k <= 400; ++k) poses.append(pose_at(0.1 * k, 0.02 * k));
  // Every write fails while the folder is a file, even for root.
  std::filesystem::rename(folder / "tiles", folder / "tiles.away");
  folder.write("tiles", "not a folder");
  std::vector<std::string> told;
  for (int k = 0; k < 200; ++k) {  // 20 s, 4 m: the window leaves many tiles
    mapper.add(flat_scan(0.1 * k));
    ASSERT_NO_THROW(mapper.process(poses, true));
    for (std::string& n : mapper.take_tile_notices()) told.push_back(std::move(n));
  }
  EXPECT_EQ(mapper.stats().integrated, 200u);
  ASSERT_NE(mapper.tile_store(), nullptr);
  EXPECT_TRUE(mapper.tile_store()->failing());
  EXPECT_GT(mapper.tile_store()->unsaved(), 0u);
  EXPECT_EQ(told.size(), 1u);
  // About one try a second of scans, not one per scan.
  EXPECT_LE(mapper.tile_store()->stats().write_failures, 200u);
  std::filesystem::remove(folder / "tiles");
  std::filesystem::rename(folder / "tiles.away", folder / "tiles");
  for (int k = 200; k < 220; ++k) {
    mapper.add(flat_scan(0.1 * k));
    mapper.process(poses, true);
  }
  EXPECT_TRUE(holds(mapper.take_tile_notices(), "written again"));
  mapper.finish();
  EXPECT_FALSE(mapper.tile_store()->failing());
  EXPECT_EQ(mapper.tile_store()->unsaved(), 0u);
  const io::MergedTiles merged = io::merge_tiles(folder / "tiles");
  EXPECT_TRUE(merged.holes.empty());
  EXPECT_GT(measured_cells(merged.map), measured_cells(mapper.mapper().map()));
}

TEST(ScanMapper, SavingFillsACopyAndLeavesTheMapAsItWas) {
  ScanMapper mapper({}, UrgParameters{});
  PoseTrack poses;
  for (int k = 0; k <= 20; ++k) poses.append(pose_at(0.1 * k, 0.01 * k));
  for (int k = 0; k < 20; ++k) mapper.add(flat_scan(0.1 * k));
  mapper.process(poses, true);
  const ExportedMap before = export_map(mapper.mapper().map());
  const ExportedMap filled = mapper.filled_layers();
  const ExportedMap after = export_map(mapper.mapper().map());
  EXPECT_EQ(before.state(), after.state());
  EXPECT_EQ(std::memcmp(before.elevation_m().data(), after.elevation_m().data(), sizeof(float) * before.elevation_m().size()),
            0);
  EXPECT_GE(map_coverage(filled), map_coverage(before));
}

}  // namespace
}  // namespace stridemap
