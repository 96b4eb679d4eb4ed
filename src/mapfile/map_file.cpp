#include "stridemap/mapfile/map_file.hpp"

#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>
#include <zlib.h>

#include <algorithm>
#include <array>
#include <bit>
#include <cerrno>
#include <cmath>
#include <cstring>
#include <fstream>
#include <iterator>
#include <limits>
#include <optional>
#include <span>
#include <system_error>

#include <nlohmann/json.hpp>

#include "stridemap/core/error.hpp"
#include "stridemap/core/map_integrity.hpp"
#include "stridemap/io/detail/atomic_output_file.hpp"
#include "stridemap/mapfile/detail/settings_json.hpp"

#ifndef STRIDEMAP_VERSION_STRING
#define STRIDEMAP_VERSION_STRING "unknown"
#endif

namespace stridemap::io {
namespace {

using nlohmann::json;

constexpr std::size_t kFixedHeaderBytes = 16;  // magic, version, metadata length
constexpr std::size_t kChecksumBytes = 4;
// Layers start on an 8-byte boundary so that a reader can map them as
// arrays in place (numpy.frombuffer, mmap).
constexpr std::size_t kLayerAlignment = 8;
constexpr std::int64_t kLargestCorner = std::numeric_limits<std::int64_t>::max() / 4;

// NumPy's names for the layer types, as the file states them.
const char* scalar_name(LayerType type) {
  return type == LayerType::f32 ? "<f4" : type == LayerType::u16 ? "<u2" : "|u1";
}

std::optional<LayerType> scalar_type(const std::string& name) {
  if (name == "<f4") return LayerType::f32;
  if (name == "<u2") return LayerType::u16;
  if (name == "|u1") return LayerType::u8;
  return std::nullopt;
}

// The map's layers in file order: widest first, so that every layer stays
// aligned to its element size; the registry's order among equals (for the
// built-in layers that is the order files have always had).
std::vector<std::size_t> file_order(const ElevationMap& map) {
  std::vector<std::size_t> order(map.layer_count());
  for (std::size_t k = 0; k < order.size(); ++k) order[k] = k;
  std::stable_sort(order.begin(), order.end(), [&](std::size_t a, std::size_t b) {
    return layer_type_bytes(map.layer_spec(a).type) > layer_type_bytes(map.layer_spec(b).type);
  });
  return order;
}

void put_le(std::string& out, std::uint64_t value, std::size_t bytes) {
  for (std::size_t k = 0; k < bytes; ++k) out.push_back(static_cast<char>((value >> (8 * k)) & 0xFF));
}

std::uint64_t get_le(const unsigned char* p, std::size_t bytes) {
  std::uint64_t value = 0;
  for (std::size_t k = 0; k < bytes; ++k) value |= static_cast<std::uint64_t>(p[k]) << (8 * k);
  return value;
}

// The element at `slot` as its little-endian bit pattern (floats by bits, so
// NaN payloads survive).
std::uint64_t element_bits(const void* data, LayerType type, std::size_t slot) {
  switch (type) {
    case LayerType::f32: return std::bit_cast<std::uint32_t>(static_cast<const float*>(data)[slot]);
    case LayerType::u16: return static_cast<const std::uint16_t*>(data)[slot];
    case LayerType::u8: break;
  }
  return static_cast<const std::uint8_t*>(data)[slot];
}

void set_element(void* data, LayerType type, std::size_t slot, std::uint64_t bits) {
  switch (type) {
    case LayerType::f32:
      static_cast<float*>(data)[slot] = std::bit_cast<float>(static_cast<std::uint32_t>(bits));
      return;
    case LayerType::u16: static_cast<std::uint16_t*>(data)[slot] = static_cast<std::uint16_t>(bits); return;
    case LayerType::u8: static_cast<std::uint8_t*>(data)[slot] = static_cast<std::uint8_t>(bits); return;
  }
}

std::uint32_t crc32_of(std::string_view bytes) {
  uLong crc = crc32(0L, Z_NULL, 0);
  // zlib takes lengths as uInt: feed large maps in pieces.
  while (!bytes.empty()) {
    const std::size_t piece = std::min<std::size_t>(bytes.size(), 1u << 30);
    crc = crc32(crc, reinterpret_cast<const Bytef*>(bytes.data()), static_cast<uInt>(piece));
    bytes.remove_prefix(piece);
  }
  return static_cast<std::uint32_t>(crc);
}

json pose_json(const TrunkPose& p) {
  json pose = {{"x_m", p.x_m},         {"y_m", p.y_m},         {"yaw_rad", p.yaw_rad},
               {"pitch_rad", p.pitch_rad}, {"roll_rad", p.roll_rad}, {"reference_elevation_m", p.reference_elevation_m},
               {"height_change_m", p.height_change_m}};
  pose["z_m"] = p.z_m ? json(*p.z_m) : json(nullptr);
  return pose;
}

[[noreturn]] void bad(const std::string& source, const std::string& what) {
  throw InputError(source + ": " + what);
}

std::string hex32(std::uint32_t v) {
  char text[16];
  std::snprintf(text, sizeof text, "0x%08x", v);
  return text;
}

// The fixed header and the metadata text, checked against the file length.
struct Frame {
  std::uint32_t version = 0;
  std::string_view metadata;
  std::size_t data_start = 0;
  std::size_t data_end = 0;  // where the checksum starts
};

Frame read_frame(std::string_view bytes, const std::string& source) {
  if (bytes.size() < kMapFileMagic.size() || bytes.substr(0, kMapFileMagic.size()) != kMapFileMagic) {
    bad(source, "not a stridemap map file (it does not start with the map file signature)");
  }
  if (bytes.size() < kFixedHeaderBytes + kChecksumBytes) {
    bad(source, "truncated map file: " + std::to_string(bytes.size()) + " bytes, shorter than the " +
                    std::to_string(kFixedHeaderBytes + kChecksumBytes) + "-byte header and checksum");
  }
  const auto* p = reinterpret_cast<const unsigned char*>(bytes.data());
  Frame frame;
  frame.data_end = bytes.size() - kChecksumBytes;
  // The checksum first: damage anywhere, the version field included, is
  // reported as damage rather than as whatever the damaged bytes now say.
  const auto stored = static_cast<std::uint32_t>(get_le(p + frame.data_end, 4));
  const std::uint32_t computed = crc32_of(bytes.substr(0, frame.data_end));
  if (stored != computed) {
    bad(source, "checksum mismatch (stored " + hex32(stored) + ", computed " + hex32(computed) +
                    "): the file is damaged or truncated");
  }
  frame.version = static_cast<std::uint32_t>(get_le(p + 8, 4));
  if (frame.version == 0 || frame.version > kMapFileVersion) {
    bad(source, "map file version " + std::to_string(frame.version) + " is not one this tool reads (1.." +
                    std::to_string(kMapFileVersion) + "); a newer stridemap wrote it?");
  }
  const std::uint64_t metadata_bytes = get_le(p + 12, 4);
  if (metadata_bytes > frame.data_end - kFixedHeaderBytes) {
    bad(source, "the header claims " + std::to_string(metadata_bytes) + " bytes of metadata but the file holds " +
                    std::to_string(frame.data_end - kFixedHeaderBytes));
  }
  frame.metadata = bytes.substr(kFixedHeaderBytes, static_cast<std::size_t>(metadata_bytes));
  frame.data_start = kFixedHeaderBytes + static_cast<std::size_t>(metadata_bytes);
  return frame;
}

// Far deeper than any metadata this tool writes (about 5 levels). Without
// a bound, 200,000 nested brackets took 19 s and 2 GB before bad_alloc.
constexpr int kMaxMetadataDepth = 64;

json parse_metadata(std::string_view text, const std::string& source) {
  const json::parser_callback_t bounded = [&source](int depth, json::parse_event_t, json&) {
    if (depth > kMaxMetadataDepth) {
      bad(source, "metadata: JSON nested deeper than " + std::to_string(kMaxMetadataDepth) + " levels");
    }
    return true;
  };
  try {
    json header = json::parse(text, bounded);
    if (!header.is_object()) bad(source, "metadata: not a JSON object");
    return header;
  } catch (const json::exception& e) {
    bad(source, std::string("metadata: not valid JSON (") + e.what() + ")");
  }
}

template <typename T>
T field(const json& object, const char* key, const std::string& source, const std::string& where) {
  const auto it = object.find(key);
  if (it == object.end()) bad(source, "metadata: " + where + key + " is missing");
  try {
    return it->get<T>();
  } catch (const json::exception&) {
    bad(source, "metadata: " + where + key + " has the wrong type (" + it->dump() + ")");
  }
}

// A whole number from the metadata. Read through nlohmann's own integer
// types only: converting a float such as 1e30 to an integer would be
// undefined behaviour.
std::int64_t integer_value(const json& value, const std::string& source, const std::string& name) {
  if (value.is_number_unsigned()) {
    const auto v = value.get<std::uint64_t>();
    if (v > static_cast<std::uint64_t>(std::numeric_limits<std::int64_t>::max())) {
      bad(source, "metadata: " + name + " is too large");
    }
    return static_cast<std::int64_t>(v);
  }
  if (value.is_number_integer()) return value.get<std::int64_t>();
  bad(source, "metadata: " + name + " must be a whole number (" + value.dump() + ")");
}

std::int64_t integer_field(const json& object, const char* key, const std::string& source, const std::string& where) {
  const auto it = object.find(key);
  if (it == object.end()) bad(source, "metadata: " + where + key + " is missing");
  return integer_value(*it, source, where + key);
}

GridOptions read_geometry(const json& header, const std::string& source, CellIndex& corner) {
  const auto it = header.find("geometry");
  if (it == header.end() || !it->is_object()) bad(source, "metadata: geometry is missing");
  const json& g = *it;
  GridOptions grid;
  const std::int64_t cells_per_side = integer_field(g, "cells_per_side", source, "geometry.");
  if (cells_per_side < 1 || cells_per_side > 20000) {
    bad(source, "metadata: geometry.cells_per_side " + std::to_string(cells_per_side) + " is outside 1..20000");
  }
  grid.cells_per_side = static_cast<int>(cells_per_side);
  grid.cell_size_m = field<double>(g, "cell_size_m", source, "geometry.");
  const auto corner_it = g.find("min_cell");
  if (corner_it == g.end() || !corner_it->is_array() || corner_it->size() != 2) {
    bad(source, "metadata: geometry.min_cell must hold two integers");
  }
  std::int64_t corner_values[2];
  for (std::size_t k = 0; k < 2; ++k) {
    corner_values[k] = integer_value((*corner_it)[k], source, "geometry.min_cell");
    if (corner_values[k] > kLargestCorner || corner_values[k] < -kLargestCorner) {
      bad(source, "metadata: geometry.min_cell " + std::to_string(corner_values[k]) + " is out of range");
    }
  }
  corner = {corner_values[0], corner_values[1]};
  if (!std::isfinite(grid.cell_size_m) || grid.cell_size_m <= 0.0) {
    bad(source, "metadata: geometry.cell_size_m must be a positive number");
  }
  return grid;
}

// One layer the file holds: its declaration and where its bytes are.
struct FileLayer {
  LayerSpec spec;
  std::size_t offset = 0;
};

// A layer this library does not declare itself (a user's): its declaration
// as the file states it. Older files carry no reset value: then NaN for
// floats, 0 for counts.
LayerSpec declared_in_file(const json& layer, const std::string& name, LayerType type, const std::string& source,
                           const std::string& where) {
  LayerSpec spec;
  spec.name = name;
  spec.type = type;
  spec.reset_value = type == LayerType::f32 ? std::numeric_limits<double>::quiet_NaN() : 0.0;
  if (const auto it = layer.find("reset_value"); it != layer.end() && !it->is_null()) {
    if (!it->is_number()) bad(source, where + "reset_value must be a number or null");
    spec.reset_value = it->get<double>();
  }
  const auto text = [&](const char* key) {
    const auto it = layer.find(key);
    if (it == layer.end() || it->is_null()) return std::string();
    if (!it->is_string()) bad(source, where + key + " must be a string");
    return it->get<std::string>();
  };
  spec.unit = text("units");
  spec.description = text("meaning");
  if (const auto it = layer.find("exported"); it != layer.end() && !it->is_null()) {
    if (!it->is_boolean()) bad(source, where + "exported must be true or false");
    spec.exported = it->get<bool>();
  }
  try {
    validate_layer_spec(spec);
  } catch (const InputError& e) {
    bad(source, e.what());
  }
  return spec;
}

// The layers the file holds, checked against the data region and each
// other before anything is allocated. The built-in layers must all be
// there with their own types; any other layer is a user's and comes along.
std::vector<FileLayer> read_layers(const json& header, const Frame& frame, std::uint64_t cells,
                                   const std::string& source) {
  const auto it = header.find("layers");
  if (it == header.end() || !it->is_array()) bad(source, "metadata: layers is missing");
  const std::span<const LayerSpec> builtin = builtin_layers();
  std::vector<FileLayer> found;
  std::vector<std::pair<std::uint64_t, std::uint64_t>> extents;
  for (const json& layer : *it) {
    if (!layer.is_object()) bad(source, "metadata: a layers entry is not an object");
    const auto name = field<std::string>(layer, "name", source, "layers[].");
    const std::string where = "layer '" + name + "': ";
    const auto type_text = field<std::string>(layer, "type", source, where);
    const std::int64_t signed_offset = integer_field(layer, "offset", source, where);
    const std::int64_t signed_size = integer_field(layer, "bytes", source, where);
    if (signed_offset < 0 || signed_size < 0) bad(source, where + "a negative offset or size");
    const auto offset = static_cast<std::uint64_t>(signed_offset);
    const auto size = static_cast<std::uint64_t>(signed_size);
    if (offset < frame.data_start || offset > frame.data_end || size > frame.data_end - offset) {
      bad(source, where + "bytes " + std::to_string(offset) + ".." + std::to_string(offset + size) +
                      " lie outside the layer data (" + std::to_string(frame.data_start) + ".." +
                      std::to_string(frame.data_end) + "): truncated or inconsistent file");
    }
    extents.emplace_back(offset, size);
    for (const FileLayer& earlier : found) {
      if (earlier.spec.name == name) bad(source, where + "appears twice");
    }
    const auto known = std::find_if(builtin.begin(), builtin.end(), [&](const LayerSpec& l) { return l.name == name; });
    const std::optional<LayerType> type = scalar_type(type_text);
    if (known != builtin.end() && type != known->type) {
      bad(source, where + "type " + type_text + ", expected " + scalar_name(known->type));
    }
    if (!type) bad(source, where + "type " + type_text + " is not one of <f4, <u2, |u1");
    if (size != cells * layer_type_bytes(*type)) {
      bad(source, where + std::to_string(size) + " bytes, but " + std::to_string(cells) + " cells of " + type_text +
                      " need " + std::to_string(cells * layer_type_bytes(*type)));
    }
    found.push_back({known != builtin.end() ? *known : declared_in_file(layer, name, *type, source, where),
                     static_cast<std::size_t>(offset)});
  }
  for (const LayerSpec& spec : builtin) {
    if (std::none_of(found.begin(), found.end(), [&](const FileLayer& l) { return l.spec.name == spec.name; })) {
      bad(source, "metadata: layer '" + spec.name + "' is missing");
    }
  }
  std::sort(extents.begin(), extents.end());
  for (std::size_t k = 1; k < extents.size(); ++k) {
    if (extents[k].first < extents[k - 1].first + extents[k - 1].second) bad(source, "metadata: layers overlap");
  }
  return found;
}

MapFileMetadata read_metadata(const json& header, const std::string& source) {
  MapFileMetadata m;
  const auto text = [&](const char* key) {
    const auto it = header.find(key);
    if (it == header.end() || it->is_null()) return std::string();
    if (!it->is_string()) bad(source, std::string("metadata: ") + key + " must be a string");
    return it->get<std::string>();
  };
  m.tool_version = text("tool_version");
  m.created_by = text("created_by");
  m.config_text = text("config");
  if (const auto it = header.find("mount"); it != header.end() && !it->is_null()) {
    if (!it->is_object()) bad(source, "metadata: mount must be an object");
    SensorMount mount;
    mount.height_m = field<double>(*it, "height_m", source, "mount.");
    mount.pitch_rad = field<double>(*it, "pitch_rad", source, "mount.");
    mount.forward_offset_m = field<double>(*it, "forward_offset_m", source, "mount.");
    mount.lateral_offset_m = field<double>(*it, "lateral_offset_m", source, "mount.");
    m.mount = mount;
  }
  if (const auto it = header.find("last_scan_time_s"); it != header.end() && !it->is_null()) {
    m.last_scan_time_s = field<double>(header, "last_scan_time_s", source, "");
  }
  if (const auto it = header.find("last_pose"); it != header.end() && !it->is_null()) {
    if (!it->is_object()) bad(source, "metadata: last_pose must be an object");
    TrunkPose pose;
    pose.x_m = field<double>(*it, "x_m", source, "last_pose.");
    pose.y_m = field<double>(*it, "y_m", source, "last_pose.");
    pose.yaw_rad = field<double>(*it, "yaw_rad", source, "last_pose.");
    pose.pitch_rad = field<double>(*it, "pitch_rad", source, "last_pose.");
    pose.roll_rad = field<double>(*it, "roll_rad", source, "last_pose.");
    pose.reference_elevation_m = field<double>(*it, "reference_elevation_m", source, "last_pose.");
    pose.height_change_m = field<double>(*it, "height_change_m", source, "last_pose.");
    if (const auto z = it->find("z_m"); z != it->end() && !z->is_null()) pose.z_m = field<double>(*it, "z_m", source, "last_pose.");
    m.last_pose = pose;
  }
  return m;
}

std::string read_whole_file(const std::string& path) {
  struct stat info {};
  if (::stat(path.c_str(), &info) != 0) {
    throw InputError(path + ": cannot open the map file: " + std::generic_category().message(errno));
  }
  if (S_ISDIR(info.st_mode)) throw InputError(path + ": is a folder, not a map file");
  std::ifstream in(path, std::ios::binary);
  if (!in) throw InputError(path + ": cannot open the map file: " + std::generic_category().message(errno));
  std::string bytes{std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
  if (in.bad()) throw InputError(path + ": read error");
  return bytes;
}

void sync_folder_of(const std::string& path) {
  const auto slash = path.find_last_of('/');
  const std::string folder = slash == std::string::npos ? "." : slash == 0 ? "/" : path.substr(0, slash);
  const int fd = ::open(folder.c_str(), O_RDONLY | O_DIRECTORY | O_CLOEXEC);
  if (fd < 0) return;  // the rename is done; a folder we cannot open cannot be synced either
  ::fsync(fd);
  ::close(fd);
}

}  // namespace

std::string tool_version() { return "stridemap " STRIDEMAP_VERSION_STRING; }

std::string encode_map_file(const ElevationMap& map, const MapFileMetadata& metadata) {
  const int n = map.cells_per_side();
  const std::size_t cells = static_cast<std::size_t>(n) * static_cast<std::size_t>(n);
  const std::vector<std::size_t> order = file_order(map);
  json header = {
      {"format", "stridemap map"},
      {"version", kMapFileVersion},
      {"tool_version", metadata.tool_version.empty() ? tool_version() : metadata.tool_version},
      {"created_by", metadata.created_by},
      {"geometry",
       {{"cells_per_side", n},
        {"cell_size_m", map.cell_size_m()},
        {"min_cell", {map.min_cell().x, map.min_cell().y}},
        {"map_frame", "X forward at the start, Y left, Z up; yaw counter-clockwise from +X"},
        {"cell_index", "cell (ix, iy) covers [ix, ix+1) x [iy, iy+1) times cell_size_m"},
        {"layout", "row-major N x N: element [i][j] is cell (min_cell[0] + i, min_cell[1] + j)"}}},
      {"units", {{"length", "m"}, {"angle", "rad"}, {"time", "s"}}},
      {"config", metadata.config_text},
      {"mount", metadata.mount ? detail::mount_json(*metadata.mount) : json(nullptr)},
      {"last_scan_time_s", metadata.last_scan_time_s ? json(*metadata.last_scan_time_s) : json(nullptr)},
      {"last_pose", metadata.last_pose ? pose_json(*metadata.last_pose) : json(nullptr)},
  };
  // Offsets depend on the metadata's length, which depends on the offsets'
  // digits: lay out with placeholders of the final width, then fill in.
  std::size_t metadata_bytes = 0;
  std::string metadata_text;
  for (int pass = 0; pass < 3; ++pass) {
    json layers = json::array();
    std::size_t offset = kFixedHeaderBytes + metadata_bytes;
    for (const std::size_t k : order) {
      const LayerSpec& spec = map.layer_spec(k);
      const std::size_t size = cells * layer_type_bytes(spec.type);
      json entry = {{"name", spec.name},
                    {"type", scalar_name(spec.type)},
                    {"units", spec.unit},
                    {"meaning", spec.description},
                    {"offset", offset},
                    {"bytes", size}};
      // A user's layer carries its whole declaration, so that a reader
      // without that user's code restores it as declared. (NaN is null.)
      if (k >= builtin_layers().size()) {
        entry["reset_value"] = std::isnan(spec.reset_value) ? json(nullptr) : json(spec.reset_value);
        entry["exported"] = spec.exported;
      }
      layers.push_back(std::move(entry));
      offset += size;
    }
    header["layers"] = layers;
    metadata_text = header.dump(1, ' ', false, json::error_handler_t::replace);
    metadata_text.push_back('\n');
    while ((kFixedHeaderBytes + metadata_text.size()) % kLayerAlignment != 0) metadata_text.push_back(' ');
    if (metadata_text.size() == metadata_bytes) break;
    metadata_bytes = metadata_text.size();
  }

  std::string out;
  std::size_t cell_bytes = 0;
  for (const std::size_t k : order) cell_bytes += layer_type_bytes(map.layer_spec(k).type);
  out.reserve(kFixedHeaderBytes + metadata_text.size() + cells * cell_bytes + kChecksumBytes);
  out.append(kMapFileMagic);
  put_le(out, kMapFileVersion, 4);
  put_le(out, metadata_text.size(), 4);
  out += metadata_text;
  for (const std::size_t k : order) {
    const void* data = map.layer_bytes(k);
    const LayerType type = map.layer_spec(k).type;
    const std::size_t width = layer_type_bytes(type);
    for (int i = 0; i < n; ++i) {
      for (int j = 0; j < n; ++j) put_le(out, element_bits(data, type, map.slot(map.cell_at_local(i, j))), width);
    }
  }
  put_le(out, crc32_of(out), 4);
  return out;
}

MapFile decode_map_file(std::string_view bytes, const std::string& source) {
  const Frame frame = read_frame(bytes, source);
  const json header = parse_metadata(frame.metadata, source);
  CellIndex corner;
  const GridOptions grid = read_geometry(header, source, corner);
  const auto n = static_cast<std::uint64_t>(grid.cells_per_side);
  const std::vector<FileLayer> layers = read_layers(header, frame, n * n, source);
  MapFileMetadata metadata = read_metadata(header, source);

  // The map's own checks (a grid too large for its cell size, a layer it
  // cannot declare, a corner out of range) know nothing of the file.
  const auto within_file = [&](auto&& step) {
    try {
      return step();
    } catch (const InputError& e) {
      bad(source, e.what());
    }
  };
  MapFile file{within_file([&] { return ElevationMap(grid); }), std::move(metadata), frame.version};
  ElevationMap& map = file.map;
  within_file([&] {
    for (const FileLayer& layer : layers) {
      if (!map.find_layer(layer.spec.name)) map.add_layer(layer.spec);
    }
    map.move_corner_to(corner);
  });
  const auto* p = reinterpret_cast<const unsigned char*>(bytes.data());
  for (const FileLayer& layer : layers) {
    const std::size_t k = *map.find_layer(layer.spec.name);
    void* data = map.layer_bytes(k);
    const std::size_t width = layer_type_bytes(layer.spec.type);
    const unsigned char* in = p + layer.offset;
    for (int i = 0; i < grid.cells_per_side; ++i) {
      for (int j = 0; j < grid.cells_per_side; ++j, in += width) {
        set_element(data, layer.spec.type, map.slot(map.cell_at_local(i, j)), get_le(in, width));
      }
    }
  }
  const std::uint8_t* state = map.state_data();
  for (std::size_t s = 0; s < n * n; ++s) {
    if (state[s] > static_cast<std::uint8_t>(CellState::filled)) {
      bad(source, "layer 'state': a cell has state " + std::to_string(state[s]) +
                      "; only 0 (unknown), 1 (measured) and 2 (filled) exist");
    }
  }
  // A checksum proves the bytes are the ones written, not that what was
  // written is a map: an infinite elevation or a NaN certainty carried into
  // a resumed run would poison every cell the fill or a foothold fit
  // touches. The file does not record the run's certainty ceiling, so only
  // a finite one is required here.
  const MapIntegrity integrity = check_map_integrity(map, std::numeric_limits<float>::max());
  if (!integrity.ok()) {
    bad(source, integrity.first_problem + " (" + std::to_string(integrity.invalid) + " invalid cell" +
                    (integrity.invalid == 1 ? "" : "s") + " in all; a measured cell needs a finite elevation and "
                    "a finite certainty > 0, a filled one a finite elevation and certainty 0, an unknown one "
                    "no elevation and certainty 0)");
  }
  return file;
}

std::string map_file_header_json(std::string_view bytes, const std::string& source) {
  const Frame frame = read_frame(bytes, source);
  json header = parse_metadata(frame.metadata, source);
  header["version"] = frame.version;
  return header.dump(2, ' ', false, json::error_handler_t::replace) + "\n";
}

bool is_map_file(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  char head[8] = {};
  in.read(head, sizeof head);
  return in.gcount() == static_cast<std::streamsize>(sizeof head) &&
         std::string_view(head, sizeof head) == kMapFileMagic;
}

void save_map_file(const std::string& path, const ElevationMap& map, const MapFileMetadata& metadata,
                   const MapFileSaveOptions& options) {
  struct stat existing {};
  if (!options.overwrite_other_files && ::stat(path.c_str(), &existing) == 0 && S_ISREG(existing.st_mode) &&
      !is_map_file(path)) {
    throw InputError("cannot write map file '" + path +
                     "': a file that is not a map file is already there; remove it or choose another name");
  }
  const std::string bytes = encode_map_file(map, metadata);
  detail::AtomicOutputFile file(path, "map file");
  file.write(bytes.data(), bytes.size());
  // Durable before it is visible: after a power cut the name holds either
  // the old map or the whole new one.
  if (std::fflush(file.stream()) != 0 || ::fsync(::fileno(file.stream())) != 0) {
    if (errno != EINVAL && errno != EROFS) {  // a pipe or device cannot be synced, nor needs to be
      file.fail("cannot flush it to disk (" + std::generic_category().message(errno) + ")");
    }
  }
  file.commit();
  sync_folder_of(path);
}

std::string mapper_config_json(const MapperConfig& config) { return detail::mapper_settings_json(config).dump(1); }

MapFileMetadata map_file_metadata(const MapperConfig& config, const std::string& created_by) {
  MapFileMetadata metadata;
  metadata.created_by = created_by;
  metadata.config_text = mapper_config_json(config);
  metadata.mount = config.mount;
  return metadata;
}

MapFile load_map_file(const std::string& path) { return decode_map_file(read_whole_file(path), path); }

}  // namespace stridemap::io
