// The run information of `live` and `map` (live/map_run_info.hpp) and its
// saving (live/map_saver.hpp): both commands' settings become the same
// fields, and a saver writes the set its information describes.
#include <gtest/gtest.h>

#include <nlohmann/json.hpp>

#include "live/test_folder.hpp"
#include "stridemap/core/error.hpp"
#include "stridemap/live/map_run_info.hpp"
#include "stridemap/live/map_saver.hpp"
#include "stridemap/mapfile/map_file.hpp"

namespace stridemap {
namespace {

MapRunSettings typical_settings() {
  MapRunSettings settings;
  settings.poses_path = "poses.txt";
  settings.out_dir = "out";
  settings.clock = "sensor";
  settings.map_filter = "cas";
  settings.resume_path = "old/map.smap";
  settings.range = "-0.05:0.12";
  settings.overwrite = true;
  return settings;
}

TEST(MapRunInfo, TheSettingsOfBothCommandsBecomeTheSameFields) {
  const MapRunSettings settings = typical_settings();
  const MapRunInfo live = map_run_info("live", "/dev/ttyACM0", settings);
  const MapRunInfo map = map_run_info("map", "run.log", settings);
  EXPECT_EQ(live.command, "live");
  EXPECT_EQ(live.scans_from, "/dev/ttyACM0");
  EXPECT_EQ(map.command, "map");
  EXPECT_EQ(map.scans_from, "run.log");
  for (const MapRunInfo* info : {&live, &map}) {
    EXPECT_EQ(info->poses_from, "poses.txt");
    EXPECT_EQ(info->clock, "sensor");
    EXPECT_EQ(info->map_filter, MapFilter::cas);
    EXPECT_EQ(info->resumed_from, "old/map.smap");
    ASSERT_TRUE(info->elevation_range_m.has_value());
    EXPECT_DOUBLE_EQ(info->elevation_range_m->first, -0.05);
    EXPECT_DOUBLE_EQ(info->elevation_range_m->second, 0.12);
    EXPECT_EQ(info->other_files, io::OtherFiles::keep);
    EXPECT_EQ(info->out_option, "--out");
    EXPECT_EQ(info->pose_lines_skipped, 0u);  // found by the run, not given
  }
  MapRunSettings defaults;
  const MapRunInfo plain = map_run_info("map", "run.log", defaults);
  EXPECT_EQ(plain.map_filter, MapFilter::fill);
  EXPECT_FALSE(plain.elevation_range_m.has_value());
  EXPECT_EQ(plain.other_files, io::OtherFiles::refuse);
}

TEST(MapRunInfo, SettingsThatDoNotParseNameTheirOption) {
  MapRunSettings settings;
  settings.map_filter = "blur";
  try {
    map_run_info("map", "run.log", settings);
    FAIL() << "no error";
  } catch (const InputError& e) {
    EXPECT_EQ(std::string(e.what()).rfind("--map-filter: ", 0), 0u) << e.what();
  }
  for (const char* range : {"0.1", "a:b", "0.2:0.1", ":", "1:inf"}) {
    EXPECT_THROW(parse_elevation_range(range), InputError) << range;
  }
  EXPECT_FALSE(parse_elevation_range("").has_value());
}

TEST(MapRunInfo, ChoicesForTheEmptyRunMessage) {
  MapRunSettings settings = typical_settings();
  settings.config_path = "robot.yaml";
  settings.window = "1.5,-0.2";
  ScanMapperOptions options;
  const MapRunChoices live = map_run_choices(settings, options, false);
  EXPECT_EQ(live.config_path, "robot.yaml");
  EXPECT_EQ(live.window, "1.5,-0.2");
  EXPECT_EQ(live.resume_path, "old/map.smap");
  EXPECT_FALSE(live.resumed_last_scan_time_s.has_value());
  EXPECT_FALSE(live.window_fit_possible);
  auto resumed = std::make_shared<io::MapFile>();
  resumed->metadata.last_scan_time_s = 123.5;
  options.resume = resumed;
  const MapRunChoices map = map_run_choices(settings, options, true);
  ASSERT_TRUE(map.resumed_last_scan_time_s.has_value());
  EXPECT_DOUBLE_EQ(*map.resumed_last_scan_time_s, 123.5);
  EXPECT_TRUE(map.window_fit_possible);
}

TEST(MapSaver, WritesTheSetItsInformationDescribes) {
  test::TestFolder dir;
  MapRunSettings settings;
  settings.poses_path = "poses.txt";
  MapSaver saver(map_run_info("map", "run.log", settings), dir / "out");
  saver.info().pose_lines_skipped = 3;
  const ScanMapper mapper(ScanMapperOptions{}, scip::to_urg_parameters(scip::ScipParameters{}));
  saver.save(mapper, scip::ScipParameters{});
  const nlohmann::json summary = nlohmann::json::parse(dir.read("out/summary.json"));
  EXPECT_EQ(summary["command"], "map");
  EXPECT_EQ(summary["scans_from"], "run.log");
  EXPECT_EQ(summary["poses_from"], "poses.txt");
  EXPECT_EQ(summary["pose_lines_skipped"], 3);
  EXPECT_FALSE(summary.contains("run"));
  EXPECT_EQ(io::load_map_file(dir / "out/map.smap").metadata.created_by, "map run.log");
}

}  // namespace
}  // namespace stridemap
