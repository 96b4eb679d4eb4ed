#include "stridemap/render/map_export.hpp"

#include <cmath>
#include <cstring>
#include <sstream>
#include <vector>

#include <gtest/gtest.h>

#include "live/test_folder.hpp"
#include "stridemap/core/error.hpp"

namespace stridemap {
namespace {

using test::TestFolder;

// A 4 x 4 map at a moved window: a known 3 x 3 block in one corner (a
// ramp along x), a single known cell apart, everything else unknown.
ElevationMap small_map() {
  ElevationMap map(GridOptions{4, 0.5});
  map.move_corner_to({10, -3});
  for (int i = 0; i < 3; ++i) {
    for (int j = 0; j < 3; ++j) {
      const std::size_t s = map.slot(map.cell_at_local(i, j));
      map.elevation_data()[s] = 0.1f * static_cast<float>(i);
      map.certainty_data()[s] = 3.0f;
      map.state_data()[s] = static_cast<std::uint8_t>(CellState::measured);
      map.mean_elevation_data()[s] = 0.1f * static_cast<float>(i) - 0.01f;
      map.mean_count_data()[s] = static_cast<std::uint16_t>(i + j + 1);
    }
  }
  const std::size_t lone = map.slot(map.cell_at_local(3, 3));
  map.elevation_data()[lone] = 0.7f;
  map.state_data()[lone] = static_cast<std::uint8_t>(CellState::filled);
  return map;
}

TEST(MapExport, NpyHeaderIsNumPyVersion1) {
  const std::string bytes = io::encode_npy("<f4", 2, 3, std::string(24, '\0'));
  ASSERT_GE(bytes.size(), 10u);
  EXPECT_EQ(bytes.substr(0, 8), std::string("\x93NUMPY\x01\x00", 8));
  const std::size_t header_length = static_cast<unsigned char>(bytes[8]) | (static_cast<unsigned char>(bytes[9]) << 8);
  EXPECT_EQ((10 + header_length) % 64, 0u);
  const std::string header = bytes.substr(10, header_length);
  EXPECT_EQ(header.rfind("{'descr': '<f4', 'fortran_order': False, 'shape': (2, 3), }", 0), 0u) << header;
  EXPECT_EQ(header.back(), '\n');
  EXPECT_EQ(bytes.size(), 10 + header_length + 24);
}

TEST(MapExport, NpyFilesHoldTheLayersInWindowOrder) {
  TestFolder folder;
  const ElevationMap map = small_map();
  const auto paths = io::export_npy(map, folder / "npy");
  ASSERT_EQ(paths.size(), io::npy_file_names(map).size());
  const std::string elevation = folder.read("npy/elevation.npy");
  const std::size_t header_length = static_cast<unsigned char>(elevation[8]) |
                                    (static_cast<unsigned char>(elevation[9]) << 8);
  ASSERT_EQ(elevation.size(), 10 + header_length + 16 * 4);
  float value = 0;
  std::memcpy(&value, elevation.data() + 10 + header_length + 4 * (2 * 4 + 1), 4);  // [2][1]
  EXPECT_EQ(value, 0.2f);
  std::memcpy(&value, elevation.data() + 10 + header_length + 4 * (0 * 4 + 3), 4);  // [0][3], unknown
  EXPECT_TRUE(std::isnan(value));
  const std::string state = folder.read("npy/state.npy");
  EXPECT_NE(state.find("'descr': '|u1'"), std::string::npos);
  EXPECT_EQ(state.back(), 2);  // [3][3], the filled cell
  const std::string count = folder.read("npy/mean_count.npy");
  EXPECT_NE(count.find("'descr': '<u2'"), std::string::npos);
  EXPECT_EQ(count.size() % 2, 0u);
}

TEST(MapExport, PlyMeshHasAVertexPerKnownCellAndHoles) {
  TestFolder folder;
  const io::PlyStats stats = io::export_ply(small_map(), folder / "map.ply");
  EXPECT_EQ(stats.vertices, 10u);
  // The 3 x 3 block gives 2 x 2 quads of two triangles; the lone cell at
  // (3, 3) touches known cells only diagonally through (2, 2): the block
  // (2..3, 2..3) has 2 known corners, no triangle.
  EXPECT_EQ(stats.triangles, 8u);
  const std::string ply = folder.read("map.ply");
  const auto end = ply.find("end_header\n");
  ASSERT_NE(end, std::string::npos);
  const std::string header = ply.substr(0, end);
  EXPECT_NE(header.find("format binary_little_endian 1.0"), std::string::npos);
  EXPECT_NE(header.find("element vertex 10\n"), std::string::npos);
  EXPECT_NE(header.find("element face 8\n"), std::string::npos);
  EXPECT_NE(header.find("property uchar red"), std::string::npos);
  // 15 bytes per vertex, 13 per triangle: nothing more, nothing less.
  EXPECT_EQ(ply.size(), end + 11 + 10 * 15 + 8 * 13);
  // The first vertex is local cell (0, 0): global (10, -3), centre (5.25, -1.25).
  float xyz[3];
  std::memcpy(xyz, ply.data() + end + 11, 12);
  EXPECT_FLOAT_EQ(xyz[0], 5.25f);
  EXPECT_FLOAT_EQ(xyz[1], -1.25f);
  EXPECT_FLOAT_EQ(xyz[2], 0.0f);
  // Every face indexes an existing vertex.
  for (std::size_t f = 0; f < stats.triangles; ++f) {
    const char* face = ply.data() + end + 11 + 10 * 15 + f * 13;
    EXPECT_EQ(face[0], 3);
    for (int k = 0; k < 3; ++k) {
      std::int32_t index = -1;
      std::memcpy(&index, face + 1 + 4 * k, 4);
      EXPECT_GE(index, 0);
      EXPECT_LT(index, 10);
    }
  }
}

TEST(MapExport, EmptyMapGivesAnEmptyButValidMesh) {
  TestFolder folder;
  const io::PlyStats stats = io::export_ply(ElevationMap(GridOptions{3, 0.1}), folder / "empty.ply");
  EXPECT_EQ(stats.vertices, 0u);
  EXPECT_EQ(stats.triangles, 0u);
  EXPECT_NE(folder.read("empty.ply").find("element vertex 0\n"), std::string::npos);
}

TEST(MapExport, CellsCsvStatesItsOrderAndHasEveryCell) {
  TestFolder folder;
  io::export_cells_csv(small_map(), folder / "csv");
  std::istringstream csv(folder.read("csv/cells.csv"));
  std::string line;
  std::getline(csv, line);
  EXPECT_NE(line.find("rows ordered by ix ascending, then iy ascending"), std::string::npos) << line;
  EXPECT_NE(line.find("cell_size_m=0.5"), std::string::npos) << line;
  std::getline(csv, line);
  EXPECT_EQ(line, "ix,iy,x_m,y_m,elevation_m,certainty,state,mean_elevation_m,mean_count");
  std::vector<std::string> rows;
  while (std::getline(csv, line)) rows.push_back(line);
  ASSERT_EQ(rows.size(), 16u);
  EXPECT_EQ(rows[0], "10,-3,5.25,-1.25,0,3,1,-0.00999999978,1");
  EXPECT_EQ(rows[3], "10,0,5.25,0.25,nan,0,0,nan,0");
  EXPECT_EQ(rows[9], "12,-2,6.25,-0.75,0.200000003,3,1,0.189999998,4");
}

TEST(MapExport, ACsvColumnNamesItsUnitOnceWhenTheLayerNameHasIt) {
  GridOptions grid{2, 0.5};
  grid.extra_layers.push_back(LayerSpec{"slope_deg", LayerType::f32, 0.0, "deg", "slope", true});
  grid.extra_layers.push_back(LayerSpec{"step", LayerType::f32, 0.0, "m", "step height", true});
  TestFolder folder;
  const std::vector<std::string> layers{"slope_deg", "step"};
  io::export_cells_csv(ElevationMap(grid), folder / "csv", layers);
  std::istringstream csv(folder.read("csv/cells.csv"));
  std::string line;
  std::getline(csv, line);
  std::getline(csv, line);
  EXPECT_EQ(line, "ix,iy,x_m,y_m,slope_deg,step_m");
}

TEST(MapExport, UnwritableDestinationsNameThePath) {
  TestFolder folder;
  folder.write("file", "x");
  try {
    io::export_npy(small_map(), folder / "file/sub");
    FAIL();
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("file/sub"), std::string::npos) << e.what();
  }
  EXPECT_THROW(io::export_ply(small_map(), folder / "missing/map.ply"), InputError);
}

}  // namespace
}  // namespace stridemap
