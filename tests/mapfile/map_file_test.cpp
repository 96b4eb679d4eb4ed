#include "stridemap/mapfile/map_file.hpp"

#include <zlib.h>

#include <bit>
#include <cctype>
#include <cmath>
#include <cstring>
#include <filesystem>
#include <limits>
#include <random>

#include <gtest/gtest.h>

#include "live/test_folder.hpp"
#include "stridemap/core/error.hpp"
#include "stridemap/core/map_integrity.hpp"
#include "stridemap/core/map_resume.hpp"
#include "stridemap/core/terrain_mapper.hpp"

namespace stridemap {
namespace {

using test::TestFolder;

// A map whose every layer holds something different in every cell, NaNs
// with payloads included, in a window moved so that the circular buffer
// wraps: what a byte-for-byte round trip must survive.
ElevationMap scrambled_map(int n, std::uint32_t seed) {
  ElevationMap map(GridOptions{n, 0.0125});
  map.move_corner_to({1234567, -89});
  std::mt19937 random(seed);
  const std::size_t cells = static_cast<std::size_t>(n) * static_cast<std::size_t>(n);
  for (std::size_t s = 0; s < cells; ++s) {
    // Random bits in every layer, within what a valid cell may hold (the
    // reader checks that): unknown cells a NaN with a payload and no
    // certainty, filled ones no certainty, any finite elevation.
    const auto state = static_cast<std::uint8_t>(random() % 3);
    float elevation = std::bit_cast<float>(static_cast<std::uint32_t>(random()));
    if (!std::isfinite(elevation)) elevation = 0.25f;
    if (state == static_cast<std::uint8_t>(CellState::unknown)) {
      elevation = std::bit_cast<float>(0x7fc00000u | (static_cast<std::uint32_t>(random()) & 0x3fffff));
    }
    map.elevation_data()[s] = elevation;
    map.certainty_data()[s] = state == static_cast<std::uint8_t>(CellState::measured)
                                  ? std::uniform_real_distribution<float>(0.001f, 100.0f)(random)
                                  : 0.0f;
    map.state_data()[s] = state;
    map.mean_elevation_data()[s] = std::bit_cast<float>(0x7fc00000u | (static_cast<std::uint32_t>(random()) & 0xffff));
    map.mean_count_data()[s] = static_cast<std::uint16_t>(random());
    map.contradiction_data()[s] = static_cast<std::uint8_t>(random());
    map.pending_elevation_data()[s] = std::uniform_real_distribution<float>(-1.0f, 1.0f)(random);
  }
  return map;
}

template <typename T>
bool same_bits(const T* a, const T* b, std::size_t count) {
  return std::memcmp(a, b, count * sizeof(T)) == 0;
}

// Every layer in window order, bit for bit: the storage may start at
// another slot, the cells must not differ.
void expect_identical(const ElevationMap& a, const ElevationMap& b) {
  ASSERT_EQ(a.cells_per_side(), b.cells_per_side());
  ASSERT_EQ(std::bit_cast<std::uint64_t>(a.cell_size_m()), std::bit_cast<std::uint64_t>(b.cell_size_m()));
  ASSERT_EQ(a.min_cell(), b.min_cell());
  std::size_t differences = 0;
  for (int i = 0; i < a.cells_per_side(); ++i) {
    for (int j = 0; j < a.cells_per_side(); ++j) {
      const std::size_t sa = a.slot(a.cell_at_local(i, j)), sb = b.slot(b.cell_at_local(i, j));
      differences += !same_bits(a.elevation_data() + sa, b.elevation_data() + sb, 1) +
                     !same_bits(a.certainty_data() + sa, b.certainty_data() + sb, 1) +
                     !same_bits(a.state_data() + sa, b.state_data() + sb, 1) +
                     !same_bits(a.mean_elevation_data() + sa, b.mean_elevation_data() + sb, 1) +
                     !same_bits(a.mean_count_data() + sa, b.mean_count_data() + sb, 1) +
                     !same_bits(a.contradiction_data() + sa, b.contradiction_data() + sb, 1) +
                     !same_bits(a.pending_elevation_data() + sa, b.pending_elevation_data() + sb, 1);
    }
  }
  EXPECT_EQ(differences, 0u);
}

// Rewrites the trailing CRC so that a deliberately edited file reaches the
// checks behind the checksum.
std::string with_fixed_checksum(std::string bytes) {
  const auto body = static_cast<uInt>(bytes.size() - 4);
  const auto crc = static_cast<std::uint32_t>(crc32(0L, reinterpret_cast<const Bytef*>(bytes.data()), body));
  for (int k = 0; k < 4; ++k) bytes[bytes.size() - 4 + static_cast<std::size_t>(k)] = static_cast<char>(crc >> (8 * k));
  return bytes;
}

std::string replace_once(std::string text, const std::string& from, const std::string& to) {
  const auto at = text.find(from);
  EXPECT_NE(at, std::string::npos) << from;
  if (at != std::string::npos) text.replace(at, from.size(), to);
  return text;
}

std::string decode_error(std::string_view bytes) {
  try {
    io::decode_map_file(bytes, "damaged.smap");
  } catch (const InputError& e) {
    return e.what();
  }
  return "";
}

// A geometry the map itself refuses (cells too large for a map) is named
// with the file, as the reader's own checks are.
TEST(MapFile, AGeometryTheMapRefusesNamesTheFile) {
  const ElevationMap map = scrambled_map(5, 2);
  const std::string bytes = io::encode_map_file(map, {});
  // The same number of characters, so that no offset moves.
  const std::string error =
      decode_error(with_fixed_checksum(replace_once(bytes, "\"cell_size_m\": 0.0125", "\"cell_size_m\": 9.0e99")));
  EXPECT_EQ(error.rfind("damaged.smap: ", 0), 0u) << error;
  EXPECT_NE(error.find("cell_size_m"), std::string::npos) << error;
}

TEST(MapFile, RoundTripsEveryLayerBitExactly) {
  const ElevationMap map = scrambled_map(37, 1);
  io::MapFileMetadata metadata;
  metadata.created_by = "test";
  metadata.config_text = "mount:\n  height_m: 0.3\n";
  metadata.mount = SensorMount{0.3, 0.5, 0.01, -0.02};
  metadata.last_scan_time_s = 1733065200.123456;
  const std::string bytes = io::encode_map_file(map, metadata);
  const io::MapFile loaded = io::decode_map_file(bytes, "memory");
  expect_identical(map, loaded.map);
  EXPECT_EQ(loaded.metadata.created_by, "test");
  EXPECT_EQ(loaded.metadata.config_text, metadata.config_text);
  ASSERT_TRUE(loaded.metadata.mount.has_value());
  EXPECT_EQ(loaded.metadata.mount->pitch_rad, 0.5);
  EXPECT_EQ(loaded.metadata.mount->lateral_offset_m, -0.02);
  EXPECT_EQ(loaded.metadata.last_scan_time_s, metadata.last_scan_time_s);
  EXPECT_EQ(loaded.metadata.tool_version.rfind("stridemap ", 0), 0u) << loaded.metadata.tool_version;
  // Deterministic: the same map and metadata give the same bytes.
  EXPECT_EQ(io::encode_map_file(loaded.map, loaded.metadata), bytes);
}

TEST(MapFile, LayersAreAlignedAndWhereTheMetadataSays) {
  const ElevationMap map = scrambled_map(5, 2);
  const std::string bytes = io::encode_map_file(map, {});
  const std::string header = io::map_file_header_json(bytes, "memory");
  // The elevation of local cell (i, j) sits at offset + 4 (i N + j), as
  // docs/map_file.md tells a reader.
  const auto at = header.find("\"offset\":");
  ASSERT_NE(at, std::string::npos);
  const std::size_t offset = std::stoul(header.substr(at + 9));
  EXPECT_EQ(offset % 8, 0u);
  const std::size_t s = map.slot(map.cell_at_local(2, 3));
  EXPECT_EQ(std::memcmp(bytes.data() + offset + 4 * (2 * 5 + 3), map.elevation_data() + s, 4), 0);
}

TEST(MapFile, SaveAndLoadThroughTheFileSystem) {
  TestFolder folder;
  const ElevationMap map = scrambled_map(20, 3);
  const std::string path = folder / "map.smap";
  io::save_map_file(path, map, {});
  expect_identical(map, io::load_map_file(path).map);
  // An existing map file is replaced; no temporary file is left behind.
  const ElevationMap other = scrambled_map(20, 4);
  io::save_map_file(path, other, {});
  expect_identical(other, io::load_map_file(path).map);
  EXPECT_EQ(std::distance(std::filesystem::directory_iterator(folder.path()), {}), 1);
}

TEST(MapFile, RefusesToReplaceAFileThatIsNotAMapFile) {
  TestFolder folder;
  const std::string path = folder.write("notes.txt", "my notes\n");
  try {
    io::save_map_file(path, scrambled_map(4, 5), {});
    FAIL() << "a text file was overwritten";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("not a map file"), std::string::npos) << e.what();
  }
  EXPECT_EQ(folder.read("notes.txt"), "my notes\n");
  io::save_map_file(path, scrambled_map(4, 5), {}, {.overwrite_other_files = true});
  EXPECT_TRUE(io::is_map_file(path));
}

TEST(MapFile, SaveIntoAMissingFolderNamesThePath) {
  TestFolder folder;
  try {
    io::save_map_file(folder / "missing/map.smap", scrambled_map(4, 6), {});
    FAIL();
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("missing/map.smap"), std::string::npos) << e.what();
  }
}

TEST(MapFile, MissingFileAndFolderAreClearErrors) {
  TestFolder folder;
  EXPECT_THROW(io::load_map_file(folder / "nothing.smap"), InputError);
  try {
    io::load_map_file(folder.path().string());
    FAIL();
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("folder"), std::string::npos) << e.what();
  }
}

TEST(MapFile, EveryDamagedByteIsFound) {
  const std::string bytes = io::encode_map_file(scrambled_map(6, 7), {});
  for (std::size_t k = 0; k < bytes.size(); k += 7) {
    std::string damaged = bytes;
    damaged[k] = static_cast<char>(damaged[k] ^ 0x10);
    const std::string error = decode_error(damaged);
    EXPECT_FALSE(error.empty()) << "a flipped bit at byte " << k << " went unnoticed";
    EXPECT_NE(error.find("damaged.smap"), std::string::npos) << error;
  }
}

TEST(MapFile, TruncatedFilesAreRefused) {
  const std::string bytes = io::encode_map_file(scrambled_map(6, 8), {});
  for (const std::size_t length : {std::size_t{0}, std::size_t{7}, std::size_t{12}, std::size_t{19},
                                   bytes.size() / 2, bytes.size() - 1}) {
    const std::string error = decode_error(std::string_view(bytes).substr(0, length));
    EXPECT_FALSE(error.empty()) << length;
  }
  EXPECT_NE(decode_error(bytes.substr(0, bytes.size() - 1)).find("checksum mismatch"), std::string::npos);
  EXPECT_NE(decode_error("P5\n2 2\n255\n....").find("not a stridemap map file"), std::string::npos);
}

TEST(MapFile, StructuralLiesBehindAValidChecksumAreRefused) {
  const std::string bytes = io::encode_map_file(scrambled_map(6, 9), {});
  std::string newer = bytes;
  newer[8] = 2;
  EXPECT_NE(decode_error(with_fixed_checksum(newer)).find("version 2"), std::string::npos);

  std::string long_header = bytes;
  long_header[15] = 0x7f;
  EXPECT_NE(decode_error(with_fixed_checksum(long_header)).find("bytes of metadata"), std::string::npos);

  // Sizes that do not fit the file are refused before anything is allocated.
  const std::string more_cells = with_fixed_checksum(replace_once(bytes, "\"cells_per_side\": 6", "\"cells_per_side\": 9"));
  EXPECT_NE(decode_error(more_cells).find("81 cells of <f4 need 324"), std::string::npos) << decode_error(more_cells);
  std::string far_offset = bytes;
  const auto offset_at = far_offset.find("\"offset\": ") + 10;
  for (std::size_t k = offset_at; std::isdigit(static_cast<unsigned char>(far_offset[k])); ++k) far_offset[k] = '9';
  far_offset = with_fixed_checksum(far_offset);
  EXPECT_NE(decode_error(far_offset).find("lie outside the layer data"), std::string::npos) << decode_error(far_offset);
  const std::string ten = io::encode_map_file(scrambled_map(10, 9), {});
  const std::string negative = with_fixed_checksum(replace_once(ten, "\"cells_per_side\": 10", "\"cells_per_side\": -1"));
  EXPECT_NE(decode_error(negative).find("outside 1..20000"), std::string::npos) << decode_error(negative);
  // A float where an integer belongs is refused, not converted (1e9 as an int would overflow).
  const std::string as_float = with_fixed_checksum(replace_once(ten, "\"cells_per_side\": 10", "\"cells_per_side\":1e9"));
  EXPECT_NE(decode_error(as_float).find("must be a whole number"), std::string::npos) << decode_error(as_float);

  const std::string wrong_type = with_fixed_checksum(replace_once(bytes, "\"type\": \"|u1\"", "\"type\": \"<f4\""));
  EXPECT_NE(decode_error(wrong_type).find("type <f4, expected |u1"), std::string::npos) << decode_error(wrong_type);

  const std::string no_layer = with_fixed_checksum(replace_once(bytes, "\"name\": \"certainty\"", "\"name\": \"certainly\""));
  EXPECT_NE(decode_error(no_layer).find("layer 'certainty' is missing"), std::string::npos);

  const std::string bad_json = with_fixed_checksum(replace_once(bytes, "{", "["));
  EXPECT_NE(decode_error(bad_json).find("metadata"), std::string::npos) << decode_error(bad_json);
}

TEST(MapFile, DeeplyNestedMetadataIsRefusedAtOnce) {
  io::MapFileMetadata metadata;
  metadata.created_by = std::string(200000, 'a');
  const std::string bytes = io::encode_map_file(scrambled_map(4, 2), metadata);
  // The same length as the string it replaces: every offset stays valid.
  const std::string deep = with_fixed_checksum(replace_once(
      bytes, "\"" + metadata.created_by + "\"", std::string(100001, '[') + std::string(100001, ']')));
  const std::string error = decode_error(deep);
  EXPECT_NE(error.find("damaged.smap"), std::string::npos) << error;
  EXPECT_NE(error.find("nested deeper than 64 levels"), std::string::npos) << error;
}

TEST(MapFile, AStateThatDoesNotExistIsRefused) {
  ElevationMap map = scrambled_map(4, 10);
  map.state_data()[5] = 9;
  const std::string error = decode_error(io::encode_map_file(map, {}));
  EXPECT_NE(error.find("state 9"), std::string::npos) << error;
}

TEST(MapFile, InvalidCellsBehindAValidChecksumAreRefusedNamingTheCell) {
  const ElevationMap valid = scrambled_map(8, 11);
  EXPECT_EQ(decode_error(io::encode_map_file(valid, {})), "");
  struct Case {
    std::uint8_t state;
    float elevation, certainty;
    const char* expected;
  };
  const float inf = std::numeric_limits<float>::infinity(), nan = std::numeric_limits<float>::quiet_NaN();
  const Case cases[] = {
      {1, inf, 2.0f, "measured but elevation inf"},
      {1, 0.1f, nan, "measured but elevation 0.1"},
      {1, 0.1f, -1.0f, "certainty -1"},
      {1, 0.1f, inf, "certainty inf"},
      {2, -inf, 0.0f, "filled but elevation -inf"},
      {0, 0.3f, 0.0f, "unknown but elevation 0.3"},
  };
  for (const Case& c : cases) {
    ElevationMap map = valid;
    const CellIndex cell = map.cell_at_local(3, 5);
    const std::size_t s = map.slot(cell);
    map.state_data()[s] = c.state;
    map.elevation_data()[s] = c.elevation;
    map.certainty_data()[s] = c.certainty;
    const std::string error = decode_error(io::encode_map_file(map, {}));
    const std::string where = "damaged.smap: cell (" + std::to_string(cell.x) + ", " + std::to_string(cell.y) + "): ";
    EXPECT_EQ(error.rfind(where, 0), 0u) << error;
    EXPECT_NE(error.find(c.expected), std::string::npos) << error;
    EXPECT_NE(error.find("(1 invalid cell in all;"), std::string::npos) << error;
  }
  // Many bad cells: the first is named and all are counted.
  ElevationMap map = valid;
  for (std::size_t s = 0; s < 10; ++s) {
    map.state_data()[s] = 1;
    map.elevation_data()[s] = inf;
    map.certainty_data()[s] = 1.0f;
  }
  EXPECT_NE(decode_error(io::encode_map_file(map, {})).find("(10 invalid cells in all;"), std::string::npos);
}

// Ranges of a sensor looking down at flat ground with a deterministic wobble,
// so that the update rule meets plausible and contradicting readings.
PlanarScan wobbly_scan(const SensorMount& mount, int index) {
  PlanarScan scan;
  scan.time_s = 0.1 * (index + 1);
  constexpr int kBeams = 181;
  scan.resize(kBeams);
  for (int i = 0; i < kBeams; ++i) {
    const double t = -0.9 + 1.8 * i / (kBeams - 1);
    const auto k = static_cast<std::size_t>(i);
    scan.angle_rad[k] = t;
    const double wobble = 0.02 * std::sin(0.7 * i + 1.3 * index) + (((i * 7 + index * 13) % 17) == 0 ? 0.15 : 0.0);
    scan.range_m[k] = mount.height_m / (std::cos(t) * std::sin(mount.pitch_rad)) + wobble;
    scan.range_error_m[k] = 0.005;
  }
  return scan;
}

TEST(MapResume, SavedAndResumedMappingEqualsMappingWithoutAStop) {
  TestFolder folder;
  SensorMount mount;
  MapperOptions options;
  options.grid = {120, 0.01};
  options.update.elevation_rule = ElevationRule::gated_highest;
  // Standing still (no travel term either way); the trunk height jumps now
  // and then, singly and three scans in a row, so that cells meet
  // contradicting readings and the gated rule replaces some.
  const auto pose_at = [](int k) {
    TrunkPose pose{0.2, -0.1, 0.3, 0.0, 0.0, 0.0, 0.0};
    const int phase = k % 9;
    pose.height_change_m = phase == 2 || (phase >= 5 && phase <= 7) ? 0.08 : 0.0;
    return pose;
  };

  TerrainMapper straight(options, mount);
  TerrainMapper first_half(options, mount);
  for (int k = 0; k < 40; ++k) {
    straight.integrate(wobbly_scan(mount, k), pose_at(k));
    if (k < 20) first_half.integrate(wobbly_scan(mount, k), pose_at(k));
  }
  io::MapFileMetadata metadata;
  metadata.mount = mount;
  metadata.last_scan_time_s = first_half.last_scan_time_s();
  io::save_map_file(folder / "half.smap", first_half.map(), metadata);

  const io::MapFile saved = io::load_map_file(folder / "half.smap");
  TerrainMapper resumed(options_for_map(options, saved.map), *saved.metadata.mount);
  resume_from_map(resumed, saved.map);
  for (int k = 20; k < 40; ++k) resumed.integrate(wobbly_scan(mount, k), pose_at(k));

  // The gated bookkeeping was exercised across the stop.
  EXPECT_GT(straight.totals().implausible, 100u);
  EXPECT_TRUE(check_map_integrity(resumed.map(), options.update.certainty_max).ok());
  expect_identical(straight.map(), resumed.map());
  EXPECT_EQ(map_layers_hash(straight.map()), map_layers_hash(resumed.map()));
  // A fresh mapper that did not resume differs: the test can tell.
  TerrainMapper fresh(options, mount);
  for (int k = 20; k < 40; ++k) fresh.integrate(wobbly_scan(mount, k), pose_at(k));
  EXPECT_NE(map_layers_hash(straight.map()), map_layers_hash(fresh.map()));
}

TEST(MapResume, AGridThatDoesNotMatchIsRefused) {
  MapperOptions options;
  options.grid = {50, 0.01};
  TerrainMapper mapper(options, SensorMount{});
  try {
    resume_from_map(mapper, ElevationMap(GridOptions{50, 0.02}));
    FAIL();
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("cannot resume"), std::string::npos) << e.what();
  }
}

}  // namespace
}  // namespace stridemap
