// An export format added from outside the library by one registration is
// listed and written like the built-in ones (docs/architecture.md, "Adding
// an output format").
#include "stridemap/render/map_export_formats.hpp"

#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "live/test_folder.hpp"
#include "stridemap/core/error.hpp"

namespace stridemap {
namespace {

using test::TestFolder;

// What the test format's writer saw on its last call.
struct WriterCall {
  int calls = 0;
  std::string path;
  std::vector<std::string> layers;
};
WriterCall last_call;

// One line: the map's side and the layers it was asked for.
const io::MapExportFormatRegistrar summary_format({
    "summary-txt",
    "Text file with the map's size",
    false,
    true,
    [](const ElevationMap&, const std::string& path, std::span<const std::string>) {
      return std::vector<std::string>{path};
    },
    [](const ElevationMap& map, const std::string& path, std::span<const std::string> layers) {
      ++last_call.calls;
      last_call.path = path;
      last_call.layers.assign(layers.begin(), layers.end());
      std::ofstream(path) << map.cells_per_side() << " cells, " << layers.size() << " layers\n";
      return "summary " + path;
    },
});

TEST(MapExportFormats, TheBuiltInFormatsComeFirstThenTheRegisteredOne) {
  std::vector<std::string> names;
  for (const io::MapExportFormat& format : io::map_export_formats()) names.push_back(format.name);
  EXPECT_EQ(names, (std::vector<std::string>{"npy", "ply", "csv", "summary-txt"}));
  EXPECT_TRUE(io::map_export_format("npy").folder);
  EXPECT_FALSE(io::map_export_format("ply").takes_layers);
  EXPECT_EQ(io::map_export_format("summary-txt").description, "Text file with the map's size");
}

TEST(MapExportFormats, ARegisteredWriterIsCalledByAnExport) {
  const TestFolder folder;
  const ElevationMap map(GridOptions{8, 0.1});
  const std::vector<std::string> layers{"elevation", "state"};
  const std::vector<io::MapExportRequest> requests{{"summary-txt", folder / "map.txt"}, {"ply", folder / "map.ply"},
                                                   {"csv", folder / "csv"}};
  EXPECT_EQ(io::map_export_outputs(map, requests, layers),
            (std::vector<std::string>{folder / "map.txt", folder / "map.ply",
                                      (std::filesystem::path(folder / "csv") / "cells.csv").string()}));
  last_call = {};
  const std::vector<std::string> lines = io::export_map(map, requests, layers);
  ASSERT_EQ(lines.size(), 3u);
  EXPECT_EQ(lines[0], "summary " + std::string(folder / "map.txt"));
  EXPECT_EQ(lines[1].rfind("PLY mesh ", 0), 0u) << lines[1];
  EXPECT_EQ(last_call.calls, 1);
  EXPECT_EQ(last_call.layers, layers);
  std::ifstream in(folder / "map.txt");
  std::stringstream text;
  text << in.rdbuf();
  EXPECT_EQ(text.str(), "8 cells, 2 layers\n");
  EXPECT_TRUE(std::filesystem::exists(folder / "csv/cells.csv"));
}

TEST(MapExportFormats, UnknownNamesAndBadRegistrationsAreInputErrors) {
  const ElevationMap map(GridOptions{4, 0.1});
  const std::vector<io::MapExportRequest> requests{{"obj", "map.obj"}};
  try {
    io::export_map(map, requests);
    FAIL() << "an unknown format was written";
  } catch (const InputError& error) {
    EXPECT_NE(std::string(error.what()).find("npy, ply, csv, summary-txt"), std::string::npos) << error.what();
  }
  const auto outputs = [](const ElevationMap&, const std::string& p, std::span<const std::string>) {
    return std::vector<std::string>{p};
  };
  const auto write = [](const ElevationMap&, const std::string&, std::span<const std::string>) { return std::string(); };
  EXPECT_THROW(io::register_map_export_format({"csv", "taken", false, false, outputs, write}), InputError);
  EXPECT_THROW(io::register_map_export_format({"--x", "option-like", false, false, outputs, write}), InputError);
  EXPECT_THROW(io::register_map_export_format({"nowriter", "", false, false, outputs, {}}), InputError);
}

}  // namespace
}  // namespace stridemap
