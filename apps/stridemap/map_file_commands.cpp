// `stridemap export MAPFILE` (one option per registered export format:
// NumPy arrays, a PLY mesh, a cell CSV, ...) and
// `stridemap map-info MAPFILE` (what the file says about itself);
// docs/map_file.md.

#include <cstdio>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <map>
#include <memory>
#include <span>
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
#include "stridemap/render/map_export_formats.hpp"

namespace stridemap::cli {
namespace {

struct ExportArgs {
  std::string map_path;
  // One path per registered format (io::map_export_formats), by name.
  std::map<std::string, std::string> paths;
  std::vector<std::string> layers;
  bool info = false;
  bool overwrite = false;
};

std::string option_of(const io::MapExportFormat& format) { return "--" + format.name; }

std::string read_bytes(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) throw InputError(path + ": cannot open the map file");
  return {std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
}

void print_info(const std::string& path) {
  std::fputs(io::map_file_header_json(read_bytes(path), path).c_str(), stdout);
}

void run_export(const ExportArgs& args) {
  const std::vector<io::MapExportFormat> formats = io::map_export_formats();
  std::vector<io::MapExportRequest> requests;
  bool takes_layers = false;
  std::string choices, layered;
  for (const io::MapExportFormat& format : formats) {
    choices += option_of(format) + (format.folder ? " DIR, " : " FILE, ");
    if (format.takes_layers) layered += (layered.empty() ? "" : " and ") + option_of(format);
    const auto path = args.paths.find(format.name);
    if (path == args.paths.end() || path->second.empty()) continue;
    requests.push_back({format.name, path->second});
    takes_layers = takes_layers || format.takes_layers;
  }
  if (requests.empty() && !args.info) {
    choices.resize(choices.size() - 2);
    throw InputError("export: nothing to do; give " + choices + " or --info");
  }
  // Loaded first: which files the arrays are depends on the layers the file
  // holds, and a wrong --layers name is refused before anything is written.
  const io::MapFile file = io::load_map_file(args.map_path);
  if (!args.layers.empty() && !takes_layers) {
    throw InputError("export: --layers selects the layers of " + layered + "; give one of them");
  }
  std::vector<NamedPath> outputs;
  for (const io::MapExportRequest& request : requests) {
    for (const std::string& path : io::map_export_outputs(file.map, std::span(&request, 1), args.layers)) {
      outputs.push_back({"--" + request.format, path});
    }
  }
  refuse_existing_files(outputs, args.overwrite);
  if (args.info) print_info(args.map_path);
  for (const io::MapExportRequest& request : requests) {
    const std::vector<std::string> line = io::export_map(file.map, std::span(&request, 1), args.layers);
    std::printf("export: %s\n", line.front().c_str());
  }
}

}  // namespace

void register_map_file_commands(CLI::App& app) {
  auto args = std::make_shared<ExportArgs>();
  CLI::App* command = app.add_subcommand("export", "A map file as NumPy arrays, a PLY mesh or CSV (docs/map_file.md)");
  command->add_option("mapfile", args->map_path, "Map file (map.smap, written by map and live)")->required();
  std::string layered;
  for (const io::MapExportFormat& format : io::map_export_formats()) {
    command->add_option(option_of(format), args->paths[format.name], format.description)
        ->type_name(format.folder ? "DIR" : "FILE");
    if (format.takes_layers) layered += (layered.empty() ? "" : " and ") + option_of(format);
  }
  command->add_option("--layers", args->layers,
                      "Layers for " + layered + ", by name (e.g. elevation,certainty); default: all for --npy, "
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
