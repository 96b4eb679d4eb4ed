// The foothold layers are computed when the map is read (lazy, the
// default): every way a run's map leaves the mapper (the tiles of a global
// map, the output folder, the map file) must hold what a run that computes
// them after every scan writes, byte for byte.
#include <gtest/gtest.h>

#include <algorithm>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <map>
#include <string>

#include "live/test_folder.hpp"
#include "stridemap/live/map_report.hpp"
#include "stridemap/live/scan_mapper.hpp"
#include "stridemap/mapfile/tile_store.hpp"

namespace stridemap {
namespace {

// Uneven ground (a range that varies along the scan line), so that the
// foothold layers vary and a stale value differs from a current one.
UrgRawScan bumpy_scan(double time_s, int k) {
  UrgRawScan raw;
  raw.time_s = time_s;
  raw.values_mm.resize(682);
  for (std::size_t i = 0; i < raw.values_mm.size(); ++i) {
    raw.values_mm[i] = static_cast<std::uint16_t>(440 + (i * 7 + static_cast<std::size_t>(k) * 3) % 40);
  }
  return raw;
}

std::map<std::string, std::string> files_in(const std::string& folder) {
  std::map<std::string, std::string> files;
  for (const auto& e : std::filesystem::recursive_directory_iterator(folder)) {
    if (!e.is_regular_file()) continue;
    std::ifstream in(e.path(), std::ios::binary);
    files[std::filesystem::relative(e.path(), folder).string()] =
        std::string(std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>());
  }
  return files;
}

struct MapRunFiles {
  std::map<std::string, std::string> tiles, outputs;
  bool stale_seen = false;  // the lazy mapper's own layers lagged at some scan
};

MapRunFiles map_run(bool every_scan, const std::string& folder) {
  ScanMapperOptions options;
  options.config.foothold.update_every_scan = every_scan;
  // The cells leaving the window are copied into their tiles at each move.
  options.config.global_map.folder = folder + "/tiles";
  MapRunFiles run;
  {
    ScanMapper mapper(options, UrgParameters{});
    PoseTrack poses;
    // 4.5 m forward and back, drifting sideways: the window moves many
    // times, and on the way back it takes in tiles written on the way out.
    for (int k = 0; k <= 300; ++k) {
      TimedPose p;
      p.time_s = 0.1 * k;
      p.pose.x_m = 0.03 * std::min(k, 300 - k);
      p.pose.y_m = 0.002 * k;
      p.pose.yaw_rad = 0.001 * k;
      poses.append(p);
    }
    for (int k = 0; k < 300; ++k) {
      mapper.add(bumpy_scan(0.1 * k, k));
      mapper.process(poses, true);
      if (!every_scan && k % 50 == 25) {
        const ElevationMap unread = mapper.mapper().map();
        const std::size_t score = *unread.find_layer("foothold_score");
        const std::size_t n = static_cast<std::size_t>(unread.cells_per_side());
        run.stale_seen = run.stale_seen ||
                         std::memcmp(unread.layer_bytes(score), mapper.map().layer_bytes(score), sizeof(float) * n * n) != 0;
      }
    }
    MapRunInfo info;
    info.command = "map";
    info.map_filter = MapFilter::none;  // the map as built, foothold layers and all
    write_map_outputs(mapper, scip::ScipParameters{}, info, nullptr, folder + "/out");
    mapper.finish();
  }
  run.tiles = files_in(folder + "/tiles");
  run.outputs = files_in(folder + "/out");
  return run;
}

TEST(LazyLayers, TilesOutputsAndMapFileAreThoseOfARunUpdatingEveryScan) {
  test::TestFolder folder;
  const MapRunFiles eager = map_run(true, folder / "eager");
  const MapRunFiles lazy = map_run(false, folder / "lazy");
  EXPECT_TRUE(lazy.stale_seen) << "the lazy layers must lag between reads, or this test shows nothing";
  ASSERT_GT(eager.tiles.size(), 1u);
  ASSERT_EQ(eager.tiles.size(), lazy.tiles.size());
  for (const auto& [name, bytes] : eager.tiles) {
    ASSERT_TRUE(lazy.tiles.count(name)) << name;
    EXPECT_TRUE(bytes == lazy.tiles.at(name)) << "tile " << name;
  }
  ASSERT_TRUE(eager.outputs.count("map.smap"));
  ASSERT_EQ(eager.outputs.size(), lazy.outputs.size());
  for (const auto& [name, bytes] : eager.outputs) {
    ASSERT_TRUE(lazy.outputs.count(name)) << name;
    EXPECT_TRUE(bytes == lazy.outputs.at(name)) << "output " << name;
  }
}

}  // namespace
}  // namespace stridemap
