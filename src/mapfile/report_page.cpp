#include "stridemap/mapfile/report_page.hpp"

#include <algorithm>
#include <bit>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <system_error>

#include <nlohmann/json.hpp>
#include <zlib.h>

#include "report_page_parts.hpp"
#include "stridemap/core/error.hpp"
#include "stridemap/core/exported_map.hpp"
#include "stridemap/io/text_file.hpp"
#include "stridemap/mapfile/grid_csv.hpp"
#include "stridemap/mapfile/map_file.hpp"

namespace stridemap::io {
namespace {

namespace fs = std::filesystem;
using nlohmann::json;

std::string read_asset_file(const fs::path& path, const std::string& what) {
  refuse_folder(path.string(), what);
  std::ifstream in(path, std::ios::binary);
  if (!in) throw InputError(path.string() + ": cannot read " + what);
  std::ostringstream text;
  text << in.rdbuf();
  return text.str();
}

// IEEE half precision, round to nearest even; NaN stays NaN and values
// beyond 65504 become infinite (no layer but a count gets near that).
std::uint16_t to_half(float value) {
  const auto bits = std::bit_cast<std::uint32_t>(value);
  const std::uint32_t sign = (bits >> 16) & 0x8000u;
  const std::uint32_t magnitude = bits & 0x7fffffffu;
  if (magnitude >= 0x7f800000u) return static_cast<std::uint16_t>(sign | 0x7c00u | (magnitude > 0x7f800000u ? 0x200u : 0u));
  if (magnitude >= 0x477ff000u) return static_cast<std::uint16_t>(sign | 0x7c00u);
  if (magnitude < 0x38800000u) {  // subnormal half (or zero)
    const float scaled = std::abs(value) * 16777216.0f;  // 2^24: units of the smallest half
    return static_cast<std::uint16_t>(sign | static_cast<std::uint32_t>(std::nearbyint(scaled)));
  }
  const std::uint32_t rounded = magnitude + 0xfffu + ((magnitude >> 13) & 1u);
  return static_cast<std::uint16_t>(sign | ((rounded - 0x38000000u) >> 13));
}

template <typename T>
std::string bytes_of(const T* values, std::size_t count) {
  static_assert(std::endian::native == std::endian::little, "the page reads little-endian arrays");
  return std::string(reinterpret_cast<const char*>(values), count * sizeof(T));
}

// zlib's format, which the page unpacks with the browser's own
// DecompressionStream('deflate'): unknown cells (NaN runs) and smooth
// layers shrink to a fraction, so that the page stays small and quick to
// parse; the bytes are exactly those given.
std::string deflated(const std::string& bytes) {
  uLongf size = compressBound(static_cast<uLong>(bytes.size()));
  std::string out(size, '\0');
  if (compress2(reinterpret_cast<Bytef*>(out.data()), &size, reinterpret_cast<const Bytef*>(bytes.data()),
                static_cast<uLong>(bytes.size()), 6) != Z_OK) {
    throw InputError("report page: compressing a map layer failed (out of memory?)");
  }
  out.resize(size);
  return out;
}

// One layer's cells as the page reads them: base64 of the zlib stream.
json packed_layer(const std::string& name, const std::string& units, const std::string& encoding,
                  const std::string& bytes) {
  return {{"name", name}, {"units", units}, {"encoding", encoding}, {"compression", "deflate"},
          {"data", detail::base64(deflated(bytes))}};
}

// Row-major copy (the page indexes [i * cols + j]); Eigen stores columns first.
template <typename Matrix>
std::vector<typename Matrix::Scalar> row_major(const Matrix& m) {
  std::vector<typename Matrix::Scalar> out(static_cast<std::size_t>(m.size()));
  std::size_t k = 0;
  for (Eigen::Index i = 0; i < m.rows(); ++i)
    for (Eigen::Index j = 0; j < m.cols(); ++j) out[k++] = m(i, j);
  return out;
}

json f32_layer(const std::string& name, const std::string& units, const Eigen::MatrixXf& values, bool exact) {
  const std::vector<float> cells = row_major(values);
  if (exact) return packed_layer(name, units, "f32", bytes_of(cells.data(), cells.size()));
  std::vector<std::uint16_t> halves(cells.size());
  std::transform(cells.begin(), cells.end(), halves.begin(), to_half);
  return packed_layer(name, units, "f16", bytes_of(halves.data(), halves.size()));
}

// A layer that holds one value everywhere (the gated rule's bookkeeping
// under the paper's rule) would only cost bytes.
bool constant(const ExportedLayer& layer) {
  const auto all_same = [](const auto& m) {
    if (m.size() == 0) return true;
    const auto first = m(0, 0);
    for (Eigen::Index k = 0; k < m.size(); ++k) {
      const auto v = m.data()[k];
      if (!(v == first || (v != v && first != first))) return false;
    }
    return true;
  };
  switch (layer.spec.type) {
    case LayerType::f32: return all_same(layer.f32);
    case LayerType::u16: return all_same(layer.u16);
    case LayerType::u8: return all_same(layer.u8);
  }
  return true;
}

json pose_summary_json(const TrunkPose& p) { return {{"x_m", p.x_m}, {"y_m", p.y_m}, {"yaw_rad", p.yaw_rad}}; }

json map_json(const std::string& name, const MapFile& file) {
  std::vector<std::string> names;
  for (std::size_t k = 0; k < file.map.layer_count(); ++k) names.push_back(file.map.layer_spec(k).name);
  const ExportedMap exported = export_map(file.map, names);
  const double s = exported.cell_size_m;
  const Eigen::Vector2d origin = exported.cell_center(0, 0);
  json out = {{"name", name},
              {"rows", exported.cells_per_side},
              {"cols", exported.cells_per_side},
              {"cell_size_m", s},
              {"origin_x_m", origin.x()},
              {"origin_y_m", origin.y()},
              {"created_by", file.metadata.created_by},
              {"layers", json::array()}};
  for (const ExportedLayer& layer : exported.layers) {
    if (layer.spec.name != "elevation" && constant(layer)) continue;
    switch (layer.spec.type) {
      case LayerType::f32:
        // float16 for every float layer: 0.05 % of the value (0.5 mm at 1 m),
        // far below a cell or the sensor's noise, and it keeps a 500 x 500
        // page with its truth under 5 MB; exact values are in the map file.
        out["layers"].push_back(f32_layer(layer.spec.name, layer.spec.unit, layer.f32, false));
        break;
      case LayerType::u16: {
        const auto cells = row_major(layer.u16);
        out["layers"].push_back(packed_layer(layer.spec.name, layer.spec.unit, "u16", bytes_of(cells.data(), cells.size())));
        break;
      }
      case LayerType::u8: {
        const auto cells = row_major(layer.u8);
        out["layers"].push_back(packed_layer(layer.spec.name, layer.spec.unit, "u8", bytes_of(cells.data(), cells.size())));
        break;
      }
    }
  }
  if (file.metadata.last_pose) out["last_pose"] = pose_summary_json(*file.metadata.last_pose);
  if (file.metadata.mount) {
    const SensorMount& m = *file.metadata.mount;
    out["mount"] = {{"height_m", m.height_m},
                    {"pitch_rad", m.pitch_rad},
                    {"yaw_rad", m.yaw_rad},
                    {"forward_offset_m", m.forward_offset_m},
                    {"lateral_offset_m", m.lateral_offset_m}};
  }
  return out;
}

// truth.csv beside the map, when it covers the same cells.
void add_truth(const fs::path& dir, json& map, std::vector<std::string>& warnings) {
  const fs::path path = dir / "truth.csv";
  std::error_code ec;
  if (!fs::is_regular_file(path, ec)) return;
  try {
    GridCsvOptions meta;
    const Eigen::MatrixXf truth = read_grid_csv(path.string(), &meta);
    const bool same_shape = truth.rows() == map["rows"].get<int>() && truth.cols() == map["cols"].get<int>();
    const bool same_cells = meta.cell_size_m && std::abs(*meta.cell_size_m - map["cell_size_m"].get<double>()) < 1e-9;
    if (!same_shape || !same_cells) {
      warnings.push_back(path.string() + ": covers other cells than map.smap (" + std::to_string(truth.rows()) + " x " +
                         std::to_string(truth.cols()) + "); no truth or error layer shown");
      return;
    }
    // Once only: the page makes the truth's own map from it.
    map["truth"] = f32_layer("truth", "m", truth, false);
  } catch (const InputError& e) {
    warnings.push_back(e.what());
  }
}

void add_path(const fs::path& dir, json& map, std::vector<std::string>& warnings) {
  const fs::path path = dir / "path.csv";
  std::error_code ec;
  if (!fs::is_regular_file(path, ec)) return;
  try {
    const Eigen::MatrixXf points = read_grid_csv(path.string());
    if (points.cols() != 2) throw InputError(path.string() + ": expected 2 columns (x_m, y_m), found " + std::to_string(points.cols()));
    json track = json::array();
    for (Eigen::Index i = 0; i < points.rows(); ++i) track.push_back({points(i, 0), points(i, 1)});
    map["path"] = std::move(track);
  } catch (const InputError& e) {
    warnings.push_back(e.what());
  }
}

MapFile load_compare(const std::string& path_text) {
  fs::path path(path_text);
  std::error_code ec;
  if (fs::is_directory(path, ec)) path /= "map.smap";
  return load_map_file(path.string());
}

}  // namespace

ReportPage build_report_page(const std::string& directory, const ReportPageOptions& options) {
  const fs::path dir(directory);
  std::error_code ec;
  if (!fs::is_directory(dir, ec)) throw InputError(directory + ": no such folder (give a run's output folder)");
  if (options.assets_dir.empty()) throw InputError("report: no folder of web assets given");
  const fs::path assets(options.assets_dir);
  detail::ReportParts parts;
  for (const char* name : {kReportThreeFile, kReportOrbitFile, kReportScriptFile, kReportStyleFile}) {
    if (!fs::is_regular_file(assets / name, ec)) {
      throw InputError((assets / name).string() +
                       ": missing: the report page's web assets come with the build (npm ci in web/, "
                       "docs/outputs.md); rebuild or reinstall stridemap");
    }
  }
  parts.three_js = read_asset_file(assets / kReportThreeFile, "three.js");
  parts.orbit_js = read_asset_file(assets / kReportOrbitFile, "OrbitControls");
  parts.script_js = read_asset_file(assets / kReportScriptFile, "the page's script");
  parts.style_css = read_asset_file(assets / kReportStyleFile, "the page's style");

  ReportPage page;
  json data = {{"maps", json::array()}, {"messages", json::array()}};
  std::vector<fs::path> pictures;
  bool has_summary = false, has_map = false;
  for (const fs::directory_entry& entry : fs::directory_iterator(dir, ec)) {
    if (entry.is_regular_file(ec) && entry.path().extension() == ".png") pictures.push_back(entry.path());
  }
  std::sort(pictures.begin(), pictures.end());
  for (const fs::path& picture : pictures) {
    parts.pictures.push_back({picture.filename().string(), read_asset_file(picture, "picture")});
  }
  const fs::path summary_path = dir / "summary.json";
  if (fs::is_regular_file(summary_path, ec)) {
    has_summary = true;
    try {
      parts.summary = json::parse(read_asset_file(summary_path, "summary"));
    } catch (const json::exception& e) {
      page.warnings.push_back(summary_path.string() + ": not JSON: " + e.what());
    }
  }
  const fs::path table_path = dir / "table.txt";
  if (fs::is_regular_file(table_path, ec)) parts.printed_table = read_asset_file(table_path, "printed table");
  // Only the rocky walk writes path.csv, and it draws that track on its
  // elevation, truth and error pictures; no other run's picture has a path.
  parts.path_drawn = fs::is_regular_file(dir / "path.csv", ec);
  const fs::path map_path = dir / "map.smap";
  if (fs::exists(map_path, ec)) {
    has_map = true;
    try {
      json map = map_json("map", load_map_file(map_path.string()));
      add_truth(dir, map, page.warnings);
      add_path(dir, map, page.warnings);
      data["maps"].push_back(std::move(map));
    } catch (const InputError& e) {
      page.warnings.push_back(e.what());
    }
  } else {
    page.warnings.push_back(map_path.string() + ": no map file in this folder, so there is no 3D view");
  }
  if (!options.compare_path.empty()) {
    // Asked for by name: a bad file here is the user's error, not a note.
    data["maps"].push_back(map_json(options.compare_path, load_compare(options.compare_path)));
  }
  if (!has_map && !has_summary && pictures.empty() && parts.printed_table.empty()) {
    throw InputError(directory + ": holds no map.smap, summary.json, table.txt or PNG picture: not a stridemap output folder");
  }
  for (const std::string& warning : page.warnings) data["messages"].push_back(warning);
  parts.title = options.title.empty() ? "stridemap report: " + fs::absolute(dir).lexically_normal().filename().string()
                                      : options.title;
  if (parts.title == "stridemap report: ") parts.title += directory;
  parts.data = std::move(data);
  page.html = detail::assemble_report_html(parts);
  return page;
}

ReportPage write_report_page(const std::string& directory, const std::string& path, const ReportPageOptions& options) {
  std::error_code ec;
  if (fs::exists(path, ec)) {
    refuse_folder(path, "the report page");
    std::ifstream in(path, std::ios::binary);
    std::string start(std::strlen(kReportPageMarker), '\0');
    in.read(start.data(), static_cast<std::streamsize>(start.size()));
    if (!in || start != kReportPageMarker) {
      throw InputError(path + ": exists and is not a stridemap report page; it is left as it is (give another --out)");
    }
  }
  ReportPage page = build_report_page(directory, options);
  write_text_file(path, page.html, "report page");
  return page;
}

}  // namespace stridemap::io
