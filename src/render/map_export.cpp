#include "stridemap/render/map_export.hpp"

#include <algorithm>
#include <bit>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <system_error>

#include "stridemap/io/detail/atomic_output_file.hpp"
#include "colour_palette.hpp"
#include "stridemap/core/error.hpp"

namespace stridemap::io {
namespace {

std::filesystem::path prepare_folder(const std::string& directory) {
  const std::filesystem::path dir(directory);
  std::error_code ec;
  std::filesystem::create_directories(dir, ec);
  if (ec) throw InputError(dir.string() + ": cannot create the output folder: " + ec.message());
  return dir;
}

void write_file(const std::string& path, const std::string& bytes, const char* kind) {
  detail::AtomicOutputFile file(path, kind);
  file.write(bytes.data(), bytes.size());
  file.commit();
}

void append_le(std::string& out, std::uint32_t value, int bytes) {
  for (int k = 0; k < bytes; ++k) out.push_back(static_cast<char>((value >> (8 * k)) & 0xFF));
}

template <typename T>
std::uint32_t bits_of(T value) {
  if constexpr (std::is_same_v<T, float>) {
    return std::bit_cast<std::uint32_t>(value);
  } else {
    return static_cast<std::uint32_t>(value);
  }
}

// A layer in window order as little-endian bytes.
template <typename T>
std::string layer_bytes(const ElevationMap& map, const T* data) {
  const int n = map.cells_per_side();
  std::string out;
  out.reserve(static_cast<std::size_t>(n) * static_cast<std::size_t>(n) * sizeof(T));
  for (int i = 0; i < n; ++i) {
    for (int j = 0; j < n; ++j) append_le(out, bits_of(data[map.slot(map.cell_at_local(i, j))]), sizeof(T));
  }
  return out;
}

const char* npy_descr(LayerType type) {
  return type == LayerType::f32 ? "<f4" : type == LayerType::u16 ? "<u2" : "|u1";
}

std::string npy_layer_bytes(const ElevationMap& map, std::size_t index) {
  switch (map.layer_spec(index).type) {
    case LayerType::f32: return layer_bytes(map, map.data(LayerId<float>{index}));
    case LayerType::u16: return layer_bytes(map, map.data(LayerId<std::uint16_t>{index}));
    case LayerType::u8: break;
  }
  return layer_bytes(map, map.data(LayerId<std::uint8_t>{index}));
}

// The cell CSV's columns when none are asked for: the planner's layers and
// the running mean, then every layer a user added.
std::vector<std::size_t> default_csv_layers(const ElevationMap& map) {
  std::vector<std::size_t> selected;
  for (const char* name : {"elevation", "certainty", "state", "mean_elevation", "mean_count"}) {
    selected.push_back(*map.find_layer(name));
  }
  for (std::size_t k = builtin_layers().size(); k < map.layer_count(); ++k) selected.push_back(k);
  return selected;
}

bool known(const ElevationMap& map, std::size_t slot) {
  return map.state_data()[slot] != static_cast<std::uint8_t>(CellState::unknown) &&
         std::isfinite(map.elevation_data()[slot]);
}

void append_float(std::string& out, float value) { append_le(out, std::bit_cast<std::uint32_t>(value), 4); }

// Shortest text that reads back to the same float.
void append_export_number(std::string& out, float value) {
  if (std::isnan(value)) {
    out += "nan";
    return;
  }
  char text[32];
  std::snprintf(text, sizeof text, "%.9g", static_cast<double>(value));
  out += text;
}

}  // namespace

std::string encode_npy(const std::string& descr, std::size_t rows, std::size_t cols, const std::string& data) {
  std::string header = "{'descr': '" + descr + "', 'fortran_order': False, 'shape': (" + std::to_string(rows) +
                       ", " + std::to_string(cols) + "), }";
  // Magic (6) + version (2) + length (2) + header, a multiple of 64 bytes,
  // the header closed by a newline: what NumPy writes and expects.
  const std::size_t total = (10 + header.size() + 1 + 63) / 64 * 64;
  header.append(total - 10 - header.size() - 1, ' ');
  header.push_back('\n');
  std::string out("\x93NUMPY\x01\x00", 8);
  append_le(out, static_cast<std::uint32_t>(header.size()), 2);
  out += header;
  out += data;
  return out;
}

std::vector<std::size_t> select_layers(const ElevationMap& map, std::span<const std::string> layer_names) {
  std::vector<std::size_t> selected;
  if (layer_names.empty()) {
    for (std::size_t k = 0; k < map.layer_count(); ++k) selected.push_back(k);
    return selected;
  }
  for (const std::string& name : layer_names) {
    const auto index = map.find_layer(name);
    if (!index) throw InputError("no map layer '" + name + "'; the map has " + map.layer_names());
    if (std::find(selected.begin(), selected.end(), *index) != selected.end()) {
      throw InputError("map layer '" + name + "' is selected twice");
    }
    selected.push_back(*index);
  }
  return selected;
}

std::vector<std::string> npy_file_names(const ElevationMap& map, std::span<const std::string> layer_names) {
  std::vector<std::string> names;
  for (const std::size_t k : select_layers(map, layer_names)) names.push_back(map.layer_spec(k).name + ".npy");
  return names;
}

std::vector<std::string> export_npy(const ElevationMap& map, const std::string& directory,
                                    std::span<const std::string> layer_names) {
  const std::vector<std::size_t> selected = select_layers(map, layer_names);
  const std::filesystem::path dir = prepare_folder(directory);
  const auto n = static_cast<std::size_t>(map.cells_per_side());
  std::vector<std::string> written;
  for (const std::size_t k : selected) {
    const std::string path = (dir / (map.layer_spec(k).name + ".npy")).string();
    write_file(path, encode_npy(npy_descr(map.layer_spec(k).type), n, n, npy_layer_bytes(map, k)), "NumPy array");
    written.push_back(path);
  }
  return written;
}

PlyStats export_ply(const ElevationMap& map, const std::string& path, const PlyOptions& options) {
  const int n = map.cells_per_side();
  const std::size_t cells = static_cast<std::size_t>(n) * static_cast<std::size_t>(n);
  // Vertex number of each local cell (i n + j), or -1 for a hole.
  std::vector<std::int32_t> vertex(cells, -1);
  float low = INFINITY, high = -INFINITY;
  std::int32_t vertices = 0;
  for (int i = 0; i < n; ++i) {
    for (int j = 0; j < n; ++j) {
      const std::size_t s = map.slot(map.cell_at_local(i, j));
      if (!known(map, s)) continue;
      vertex[static_cast<std::size_t>(i) * static_cast<std::size_t>(n) + static_cast<std::size_t>(j)] = vertices++;
      low = std::min(low, map.elevation_data()[s]);
      high = std::max(high, map.elevation_data()[s]);
    }
  }
  const double lo = options.elevation_min_m.value_or(vertices > 0 ? low : 0.0);
  const double hi = options.elevation_max_m.value_or(vertices > 0 ? high : 1.0);
  const auto palette = detail::colour_scale_bgr(options.colours);

  std::string body;
  for (int i = 0; i < n; ++i) {
    for (int j = 0; j < n; ++j) {
      const CellIndex cell = map.cell_at_local(i, j);
      const std::size_t s = map.slot(cell);
      if (!known(map, s)) continue;
      const Eigen::Vector2d centre = map.cell_center(cell);
      const float z = map.elevation_data()[s];
      append_float(body, static_cast<float>(centre.x()));
      append_float(body, static_cast<float>(centre.y()));
      append_float(body, z);
      const double t = hi > lo ? std::clamp((static_cast<double>(z) - lo) / (hi - lo), 0.0, 1.0) : 0.5;
      const cv::Vec3b bgr = palette[static_cast<std::size_t>(std::lround(t * 255.0))];
      body.push_back(static_cast<char>(bgr[2]));
      body.push_back(static_cast<char>(bgr[1]));
      body.push_back(static_cast<char>(bgr[0]));
    }
  }
  PlyStats stats;
  stats.vertices = static_cast<std::size_t>(vertices);
  const auto at = [&](int i, int j) {
    return vertex[static_cast<std::size_t>(i) * static_cast<std::size_t>(n) + static_cast<std::size_t>(j)];
  };
  const auto triangle = [&](std::int32_t a, std::int32_t b, std::int32_t c) {
    body.push_back(3);
    append_le(body, static_cast<std::uint32_t>(a), 4);
    append_le(body, static_cast<std::uint32_t>(b), 4);
    append_le(body, static_cast<std::uint32_t>(c), 4);
    ++stats.triangles;
  };
  for (int i = 0; i + 1 < n; ++i) {
    for (int j = 0; j + 1 < n; ++j) {
      // Counter-clockwise seen from above (+X then +Y), so normals face up.
      const std::int32_t corner[4] = {at(i, j), at(i + 1, j), at(i + 1, j + 1), at(i, j + 1)};
      const int present = static_cast<int>(std::count_if(corner, corner + 4, [](std::int32_t v) { return v >= 0; }));
      if (present == 4) {
        triangle(corner[0], corner[1], corner[2]);
        triangle(corner[0], corner[2], corner[3]);
      } else if (present == 3) {
        std::int32_t kept[3];
        int k = 0;
        for (const std::int32_t v : corner) {
          if (v >= 0) kept[k++] = v;
        }
        triangle(kept[0], kept[1], kept[2]);
      }
    }
  }
  std::string header =
      "ply\nformat binary_little_endian 1.0\n"
      "comment stridemap elevation map: map frame, x forward, y left, z up, metres\n"
      "comment one vertex per known cell centre; unknown cells are holes\n"
      "element vertex " + std::to_string(stats.vertices) +
      "\nproperty float x\nproperty float y\nproperty float z\n"
      "property uchar red\nproperty uchar green\nproperty uchar blue\n"
      "element face " + std::to_string(stats.triangles) +
      "\nproperty list uchar int vertex_indices\nend_header\n";
  write_file(path, header + body, "PLY mesh");
  return stats;
}

std::string export_cells_csv(const ElevationMap& map, const std::string& directory,
                             std::span<const std::string> layer_names) {
  const std::vector<std::size_t> selected =
      layer_names.empty() ? default_csv_layers(map) : select_layers(map, layer_names);
  const std::filesystem::path dir = prepare_folder(directory);
  const int n = map.cells_per_side();
  char geometry[160];
  std::snprintf(geometry, sizeof geometry, "cell_size_m=%.17g; cells_per_side=%d; min_cell=%lld,%lld",
                map.cell_size_m(), n, static_cast<long long>(map.min_cell().x),
                static_cast<long long>(map.min_cell().y));
  std::string out = "# stridemap map cells; rows ordered by ix ascending, then iy ascending; ix, iy: global cell "
                    "index, x_m, y_m: cell centre in the map frame (x forward, y left) [m]; elevations [m]; "
                    "state 0 unknown, 1 measured, 2 filled; nan: none; ";
  out += geometry;
  out += "\nix,iy,x_m,y_m";
  // A column is its layer's name with the unit appended: elevation_m.
  for (const std::size_t k : selected) {
    const LayerSpec& spec = map.layer_spec(k);
    // Not twice when the name already ends in it (slope_deg, not slope_deg_deg).
    const std::string suffix = spec.unit.empty() ? "" : "_" + spec.unit;
    const bool named = !suffix.empty() && spec.name.size() >= suffix.size() &&
                       spec.name.compare(spec.name.size() - suffix.size(), suffix.size(), suffix) == 0;
    out += "," + spec.name + (named ? "" : suffix);
  }
  out.push_back('\n');
  for (int i = 0; i < n; ++i) {
    for (int j = 0; j < n; ++j) {
      const CellIndex cell = map.cell_at_local(i, j);
      const std::size_t s = map.slot(cell);
      const Eigen::Vector2d centre = map.cell_center(cell);
      char prefix[96];
      std::snprintf(prefix, sizeof prefix, "%lld,%lld,%.12g,%.12g,", static_cast<long long>(cell.x),
                    static_cast<long long>(cell.y), centre.x(), centre.y());
      out += prefix;
      for (std::size_t c = 0; c < selected.size(); ++c) {
        if (c > 0) out.push_back(',');
        const std::size_t k = selected[c];
        switch (map.layer_spec(k).type) {
          case LayerType::f32: append_export_number(out, map.data(LayerId<float>{k})[s]); break;
          case LayerType::u16: out += std::to_string(map.data(LayerId<std::uint16_t>{k})[s]); break;
          case LayerType::u8: out += std::to_string(map.data(LayerId<std::uint8_t>{k})[s]); break;
        }
      }
      out.push_back('\n');
    }
  }
  const std::string path = (dir / "cells.csv").string();
  write_file(path, out, "cell CSV");
  return path;
}

}  // namespace stridemap::io
