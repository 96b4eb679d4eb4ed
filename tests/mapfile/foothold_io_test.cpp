// The foothold layers through the mapper config (strict reader) and the map
// file: saved with their values, loaded back, old files still usable.
#include <cmath>
#include <cstring>
#include <fstream>
#include <iterator>
#include <string>

#include <gtest/gtest.h>

#include "stridemap/config/mapper_config.hpp"
#include "stridemap/core/error.hpp"
#include "stridemap/core/foothold.hpp"
#include "stridemap/mapfile/map_file.hpp"
#include "stridemap/mapfile/map_resume_check.hpp"
#include "test_paths.hpp"

namespace stridemap {
namespace {

std::string error_of(const std::string& text) {
  try {
    parse_mapper_config(text, "robot.yaml");
  } catch (const InputError& e) {
    return e.what();
  }
  return "no error";
}

TEST(FootholdConfig, TheSectionSetsTheOptionsAndTheShippedFileHoldsTheDefaults) {
  const MapperConfig c = parse_mapper_config(
      "foothold:\n  foot_radius_m: 0.03\n  max_slope_deg: 20\n  max_step_m: 0.08\n  enabled: false\n  safe_score: 0.7\n",
      "robot.yaml");
  EXPECT_DOUBLE_EQ(c.foothold.foot_radius_m, 0.03);
  EXPECT_DOUBLE_EQ(c.foothold.max_slope_deg, 20.0);
  EXPECT_DOUBLE_EQ(c.foothold.max_step_m, 0.08);
  EXPECT_FALSE(c.foothold.enabled);
  EXPECT_DOUBLE_EQ(c.foothold.safe_score, 0.7);
  EXPECT_DOUBLE_EQ(c.foothold.max_roughness_m, FootholdOptions{}.max_roughness_m);
  const MapperConfig shipped = load_mapper_config(std::string(STRIDEMAP_SOURCE_DIR) + "/configs/urg_messor.yaml");
  const FootholdOptions d;
  EXPECT_EQ(shipped.foothold.enabled, d.enabled);
  EXPECT_DOUBLE_EQ(shipped.foothold.foot_radius_m, d.foot_radius_m);
  EXPECT_DOUBLE_EQ(shipped.foothold.max_slope_deg, d.max_slope_deg);
  EXPECT_DOUBLE_EQ(shipped.foothold.max_step_m, d.max_step_m);
  EXPECT_DOUBLE_EQ(shipped.foothold.max_roughness_m, d.max_roughness_m);
  EXPECT_DOUBLE_EQ(shipped.foothold.edge_search_radius_m, d.edge_search_radius_m);
  EXPECT_DOUBLE_EQ(shipped.foothold.edge_clearance_m, d.edge_clearance_m);
  EXPECT_DOUBLE_EQ(shipped.foothold.full_certainty, d.full_certainty);
  EXPECT_DOUBLE_EQ(shipped.foothold.min_known_fraction, d.min_known_fraction);
  EXPECT_DOUBLE_EQ(shipped.foothold.safe_score, d.safe_score);
}

TEST(FootholdConfig, BadValuesAndUnknownFieldsNameFileLineAndField) {
  EXPECT_NE(error_of("foothold:\n  foot_radius_m: -0.02\n").find("robot.yaml:2: foothold.foot_radius_m"),
            std::string::npos);
  EXPECT_NE(error_of("foothold:\n  max_slope_deg: 95\n").find("foothold.max_slope_deg"), std::string::npos);
  EXPECT_NE(error_of("foothold:\n  safe_score: 2\n").find("foothold.safe_score"), std::string::npos);
  EXPECT_NE(error_of("foothold:\n  foot_radius: 0.02\n").find("foothold.foot_radius: unknown field"),
            std::string::npos);
  EXPECT_NE(error_of("foothold:\n  enabled: maybe\n").find("foothold.enabled"), std::string::npos);
}

TEST(FootholdMapFile, TheLayersRoundTripWithTheirValues) {
  ElevationMap map(GridOptions{12, 0.01});
  for (int i = 0; i < 12; ++i) {
    for (int j = 0; j < 12; ++j) {
      if ((i * 7 + j * 3) % 5 == 0) continue;  // some unknown cells
      const std::size_t s = map.slot(map.cell_at_local(i, j));
      map.elevation_data()[s] = 0.01f * static_cast<float>(i % 4) + 0.002f * static_cast<float>(j);
      map.certainty_data()[s] = 6.0f;
      map.state_data()[s] = static_cast<std::uint8_t>(CellState::measured);
    }
  }
  FootholdLayers foothold(map, FootholdOptions{});
  foothold.recompute_all(map);
  const io::MapFile file = io::decode_map_file(io::encode_map_file(map, {}), "footholds.smap");
  EXPECT_EQ(file.version, io::kMapFileVersion);
  ASSERT_EQ(file.map.layer_count(), map.layer_count());
  for (const LayerSpec& spec : foothold_layer_specs()) {
    const auto index = file.map.find_layer(spec.name);
    ASSERT_TRUE(index) << spec.name;
    EXPECT_EQ(file.map.layer_spec(*index).unit, spec.unit);
    EXPECT_EQ(std::memcmp(file.map.layer_bytes(*index), map.layer_bytes(*map.find_layer(spec.name)), 144 * 4), 0)
        << spec.name;
  }
  // A program that attaches to the loaded map finds the layers and keeps them.
  ElevationMap loaded = file.map;
  FootholdLayers again(loaded, FootholdOptions{});
  EXPECT_EQ(loaded.layer_count(), map.layer_count());
}

TEST(FootholdMapFile, AFileFromBeforeTheLayersLoadsAndGetsThem) {
  const std::string path = std::string(STRIDEMAP_SOURCE_DIR) + "/fuzz/corpus/map_file/mixed_3x3.smap";
  std::ifstream in(path, std::ios::binary);
  const std::string bytes((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  ASSERT_FALSE(bytes.empty()) << path;
  io::MapFile file = io::decode_map_file(bytes, path);
  EXPECT_FALSE(file.map.find_layer("foothold_score"));
  FootholdLayers foothold(file.map, FootholdOptions{});
  foothold.recompute_all(file.map);
  EXPECT_TRUE(file.map.find_layer("foothold_score"));
}

TEST(FootholdMapFile, FootholdSettingsDoNotBlockResuming) {
  MapperConfig config;
  ElevationMap map(config.mapper.grid);
  io::MapFile saved{map, io::map_file_metadata(config, "test"), io::kMapFileVersion};
  config.foothold.max_step_m = 0.09;
  EXPECT_TRUE(io::map_config_differences(saved, config).empty());
  config.mapper.update.certainty_increment = 4.0;  // a real difference still counts
  EXPECT_FALSE(io::map_config_differences(saved, config).empty());
}

}  // namespace
}  // namespace stridemap
