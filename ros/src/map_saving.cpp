#include "stridemap_ros/map_saving.hpp"

#include <filesystem>

#include "stridemap/core/error.hpp"
#include "stridemap/mapfile/map_file.hpp"
#include "stridemap_ros/message_mapper_library.hpp"

namespace stridemap::ros_adapter {

void save_map(const MessageMapper& mapper, const std::string& path, const std::string& created_by,
              std::set<std::string>& written) {
  if (path.empty()) throw InputError("map_file: no path given");
  std::error_code ec;
  const std::string key = std::filesystem::weakly_canonical(path, ec).string();
  if (std::filesystem::exists(path, ec) && !written.count(key)) {
    throw InputError(path + ": exists and was not written by this run; it is left as it is (choose another map_file)");
  }
  const TerrainMapper& m = mapper.impl().pipeline->mapper();
  io::MapFileMetadata metadata = io::map_file_metadata(mapper.impl().config, created_by);
  metadata.last_scan_time_s = m.last_scan_time_s();
  metadata.last_pose = m.last_pose();
  io::save_map_file(path, mapper.impl().pipeline->map(), metadata);
  written.insert(std::filesystem::weakly_canonical(path, ec).string());
}

}  // namespace stridemap::ros_adapter
