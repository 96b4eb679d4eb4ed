#include "stridemap/render/map_export_formats.hpp"

#include <algorithm>
#include <cstdio>
#include <filesystem>
#include <mutex>

#include "stridemap/core/error.hpp"
#include "stridemap/core/printable_text.hpp"
#include "stridemap/render/map_export.hpp"

namespace stridemap::io {
namespace {

struct Registry {
  std::mutex mutex;
  std::vector<MapExportFormat> formats;
};

// Called with the mutex held.
void add_format(Registry& registry, MapExportFormat format) {
  const std::string& name = format.name;
  if (name.empty() || name.front() == '-' ||
      std::any_of(name.begin(), name.end(), [](char c) { return c == '=' || c == ' ' || c == '\t' || c == ','; })) {
    throw InputError("map export format registration: invalid name \"" + name + "\"");
  }
  if (std::any_of(registry.formats.begin(), registry.formats.end(), [&](const auto& f) { return f.name == name; })) {
    throw InputError("map export format registration: \"" + name + "\" is already registered");
  }
  if (!format.outputs || !format.write) {
    throw InputError("map export format registration: \"" + name + "\" needs both outputs and write");
  }
  registry.formats.push_back(std::move(format));
}

std::string in_folder(const std::string& folder, const std::string& name) {
  return (std::filesystem::path(folder) / name).string();
}

Registry& registry() {
  // Never destroyed: a registrar object in another file may outlive a
  // local static.
  static Registry& instance = *[] {
    auto* registry = new Registry;
    Registry& r = *registry;
    add_format(r, {"npy", "Folder for one .npy array per layer", true, true,
                   [](const ElevationMap& map, const std::string& path, std::span<const std::string> layers) {
                     std::vector<std::string> paths;
                     for (const std::string& name : npy_file_names(map, layers)) paths.push_back(in_folder(path, name));
                     return paths;
                   },
                   [](const ElevationMap& map, const std::string& path, std::span<const std::string> layers) {
                     export_npy(map, path, layers);
                     return "NumPy arrays in " + printable_text(path);
                   }});
    add_format(r, {"ply", "PLY mesh file, coloured by elevation", false, false,
                   [](const ElevationMap&, const std::string& path, std::span<const std::string>) {
                     return std::vector<std::string>{path};
                   },
                   [](const ElevationMap& map, const std::string& path, std::span<const std::string>) {
                     const PlyStats stats = export_ply(map, path);
                     return "PLY mesh " + printable_text(path) + ": " + std::to_string(stats.vertices) +
                            " vertices, " + std::to_string(stats.triangles) + " triangles";
                   }});
    add_format(r, {"csv", "Folder for cells.csv, one line per cell", true, true,
                   [](const ElevationMap&, const std::string& path, std::span<const std::string>) {
                     return std::vector<std::string>{in_folder(path, "cells.csv")};
                   },
                   [](const ElevationMap& map, const std::string& path, std::span<const std::string> layers) {
                     return printable_text(export_cells_csv(map, path, layers));
                   }});
    return registry;
  }();
  return instance;
}

std::span<const std::string> layers_for(const MapExportFormat& format, std::span<const std::string> layers) {
  return format.takes_layers ? layers : std::span<const std::string>{};
}

}  // namespace

void register_map_export_format(MapExportFormat format) {
  Registry& r = registry();
  const std::lock_guard lock(r.mutex);
  add_format(r, std::move(format));
}

std::vector<MapExportFormat> map_export_formats() {
  Registry& r = registry();
  const std::lock_guard lock(r.mutex);
  return r.formats;
}

MapExportFormat map_export_format(std::string_view name) {
  const std::vector<MapExportFormat> formats = map_export_formats();
  std::string names;
  for (const MapExportFormat& format : formats) {
    if (format.name == name) return format;
    names += (names.empty() ? "" : ", ") + format.name;
  }
  throw InputError("unknown map export format \"" + std::string(name) + "\"; formats: " + names);
}

std::vector<std::string> map_export_outputs(const ElevationMap& map, std::span<const MapExportRequest> requests,
                                            std::span<const std::string> layers) {
  std::vector<std::string> paths;
  for (const MapExportRequest& request : requests) {
    const MapExportFormat format = map_export_format(request.format);
    for (std::string& path : format.outputs(map, request.path, layers_for(format, layers))) {
      paths.push_back(std::move(path));
    }
  }
  return paths;
}

std::vector<std::string> export_map(const ElevationMap& map, std::span<const MapExportRequest> requests,
                                    std::span<const std::string> layers) {
  std::vector<MapExportFormat> formats;
  for (const MapExportRequest& request : requests) formats.push_back(map_export_format(request.format));
  std::vector<std::string> lines;
  for (std::size_t i = 0; i < requests.size(); ++i) {
    lines.push_back(formats[i].write(map, requests[i].path, layers_for(formats[i], layers)));
  }
  return lines;
}

}  // namespace stridemap::io
