#pragma once
// Saving the map as a .smap file (docs/map_file.md) from the node or the
// bag command: the mapper's whole state (not the filled copy), with the
// configuration, mount, last pose and time, so `stridemap map --resume`
// and the export commands read it. C++17 (see message_mapper.hpp).
#include <set>
#include <string>

#include "stridemap_ros/message_mapper.hpp"

namespace stridemap::ros_adapter {

/// Writes the map to `path` atomically. A file at `path` that this process
/// did not write before (`written`) is never replaced: InputError naming it.
/// On success `path` joins `written`.
void save_map(const MessageMapper& mapper, const std::string& path, const std::string& created_by,
              std::set<std::string>& written);

}  // namespace stridemap::ros_adapter
