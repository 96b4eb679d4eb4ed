#include "stridemap/io/map_export.hpp"

#include <algorithm>
#include <bit>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <system_error>

#include "atomic_output_file.hpp"
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

struct NpyLayer {
  const char* name;
  const char* descr;
};

constexpr NpyLayer kNpyLayers[] = {
    {"elevation", "<f4"},      {"certainty", "<f4"},         {"state", "|u1"},         {"mean_elevation", "<f4"},
    {"mean_count", "<u2"},     {"pending_elevation", "<f4"}, {"contradictions", "|u1"},
};

std::string npy_layer_bytes(const ElevationMap& map, const std::string& name) {
  if (name == "elevation") return layer_bytes(map, map.elevation_data());
  if (name == "certainty") return layer_bytes(map, map.certainty_data());
  if (name == "state") return layer_bytes(map, map.state_data());
  if (name == "mean_elevation") return layer_bytes(map, map.mean_elevation_data());
  if (name == "mean_count") return layer_bytes(map, map.mean_count_data());
  if (name == "pending_elevation") return layer_bytes(map, map.pending_elevation_data());
  return layer_bytes(map, map.contradiction_data());
}

bool known(const ElevationMap& map, std::size_t slot) {
  return map.state_data()[slot] != static_cast<std::uint8_t>(CellState::unknown) &&
         std::isfinite(map.elevation_data()[slot]);
}

void append_float(std::string& out, float value) { append_le(out, std::bit_cast<std::uint32_t>(value), 4); }

// Shortest text that reads back to the same float.
void append_number(std::string& out, float value) {
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

std::vector<std::string> npy_file_names() {
  std::vector<std::string> names;
  for (const NpyLayer& layer : kNpyLayers) names.push_back(std::string(layer.name) + ".npy");
  return names;
}

std::vector<std::string> export_npy(const ElevationMap& map, const std::string& directory) {
  const std::filesystem::path dir = prepare_folder(directory);
  const auto n = static_cast<std::size_t>(map.cells_per_side());
  std::vector<std::string> written;
  for (const NpyLayer& layer : kNpyLayers) {
    const std::string path = (dir / (std::string(layer.name) + ".npy")).string();
    write_file(path, encode_npy(layer.descr, n, n, npy_layer_bytes(map, layer.name)), "NumPy array");
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

std::string export_cells_csv(const ElevationMap& map, const std::string& directory) {
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
  out += "\nix,iy,x_m,y_m,elevation_m,certainty,state,mean_elevation_m,mean_count\n";
  for (int i = 0; i < n; ++i) {
    for (int j = 0; j < n; ++j) {
      const CellIndex cell = map.cell_at_local(i, j);
      const std::size_t s = map.slot(cell);
      const Eigen::Vector2d centre = map.cell_center(cell);
      char prefix[96];
      std::snprintf(prefix, sizeof prefix, "%lld,%lld,%.12g,%.12g,", static_cast<long long>(cell.x),
                    static_cast<long long>(cell.y), centre.x(), centre.y());
      out += prefix;
      append_number(out, map.elevation_data()[s]);
      out.push_back(',');
      append_number(out, map.certainty_data()[s]);
      out.push_back(',');
      out += std::to_string(map.state_data()[s]);
      out.push_back(',');
      append_number(out, map.mean_elevation_data()[s]);
      out.push_back(',');
      out += std::to_string(map.mean_count_data()[s]);
      out.push_back('\n');
    }
  }
  const std::string path = (dir / "cells.csv").string();
  write_file(path, out, "cell CSV");
  return path;
}

}  // namespace stridemap::io
