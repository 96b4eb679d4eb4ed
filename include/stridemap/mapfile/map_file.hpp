#pragma once
// The map file (`.smap`, docs/map_file.md): the whole state of an
// ElevationMap (every layer the update rule keeps, not only what a planner
// reads) with what it takes to understand it without this library: the
// geometry, units, layer names and types, the tool's version, and the
// configuration and mount the map was made with. Versioned, checksummed
// (CRC-32), written atomically; a saved map loads back bit for bit, so that
// mapping can go on from it (core/map_resume.hpp).
#include <cstdint>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "stridemap/config/mapper_config.hpp"
#include "stridemap/core/grid_map.hpp"
#include "stridemap/core/pose.hpp"

namespace stridemap::io {

inline constexpr std::uint32_t kMapFileVersion = 1;
/// The first 8 bytes of every map file. The CR LF and ^Z catch a transfer
/// that translated line ends, as PNG's signature does.
inline constexpr std::string_view kMapFileMagic{"SMAP\r\n\x1a\n", 8};

/// "stridemap 0.1.0": the version every output that records one names
/// (map files, experiments' summary.json).
std::string tool_version();

/// What the map was made from and with. Everything is optional for a
/// reader; save_map_file fills tool_version when it is empty.
struct MapFileMetadata {
  std::string tool_version;            ///< "stridemap 0.1.0"
  std::string created_by;              ///< the command, e.g. "map --log run.log --poses poses.txt"
  /// The mapper configuration used, as text: mapper_config_json() of the
  /// effective settings, or a YAML file's text.
  std::string config_text;
  std::optional<SensorMount> mount;    ///< the sensor mount the scans were integrated with
  std::optional<double> last_scan_time_s;  ///< time of the last scan integrated
  /// Pose of the last scan integrated: resuming measures the next scan's
  /// motion (the travel term of Delta z_max) from it, as an unbroken run does.
  std::optional<TrunkPose> last_pose;
};

/// A loaded map file.
struct MapFile {
  ElevationMap map;
  MapFileMetadata metadata;
  std::uint32_t version = kMapFileVersion;
};

struct MapFileSaveOptions {
  /// Replace an existing file at the path that is not a map file. Off: such
  /// a file is refused (InputError), so a wrong path never destroys a
  /// user's data. An existing map file is always replaced.
  bool overwrite_other_files = false;
};

/// The file's bytes for `map`; what save_map_file writes.
std::string encode_map_file(const ElevationMap& map, const MapFileMetadata& metadata);
/// Parses a map file's bytes; `source` names it in messages. Throws
/// InputError "<source>: <what is wrong>" for a wrong magic or version,
/// sizes that do not fit the length, a checksum mismatch, bad metadata or a
/// cell state that does not exist. Sizes are checked before any layer is
/// allocated.
MapFile decode_map_file(std::string_view bytes, const std::string& source);

/// Writes `map` to `path` atomically: a temporary file in the same folder,
/// fsync, rename, fsync of the folder. Throws InputError naming the path.
void save_map_file(const std::string& path, const ElevationMap& map, const MapFileMetadata& metadata,
                   const MapFileSaveOptions& options = {});
/// Reads a map file (see decode_map_file); a missing or unreadable file is
/// an InputError naming it.
MapFile load_map_file(const std::string& path);

/// True when the file at `path` starts with kMapFileMagic.
bool is_map_file(const std::string& path);

/// Every setting of a mapper configuration (defaults included) as JSON
/// text, in the units of the structs (SI, radians), for MapFileMetadata.
std::string mapper_config_json(const MapperConfig& config);
/// Metadata for a map made with `config`: its text, its mount, the tool's
/// version.
MapFileMetadata map_file_metadata(const MapperConfig& config, const std::string& created_by);

/// The metadata as the JSON object the file carries (for `map-info`).
std::string map_file_header_json(std::string_view bytes, const std::string& source);

}  // namespace stridemap::io
