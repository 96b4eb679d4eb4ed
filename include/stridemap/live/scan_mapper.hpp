#pragma once
// Mapping from a stream of raw URG scans and a stream of timestamped poses,
// as `stridemap live` does on-line and `stridemap map` does from a log: the
// same class and the same decisions, so both give the same map from the
// same data. A thin layer over MappingPipeline (pipeline/) configured from
// the mapper's YAML settings. A scan waits until the poses around its time have arrived;
// it is then converted with the sensor's own parameters (PP), filtered
// (optional), and integrated at the interpolated pose. A scan that can
// never get a pose (before the first pose, in a gap, after the last pose
// once the poses are complete) is skipped and counted.
#include <cstddef>
#include <cstdint>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "stridemap/config/mapper_config.hpp"
#include "stridemap/core/pose_track.hpp"
#include "stridemap/core/terrain_mapper.hpp"
#include "stridemap/mapfile/map_file.hpp"
#include "stridemap/mapfile/map_outputs.hpp"
#include "stridemap/mapfile/tile_store.hpp"
#include "stridemap/pipeline/mapping_pipeline.hpp"
#include "stridemap/preprocess/scan_filter_chain.hpp"
#include "stridemap/sensors/urg04lx.hpp"

namespace stridemap {

struct ScanMapperOptions {
  MapperConfig config{};
  /// Scan filters between the sensor model and the mapper (none by default;
  /// with scan-sequence the map lags one scan until finish()).
  std::vector<ScanFilterKind> filters{};
  ScanFilterChainOptions filter_options{};
  /// Go on mapping from this saved map (mapfile/map_file.hpp) instead of an
  /// empty one. Its settings must be `config`'s (mapfile/map_resume_check.hpp),
  /// else the constructor throws InputError naming `resume_source` and every
  /// difference. A scan-sequence filter starts afresh: it has no previous
  /// scan to compare the first one with.
  std::shared_ptr<const io::MapFile> resume{};
  std::string resume_source{};
  /// A window that stays where it is put (`--window`, live/map_window.hpp)
  /// instead of following the robot: its corner cell. config.mapper must
  /// have follow_robot off and the window's size. Not with `resume`: a
  /// saved map keeps its own window.
  std::optional<CellIndex> window_corner{};
};

/// scans (offered with add()), integrated (reached the mapper),
/// before_first_pose / after_last_pose / pose_gap (skipped for want of a
/// pose), rejected (steps or length do not fit the sensor's parameters),
/// beams (the URG's raw values).
using ScanMapperStats = PipelineStats;

class ScanMapper {
 public:
  /// `sensor` from the sensor's PP reply (UrgDriver::urg_parameters, or a
  /// log's parameters). Throws InputError for invalid options.
  ScanMapper(const ScanMapperOptions& options, const UrgParameters& sensor);

  /// Queues a scan; raw.time_s must be on the poses' clock. `arrival_s` is
  /// when it arrived (any clock; only expire() compares it).
  void add(const UrgRawScan& raw, double arrival_s = 0.0);
  /// Integrates the waiting scans, oldest first, while their pose is known;
  /// with `poses_complete` a scan after the last pose is skipped instead of
  /// waiting. Returns the scans integrated. Drops poses no longer needed.
  /// With a global map, saves the window into its tiles every
  /// global_map.save_interval_s of scan time.
  std::size_t process(PoseTrack& poses, bool poses_complete);
  /// Skips the waiting scans that arrived at or before `before_s` (live
  /// mapping: the poses for them are overdue). Returns how many.
  std::size_t expire(double before_s);
  /// Ends the stream: the scan held by scan-sequence is integrated, and
  /// with a global map (config.global_map) every tile is written.
  void finish();
  /// The global map the window's cells go to; nullptr without one.
  const io::TileStore* tile_store() const { return tiles_.get(); }
  /// The global map's problems since the last call (a tile write failing
  /// or working again, a damaged tile set aside), one line each; empty
  /// without a global map.
  std::vector<std::string> take_tile_notices();

  std::size_t waiting() const { return pipeline_.waiting(); }
  /// Room for `scans` scans waiting for their poses at once (no allocation then).
  void reserve(std::size_t scans);
  const ScanMapperStats& stats() const { return stats_; }
  /// The mapper's counts; the map itself is read with map().
  const TerrainMapper& mapper() const { return pipeline_.mapper(); }
  /// The map being built, its foothold layers current (MappingPipeline::map()).
  const ElevationMap& map() const { return pipeline_.map(); }
  const ScanMapperOptions& options() const { return options_; }
  /// The map with the fill-in (eq. 11) applied to a copy: the map being
  /// built is not changed, so saving it often changes nothing.
  ExportedMap filled_layers() const;
  /// The pipeline's options this mapper builds (also the fit pass's, live/map_window.hpp).
  static PipelineOptions pipeline_options(const ScanMapperOptions& options, const UrgParameters& sensor);

 private:

  ScanMapperOptions options_;
  MappingPipeline pipeline_;
  ScanMapperStats stats_;  // the pipeline's, as of the last call
  std::unique_ptr<io::TileStore> tiles_;  // on the heap: the mapper points at it
  std::optional<double> last_tile_save_s_;  // scan time of the last save (global_map.save_interval_s)
  std::optional<double> last_tile_retry_s_;  // scan time of the last try after a failed tile write
  void save_tiles_when_due();
};

}  // namespace stridemap
