// Resuming needs the settings the map was made with: a map file that does
// not record its mount or configuration (a bare Map saved from Python,
// merge-tiles' output) is refused by name, not resumed with whatever
// settings the new run has.
#include <string>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "stridemap/core/error.hpp"
#include "stridemap/mapfile/map_file.hpp"
#include "stridemap/mapfile/map_resume_check.hpp"
#include "stridemap/config/mapper_config.hpp"

namespace stridemap {
namespace {

// Through the file's bytes, as `map --resume` reads it.
io::MapFile saved_with(const MapperConfig& config, const io::MapFileMetadata& metadata) {
  const ElevationMap map(config.mapper.grid);
  return io::decode_map_file(io::encode_map_file(map, metadata), "saved.smap");
}

std::string refusal(const io::MapFile& saved, const MapperConfig& config) {
  try {
    io::check_map_resumable(saved, config, "--resume saved.smap");
  } catch (const InputError& e) {
    return e.what();
  }
  return "";
}

TEST(MapResumeCheck, AFileWithoutMountOrConfigurationIsRefusedNamingBoth) {
  const MapperConfig config;
  io::MapFileMetadata bare;
  bare.created_by = "a script";
  const io::MapFile saved = saved_with(config, bare);
  EXPECT_EQ(io::missing_resume_settings(saved),
            (std::vector<std::string>{"the sensor mount", "the mapper configuration"}));
  // Its geometry is this run's: without the check, it would be resumed.
  EXPECT_TRUE(io::map_config_differences(saved, config).empty());
  const std::string message = refusal(saved, config);
  EXPECT_EQ(message.rfind("--resume saved.smap: cannot resume mapping from this map: the file does not record the "
                          "sensor mount or the mapper configuration it was made with",
                          0),
            0u)
      << message;
  EXPECT_NE(message.find("map its scans again"), std::string::npos) << message;
}

TEST(MapResumeCheck, EachMissingPieceIsNamedAlone) {
  const MapperConfig config;
  io::MapFileMetadata no_mount = io::map_file_metadata(config, "test");
  no_mount.mount.reset();
  const std::string without_mount = refusal(saved_with(config, no_mount), config);
  EXPECT_NE(without_mount.find("does not record the sensor mount it was made with"), std::string::npos)
      << without_mount;

  io::MapFileMetadata no_config = io::map_file_metadata(config, "test");
  no_config.config_text.clear();
  const std::string without_config = refusal(saved_with(config, no_config), config);
  EXPECT_NE(without_config.find("does not record the mapper configuration it was made with"), std::string::npos)
      << without_config;
}

TEST(MapResumeCheck, TheToolsOwnMetadataResumesAndDifferencesStillCount) {
  MapperConfig config;
  const io::MapFile saved = saved_with(config, io::map_file_metadata(config, "map --log run.log"));
  EXPECT_TRUE(io::missing_resume_settings(saved).empty());
  EXPECT_EQ(refusal(saved, config), "");
  config.mount.height_m += 0.1;
  const std::string message = refusal(saved, config);
  EXPECT_NE(message.find("it was made with other settings (mount.height_m"), std::string::npos) << message;
}

TEST(MapResumeCheck, FusedLayersMayStartOrGoOnButNotBeLeftBehind) {
  MapperConfig without;
  MapperConfig with;
  with.height_fusion.enabled = true;
  // A map without them: a run may start keeping them (they start unknown).
  const io::MapFile plain = saved_with(without, io::map_file_metadata(without, "map"));
  EXPECT_EQ(refusal(plain, with), "");
  // A map file from before the section existed: the same.
  io::MapFileMetadata older = io::map_file_metadata(without, "map");
  nlohmann::json settings = nlohmann::json::parse(older.config_text);
  ASSERT_EQ(settings.erase("height_fusion"), 1u) << older.config_text;
  older.config_text = settings.dump();
  EXPECT_EQ(refusal(saved_with(without, older), with), "");
  EXPECT_EQ(refusal(saved_with(without, older), without), "");
  // A map that kept them: other gate settings go on, dropping them does not.
  const io::MapFile fused = saved_with(with, io::map_file_metadata(with, "map"));
  MapperConfig wider = with;
  wider.height_fusion.mahalanobis_gate = 4.0;
  EXPECT_EQ(refusal(fused, wider), "");
  const std::string message = refusal(fused, without);
  EXPECT_NE(message.find("height_fusion.enabled: the map has true (its fused layers), this run false"),
            std::string::npos)
      << message;
}

}  // namespace
}  // namespace stridemap
