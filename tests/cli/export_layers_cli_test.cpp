// `stridemap export --layers`: the layers of a map file chosen by name, a
// user's own layer included; an unknown name is refused before anything is
// written.
#include <filesystem>
#include <string>

#include <gtest/gtest.h>

#include "cli/cli_runner.hpp"
#include "live/test_folder.hpp"
#include "stridemap/mapfile/map_file.hpp"

namespace stridemap {
namespace {

using test::run_cli;
using test::shell_quoted;
using test::TestFolder;

std::string map_with_hit_count(const TestFolder& folder) {
  LayerSpec hits;
  hits.name = "hit_count";
  hits.type = LayerType::u16;
  ElevationMap map(GridOptions{6, 0.05, {hits}});
  map.data(map.layer<std::uint16_t>("hit_count"))[7] = 3;
  const std::string path = folder / "map.smap";
  io::save_map_file(path, map, {});
  return path;
}

TEST(ExportCli, LayersAreChosenByName) {
  TestFolder folder;
  const std::string map = map_with_hit_count(folder);
  const auto exported = run_cli("export " + shell_quoted(map) + " --npy " + shell_quoted(folder / "npy") +
                                " --csv " + shell_quoted(folder / "csv") + " --layers hit_count,elevation");
  ASSERT_EQ(exported.exit_code, 0) << exported.output;
  EXPECT_TRUE(std::filesystem::exists(folder.path() / "npy/hit_count.npy"));
  EXPECT_TRUE(std::filesystem::exists(folder.path() / "npy/elevation.npy"));
  EXPECT_FALSE(std::filesystem::exists(folder.path() / "npy/certainty.npy"));
  EXPECT_NE(folder.read("csv/cells.csv").find("\nix,iy,x_m,y_m,hit_count,elevation_m\n"), std::string::npos);

  const auto info = run_cli("map-info " + shell_quoted(map));
  ASSERT_EQ(info.exit_code, 0) << info.output;
  EXPECT_NE(info.output.find("\"hit_count\""), std::string::npos) << info.output;
}

TEST(ExportCli, AnUnknownLayerNameListsTheLayersThereAre) {
  TestFolder folder;
  const std::string map = map_with_hit_count(folder);
  const auto refused =
      run_cli("export " + shell_quoted(map) + " --npy " + shell_quoted(folder / "npy") + " --layers elevation,slope");
  EXPECT_EQ(refused.exit_code, 2) << refused.output;
  EXPECT_NE(refused.output.find("'slope'"), std::string::npos) << refused.output;
  EXPECT_NE(refused.output.find("contradictions, hit_count"), std::string::npos) << refused.output;
  EXPECT_FALSE(std::filesystem::exists(folder.path() / "npy"));

  const auto alone = run_cli("export " + shell_quoted(map) + " --layers elevation --ply " + shell_quoted(folder / "m.ply"));
  EXPECT_EQ(alone.exit_code, 2) << alone.output;
  EXPECT_FALSE(std::filesystem::exists(folder.path() / "m.ply"));
}

}  // namespace
}  // namespace stridemap
