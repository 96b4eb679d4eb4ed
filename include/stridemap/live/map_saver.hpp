#pragma once
// Saving a run's map: its run information and output folder kept together,
// so that every save of a run (live's periodic ones, the last, map's one)
// writes the same set the same way (write_map_outputs).
#include <string>
#include <utility>

#include "stridemap/live/map_report.hpp"
#include "stridemap/live/map_run_info.hpp"

namespace stridemap {

class MapSaver {
 public:
  MapSaver(MapRunInfo info, std::string directory) : info_(std::move(info)), directory_(std::move(directory)) {}

  /// What the run finds out as it goes (skipped lines) is added here.
  MapRunInfo& info() { return info_; }
  const MapRunInfo& info() const { return info_; }
  const std::string& directory() const { return directory_; }

  /// write_map_outputs into the folder; `run` only for live mapping's last
  /// save. Throws InputError naming the folder.
  ExportedMap save(const ScanMapper& mapper, const scip::ScipParameters& sensor,
                   const LiveRunStats* run = nullptr) const {
    return write_map_outputs(mapper, sensor, info_, run, directory_);
  }

 private:
  MapRunInfo info_;
  std::string directory_;
};

}  // namespace stridemap
