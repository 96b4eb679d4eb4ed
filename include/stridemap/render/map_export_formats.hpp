#pragma once
// The map's export formats by name. Each format is one registration (name,
// what it writes, whether its path is a folder, whether it takes a layer
// selection, the files it writes, the writer), and the list of registrations
// is the only list of formats: `stridemap export` has one option per format
// (--npy, --ply, --csv, ...) and its messages, Python's Map.export and
// export_formats() read it. A format registered at run time (a user's
// program, a test) is therefore written like a built-in one
// (docs/architecture.md, "Adding an output format").
//
// Register before the first export and from one thread: the registry is for
// start-up.
#include <functional>
#include <span>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

#include "stridemap/core/grid_map.hpp"

namespace stridemap::io {

struct MapExportFormat {
  /// The tool's option is --<name>; no blank, '=' or leading '-'.
  std::string name;
  /// One line for the tool's help and Python.
  std::string description;
  /// The path names a folder the files go into (the help's DIR), else the one file (FILE).
  bool folder = false;
  /// Reads a layer selection (the tool's --layers; empty: the format's default).
  bool takes_layers = false;
  /// The paths of the files the writer would write, for the check that
  /// nothing is overwritten unasked before any file is written.
  std::function<std::vector<std::string>(const ElevationMap& map, const std::string& path,
                                         std::span<const std::string> layers)>
      outputs;
  /// Writes the map; returns what the tool prints after "export: " (paths
  /// passed through printable_text). Throws InputError naming the path.
  std::function<std::string(const ElevationMap& map, const std::string& path, std::span<const std::string> layers)>
      write;
};

/// Adds a format after the built-in npy, ply and csv. Throws InputError on
/// an invalid or taken name or a missing function.
void register_map_export_format(MapExportFormat format);

/// For a registration from a namespace-scope object (the tests' way).
struct MapExportFormatRegistrar {
  explicit MapExportFormatRegistrar(MapExportFormat format) { register_map_export_format(std::move(format)); }
};

/// Every format in registration order: npy, ply, csv, then any registered.
std::vector<MapExportFormat> map_export_formats();

/// The format of that name; throws InputError listing the names.
MapExportFormat map_export_format(std::string_view name);

struct MapExportRequest {
  std::string format;  ///< a registered name
  std::string path;
};

/// The files the requests would write, in the order given.
std::vector<std::string> map_export_outputs(const ElevationMap& map, std::span<const MapExportRequest> requests,
                                            std::span<const std::string> layers = {});

/// Writes each request in the order given; returns each writer's line.
/// `layers` goes to the formats that take a selection, the others get none.
/// Throws InputError for an unknown format or a writer's error.
std::vector<std::string> export_map(const ElevationMap& map, std::span<const MapExportRequest> requests,
                                    std::span<const std::string> layers = {});

}  // namespace stridemap::io
