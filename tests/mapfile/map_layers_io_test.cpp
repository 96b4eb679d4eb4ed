// A layer a user declares goes through every output by name: the map file
// (round trip, declaration included), NumPy arrays and the cell CSV; and
// maps saved before layers were an open set still load.
#include <cmath>
#include <cstdint>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <string>
#include <vector>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>
#include <zlib.h>

#include "live/test_folder.hpp"
#include "stridemap/core/error.hpp"
#include "stridemap/core/map_resume.hpp"
#include "stridemap/core/terrain_mapper.hpp"
#include "stridemap/mapfile/map_file.hpp"
#include "stridemap/render/map_export.hpp"
#include "test_paths.hpp"

namespace stridemap {
namespace {

using test::TestFolder;

LayerSpec spec(const std::string& name, LayerType type, double reset, bool exported) {
  LayerSpec s;
  s.name = name;
  s.type = type;
  s.reset_value = reset;
  s.unit = type == LayerType::f32 ? "m" : "";
  s.description = name + " of the cell";
  s.exported = exported;
  return s;
}

// Built-in layers plus a counter, a float and a flag, with values in a
// window moved off the origin so that window order and slot order differ.
ElevationMap map_with_user_layers() {
  ElevationMap map(GridOptions{5, 0.1,
                               {spec("hit_count", LayerType::u16, 0.0, true),
                                spec("roughness", LayerType::f32, std::nan(""), false),
                                spec("flag", LayerType::u8, 7.0, true)}});
  map.move_corner_to({3, -2});
  const auto hits = map.layer<std::uint16_t>("hit_count");
  const auto rough = map.layer<float>("roughness");
  for (int i = 0; i < 5; ++i) {
    for (int j = 0; j < 5; ++j) {
      const std::size_t s = map.slot(map.cell_at_local(i, j));
      map.data(hits)[s] = static_cast<std::uint16_t>(1000 * i + j);
      if (i == j) map.data(rough)[s] = 0.001f * static_cast<float>(i);
      map.elevation_data()[s] = 0.01f * static_cast<float>(i + j);
      map.certainty_data()[s] = 1.0f;
      map.state_data()[s] = static_cast<std::uint8_t>(CellState::measured);
    }
  }
  return map;
}

std::string read_file(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  return {std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
}

TEST(MapLayersIo, UserLayersRoundTripThroughTheMapFileWithTheirDeclaration) {
  const ElevationMap map = map_with_user_layers();
  const std::string bytes = io::encode_map_file(map, {});
  const ElevationMap loaded = io::decode_map_file(bytes, "user.smap").map;
  ASSERT_EQ(loaded.layer_count(), map.layer_count());
  for (const char* name : {"hit_count", "roughness", "flag"}) {
    const LayerSpec& a = map.layer_spec(*map.find_layer(name));
    const LayerSpec& b = loaded.layer_spec(*loaded.find_layer(name));
    EXPECT_EQ(a.type, b.type) << name;
    EXPECT_EQ(a.unit, b.unit) << name;
    EXPECT_EQ(a.description, b.description) << name;
    EXPECT_EQ(a.exported, b.exported) << name;
    EXPECT_TRUE(a.reset_value == b.reset_value || (std::isnan(a.reset_value) && std::isnan(b.reset_value))) << name;
  }
  // Element for element, by cell (the loaded map's slots may differ).
  const auto hits = loaded.layer<std::uint16_t>("hit_count");
  const auto rough = loaded.layer<float>("roughness");
  const auto flag = loaded.layer<std::uint8_t>("flag");
  for (int i = 0; i < 5; ++i) {
    for (int j = 0; j < 5; ++j) {
      const CellIndex c = map.cell_at_local(i, j);
      EXPECT_EQ(loaded.data(hits)[loaded.slot(c)], 1000 * i + j);
      if (i == j) {
        EXPECT_EQ(loaded.data(rough)[loaded.slot(c)], 0.001f * static_cast<float>(i));
      } else {
        EXPECT_TRUE(std::isnan(loaded.data(rough)[loaded.slot(c)]));
      }
      EXPECT_EQ(loaded.data(flag)[loaded.slot(c)], 7);
    }
  }
  // Saving the loaded map again gives the same bytes.
  EXPECT_EQ(io::encode_map_file(loaded, {}), bytes);

  // Every layer stays aligned to its element size in the file.
  const auto header = nlohmann::json::parse(io::map_file_header_json(bytes, "user.smap"));
  for (const auto& layer : header["layers"]) {
    const std::string type = layer["type"];
    const std::size_t width = type == "<f4" ? 4 : type == "<u2" ? 2 : 1;
    EXPECT_EQ(layer["offset"].get<std::size_t>() % width, 0u) << layer.dump();
  }
}

TEST(MapLayersIo, ResumingKeepsTheMappersLayerHandles) {
  // Declared narrow first: the file lays the float out before the flag, so
  // the loaded map's order differs from the mapper's.
  MapperOptions options;
  options.grid = GridOptions{6, 0.1, {spec("flag", LayerType::u8, 0.0, true), spec("roughness", LayerType::f32, 0.0, true)}};
  TerrainMapper first(options, SensorMount{});
  const auto flag = first.map().layer<std::uint8_t>("flag");
  const auto rough = first.map().layer<float>("roughness");
  first.map().data(flag)[3] = 9;
  first.map().data(rough)[4] = 0.25f;
  const io::MapFile file = io::decode_map_file(io::encode_map_file(first.map(), {}), "resume.smap");
  EXPECT_NE(*file.map.find_layer("flag"), flag.index);

  TerrainMapper second(options, SensorMount{});
  const auto flag_again = second.map().layer<std::uint8_t>("flag");  // taken before resuming
  resume_from_map(second, file.map);
  EXPECT_EQ(second.map().data(flag_again)[3], 9);
  EXPECT_EQ(second.map().data(rough)[4], 0.25f);
  EXPECT_EQ(second.map().layer_count(), first.map().layer_count());

  // A layer of the same name but another type cannot be continued.
  MapperOptions other = options;
  other.grid.extra_layers[0].type = LayerType::u16;
  TerrainMapper third(other, SensorMount{});
  EXPECT_THROW(resume_from_map(third, file.map), InputError);
}

TEST(MapLayersIo, AMapFileWrittenBeforeUserLayersLoads) {
  const std::string path = std::string(STRIDEMAP_SOURCE_DIR) + "/fuzz/corpus/map_file/mixed_3x3.smap";
  const std::string bytes = read_file(path);
  ASSERT_FALSE(bytes.empty()) << path;
  const io::MapFile file = io::decode_map_file(bytes, path);
  EXPECT_EQ(file.map.layer_count(), builtin_layers().size());
  // Saved again and loaded, every layer comes back bit for bit.
  const io::MapFile again = io::decode_map_file(io::encode_map_file(file.map, file.metadata), "again.smap");
  const std::size_t cells = 9;
  for (std::size_t k = 0; k < file.map.layer_count(); ++k) {
    EXPECT_EQ(std::memcmp(again.map.layer_bytes(k), file.map.layer_bytes(k),
                          cells * layer_type_bytes(file.map.layer_spec(k).type)),
              0)
        << file.map.layer_spec(k).name;
  }
}

TEST(MapLayersIo, ExportsSelectLayersByName) {
  TestFolder folder;
  const ElevationMap map = map_with_user_layers();
  const std::vector<std::string> names{"hit_count", "elevation"};
  const auto paths = io::export_npy(map, folder / "npy", names);
  ASSERT_EQ(paths.size(), 2u);
  EXPECT_TRUE(std::filesystem::exists(folder.path() / "npy/hit_count.npy"));
  EXPECT_FALSE(std::filesystem::exists(folder.path() / "npy/certainty.npy"));
  const std::string npy = folder.read("npy/hit_count.npy");
  EXPECT_NE(npy.find("'descr': '<u2'"), std::string::npos);
  // Element [1][2] of a 5 x 5 array of 2-byte values after the header.
  const std::size_t data = npy.size() - 25 * 2;
  const std::size_t at = data + (1 * 5 + 2) * 2;
  EXPECT_EQ(static_cast<unsigned char>(npy[at]) | (static_cast<unsigned char>(npy[at + 1]) << 8), 1002);

  // Every layer by default, the user's included.
  EXPECT_EQ(io::export_npy(map, folder / "all").size(), map.layer_count());

  io::export_cells_csv(map, folder / "csv", names);
  const std::string csv = folder.read("csv/cells.csv");
  EXPECT_NE(csv.find("\nix,iy,x_m,y_m,hit_count,elevation_m\n"), std::string::npos) << csv.substr(0, 400);
  io::export_cells_csv(map, folder / "csv_default");
  EXPECT_NE(folder.read("csv_default/cells.csv")
                .find("ix,iy,x_m,y_m,elevation_m,certainty,state,mean_elevation_m,mean_count,hit_count,roughness_m,flag\n"),
            std::string::npos);
}

TEST(MapLayersIo, AnUnknownLayerNameIsRefusedBeforeAnythingIsWritten) {
  TestFolder folder;
  const ElevationMap map = map_with_user_layers();
  const std::vector<std::string> names{"elevation", "slope"};
  try {
    io::export_npy(map, folder / "npy", names);
    FAIL() << "no error";
  } catch (const InputError& e) {
    const std::string what = e.what();
    EXPECT_NE(what.find("'slope'"), std::string::npos) << what;
    EXPECT_NE(what.find("hit_count, roughness, flag"), std::string::npos) << what;
  }
  EXPECT_FALSE(std::filesystem::exists(folder.path() / "npy"));
  const std::vector<std::string> twice{"elevation", "elevation"};
  EXPECT_THROW(io::export_cells_csv(map, folder / "csv", twice), InputError);
}

TEST(MapLayersIo, AUserLayerWithABadDeclarationInTheFileIsRefused) {
  ElevationMap map = map_with_user_layers();
  std::string bytes = io::encode_map_file(map, {});
  // Rename the counter to a name no layer may have (same length, so every
  // offset holds) and redo the checksum, so only the name is wrong.
  const std::string from = "\"name\": \"hit_count\"", to = "\"name\": \"Hit-Count\"";
  const auto at = bytes.find(from);
  ASSERT_NE(at, std::string::npos);
  bytes.replace(at, from.size(), to);
  const std::size_t body = bytes.size() - 4;
  const auto crc = static_cast<std::uint32_t>(crc32(0L, reinterpret_cast<const Bytef*>(bytes.data()), static_cast<uInt>(body)));
  for (int k = 0; k < 4; ++k) bytes[body + static_cast<std::size_t>(k)] = static_cast<char>(crc >> (8 * k));
  try {
    io::decode_map_file(bytes, "bad.smap");
    FAIL() << "no error";
  } catch (const InputError& e) {
    const std::string what = e.what();
    EXPECT_NE(what.find("bad.smap"), std::string::npos) << what;
    EXPECT_NE(what.find("Hit-Count"), std::string::npos) << what;
  }
}

}  // namespace
}  // namespace stridemap
