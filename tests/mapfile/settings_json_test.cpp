// The one writer of a run's settings as JSON (mapfile/detail/settings_json.hpp):
// the map file records what it writes, the resume check compares what it
// writes, and a summary's settings come from it.
#include <string>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "stridemap/config/mapper_config.hpp"
#include "stridemap/core/error.hpp"
#include "stridemap/mapfile/detail/settings_json.hpp"
#include "stridemap/mapfile/map_file.hpp"
#include "stridemap/mapfile/map_resume_check.hpp"

namespace stridemap {
namespace {

MapperConfig tilted_config() {
  MapperConfig config;
  config.mount.height_m = 0.42;
  config.mount.pitch_rad = 0.5;
  config.mount.forward_offset_m = 0.1;
  return config;
}

TEST(SettingsJson, TheMapFileRecordsTheWritersText) {
  const MapperConfig config = tilted_config();
  const io::MapFileMetadata metadata = io::map_file_metadata(config, "map run.log");
  EXPECT_EQ(metadata.config_text, io::detail::mapper_settings_json(config).dump(1));
  EXPECT_EQ(io::mapper_config_json(config), metadata.config_text);
  const nlohmann::json recorded = nlohmann::json::parse(metadata.config_text);
  EXPECT_EQ(recorded["mount"], io::detail::mount_json(config.mount));
  EXPECT_DOUBLE_EQ(recorded["mount"]["height_m"].get<double>(), 0.42);
  for (const char* section : {"mount", "map", "update", "fill", "range_calibration", "foothold"}) {
    EXPECT_TRUE(recorded.contains(section)) << section;
  }
}

TEST(SettingsJson, TheHeadersMountIsTheWritersToo) {
  const MapperConfig config = tilted_config();
  const ElevationMap map(config.mapper.grid);
  const std::string header =
      io::map_file_header_json(io::encode_map_file(map, io::map_file_metadata(config, "test")), "test.smap");
  EXPECT_EQ(nlohmann::json::parse(header)["mount"], io::detail::mount_json(config.mount));
}

// A map whose configuration is other text (a YAML file's) is still checked
// by its mount, written the same way as this run's.
TEST(SettingsJson, TheResumeChecksMountFallbackComparesTheWritersFields) {
  const MapperConfig config = tilted_config();
  io::MapFileMetadata metadata = io::map_file_metadata(config, "test");
  metadata.config_text = "mount:\n  height_m: 0.42\n";
  const ElevationMap map(config.mapper.grid);
  const io::MapFile saved = io::decode_map_file(io::encode_map_file(map, metadata), "saved.smap");
  EXPECT_TRUE(io::map_config_differences(saved, config).empty());
  MapperConfig other = config;
  other.mount.lateral_offset_m = 0.05;
  const std::vector<std::string> differences = io::map_config_differences(saved, other);
  ASSERT_EQ(differences.size(), 1u);
  EXPECT_EQ(differences[0].rfind("mount.lateral_offset_m: the map has 0.0, this run 0.05", 0), 0u) << differences[0];
}

TEST(SettingsJson, RunSettingsForSummaries) {
  const nlohmann::json live = io::detail::run_settings_json("paper", MapFilter::cas, std::string("sensor"));
  EXPECT_EQ(live, (nlohmann::json{{"filters", "paper"}, {"map_filter", "cas"}, {"clock", "sensor"}}));
  const nlohmann::json experiment = io::detail::run_settings_json("none", MapFilter::fill);
  EXPECT_EQ(experiment, (nlohmann::json{{"filters", "none"}, {"map_filter", "fill"}}));
  // A run whose clock is not known yet still says so.
  EXPECT_TRUE(io::detail::run_settings_json("none", MapFilter::none, std::string()).contains("clock"));
}

}  // namespace
}  // namespace stridemap
