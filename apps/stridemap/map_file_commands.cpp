// `stridemap export MAPFILE` (NumPy arrays, a PLY mesh, a cell CSV) and
// `stridemap map-info MAPFILE` (what the file says about itself);
// docs/map_file.md.

#include <cstdio>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <memory>
#include <string>
#include <system_error>
#include <utility>
#include <vector>

#include "commands.hpp"
#include "output_guard.hpp"
#include "stridemap/core/printable_text.hpp"
#include "stridemap/core/error.hpp"
#include "stridemap/mapfile/map_file.hpp"
#include "stridemap/mapfile/tile_store.hpp"
#include "stridemap/render/map_export.hpp"

namespace stridemap::cli {
namespace {

struct ExportArgs {
  std::string map_path;
  std::string npy_dir;
  std::string ply_path;
  std::string csv_dir;
  std::vector<std::string> layers;
  bool info = false;
  bool overwrite = false;
};

std::string read_bytes(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) throw InputError(path + ": cannot open the map file");
  return {std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
}

void print_info(const std::string& path) {
  std::fputs(io::map_file_header_json(read_bytes(path), path).c_str(), stdout);
}

void run_export(const ExportArgs& args) {
  if (args.npy_dir.empty() && args.ply_path.empty() && args.csv_dir.empty() && !args.info) {
    throw InputError("export: nothing to do; give --npy DIR, --ply FILE, --csv DIR or --info");
  }
  // Loaded first: which files the arrays are depends on the layers the file
  // holds, and a wrong --layers name is refused before anything is written.
  const io::MapFile file = io::load_map_file(args.map_path);
  if (!args.layers.empty() && args.npy_dir.empty() && args.csv_dir.empty()) {
    throw InputError("export: --layers selects the layers of --npy and --csv; give one of them");
  }
  std::vector<NamedPath> outputs;
  for (const std::string& name : io::npy_file_names(file.map, args.layers)) {
    if (!args.npy_dir.empty()) outputs.push_back({"--npy", (std::filesystem::path(args.npy_dir) / name).string()});
  }
  outputs.push_back({"--ply", args.ply_path});
  if (!args.csv_dir.empty()) outputs.push_back({"--csv", (std::filesystem::path(args.csv_dir) / "cells.csv").string()});
  refuse_existing_files(outputs, args.overwrite);
  if (args.info) print_info(args.map_path);
  if (!args.npy_dir.empty()) {
    io::export_npy(file.map, args.npy_dir, args.layers);
    std::printf("export: NumPy arrays in %s\n", printable_text(args.npy_dir).c_str());
  }
  if (!args.ply_path.empty()) {
    const io::PlyStats stats = io::export_ply(file.map, args.ply_path);
    std::printf("export: PLY mesh %s: %zu vertices, %zu triangles\n", printable_text(args.ply_path).c_str(), stats.vertices,
                stats.triangles);
  }
  if (!args.csv_dir.empty()) {
    std::printf("export: %s\n", printable_text(io::export_cells_csv(file.map, args.csv_dir, args.layers)).c_str());
  }
}

}  // namespace

void register_map_file_commands(CLI::App& app) {
  auto args = std::make_shared<ExportArgs>();
  CLI::App* command = app.add_subcommand("export", "A map file as NumPy arrays, a PLY mesh or CSV (docs/map_file.md)");
  command->add_option("mapfile", args->map_path, "Map file (map.smap, written by map and live)")->required();
  command->add_option("--npy", args->npy_dir, "Folder for one .npy array per layer");
  command->add_option("--ply", args->ply_path, "PLY mesh file, coloured by elevation");
  command->add_option("--csv", args->csv_dir, "Folder for cells.csv, one line per cell");
  command->add_option("--layers", args->layers,
                      "Layers for --npy and --csv, by name (e.g. elevation,certainty); default: all for --npy, "
                      "the planner's and the user's for --csv; map-info lists them")
      ->delimiter(',');
  command->add_flag("--info", args->info, "Also print the map file's metadata");
  command->add_flag("--overwrite", args->overwrite, "Replace existing output files");
  command->callback([args] { run_export(*args); });

  auto info_path = std::make_shared<std::string>();
  CLI::App* info = app.add_subcommand("map-info", "Print a map file's metadata as JSON (checks the file whole)");
  info->add_option("mapfile", *info_path, "Map file")->required();
  info->callback([info_path] {
    io::load_map_file(*info_path);  // the whole file checked, not only its header
    print_info(*info_path);
  });

  // The global map's tiles (docs/global_map.md) as one map file.
  auto merge = std::make_shared<std::pair<std::string, std::string>>();
  CLI::App* tiles = app.add_subcommand("merge-tiles", "A global map folder's tiles as one map file (docs/global_map.md)");
  tiles->add_option("folder", merge->first, "Global map folder (--global-map of map or live)")->required();
  tiles->add_option("--out", merge->second, "Map file to write; must not exist yet")->required();
  tiles->callback([merge] {
    std::error_code ec;
    if (std::filesystem::exists(std::filesystem::symlink_status(merge->second, ec))) {
      throw InputError("--out: '" + merge->second + "' exists; merge-tiles writes only a new file");
    }
    const io::MergedTiles merged = io::merge_tiles(merge->first);
    io::MapFileMetadata metadata;
    metadata.created_by = "merge-tiles " + merge->first;
    io::save_map_file(merge->second, merged.map, metadata);
    std::printf("merge-tiles: %d x %d cells of %g m from %s into %s\n", merged.map.cells_per_side(),
                merged.map.cells_per_side(), merged.map.cell_size_m(), merge->first.c_str(), merge->second.c_str());
    if (!merged.holes.empty()) {
      for (const std::string& hole : merged.holes) std::fprintf(stderr, "  %s\n", printable_text(hole).c_str());
      throw RunFailed("merge-tiles: the merged map has holes where " + std::to_string(merged.holes.size()) +
                      " tiles are missing or damaged (listed above); their cells are unknown");
    }
  });
}

}  // namespace stridemap::cli
