#pragma once
// Outputs of the rocky-walk experiment: the maps of the whole walk (the
// mosaic: elevation, certainty, error, truth, a 3D view) and of the final
// local map as PNG, the mosaic's layers as CSV, summary.json (shape in
// docs/experiments.md) and the printed table.
#include <string>

#include "stridemap/experiments/rocky_walk.hpp"

namespace stridemap {

struct RockyWalkRunInfo {
  std::string scene_path;
  std::string path_source;  ///< the path file, or "<scene>:walk_path"
};

std::string rocky_walk_summary_json(const RockyWalkResult& result, const RockyWalkOptions& options,
                                    const RockyWalkRunInfo& info);
std::string rocky_walk_table(const RockyWalkResult& result);

/// Writes everything into `directory` (created if missing); InputError
/// naming the file when something cannot be written.
void write_rocky_walk_outputs(const RockyWalkResult& result, const RockyWalkOptions& options,
                              const RockyWalkRunInfo& info, const std::string& directory);

}  // namespace stridemap
