#include "stridemap/live/scan_mapper.hpp"

#include <algorithm>
#include <utility>

#include "stridemap/core/map_resume.hpp"
#include "stridemap/mapfile/map_resume_check.hpp"

namespace stridemap {

PipelineOptions ScanMapper::pipeline_options(const ScanMapperOptions& options, const UrgParameters& sensor) {
  PipelineOptions p;
  p.sensor = SensorKind::urg;
  p.urg = sensor;
  p.calibration = options.config.calibration;
  p.filters = options.filters;
  p.filter_options = options.filter_options;
  p.mapper = options.config.mapper;
  p.map_filter = {MapFilter::fill, options.config.fill, {}};
  p.mount = options.config.mount;
  p.foothold = options.config.foothold;
  p.visibility = options.config.visibility;
  p.height_fusion = options.config.height_fusion;
  return p;
}

ScanMapper::ScanMapper(const ScanMapperOptions& options, const UrgParameters& sensor)
    : options_(options), pipeline_(pipeline_options(options, sensor)) {
  if (options_.resume && options_.window_corner) {
    throw InputError("a resumed map keeps the window of its map file; give no window with it");
  }
  if (options_.resume) {
    io::check_map_resumable(*options_.resume, options_.config, options_.resume_source);
    const io::MapFileMetadata& saved = options_.resume->metadata;
    resume_from_map(pipeline_.mapper(), options_.resume->map, saved.last_pose, saved.last_scan_time_s);
    pipeline_.recompute_foothold();
    options_.resume.reset();  // the mapper has its copy
  }
  if (options_.window_corner) {
    pipeline_.mapper().map().move_corner_to(*options_.window_corner);
  }
  if (!options_.config.global_map.folder.empty()) {
    // Made last: it takes the layers of the map as resumed, foothold layers included.
    tiles_ = std::make_unique<io::TileStore>(options_.config.global_map, pipeline_.mapper().map(),
                                             io::map_file_metadata(options_.config, "global map"));
    pipeline_.set_window_listener(tiles_.get());
  }
}

void ScanMapper::add(const UrgRawScan& raw, double arrival_s) {
  pipeline_.queue(raw, arrival_s);
  stats_ = pipeline_.stats();
}

void ScanMapper::reserve(std::size_t scans) {
  const UrgParameters& urg = pipeline_.options().urg;
  pipeline_.reserve_queue(scans, static_cast<std::size_t>(std::max(0, urg.beam_count())));
}

std::size_t ScanMapper::process(PoseTrack& poses, bool poses_complete) {
  const std::size_t integrated = pipeline_.process(poses, poses_complete);
  stats_ = pipeline_.stats();
  if (integrated > 0) save_tiles_when_due();
  return integrated;
}

// A failed tile write is tried again after this much scan time, as live's
// failed saves are (LiveMappingOptions::save_retry_s).
constexpr double kTileRetryS = 1.0;

void ScanMapper::save_tiles_when_due() {
  const double interval_s = options_.config.global_map.save_interval_s;
  const std::optional<double> now_s = pipeline_.mapper().last_scan_time_s();
  if (!tiles_ || !now_s) return;
  if (tiles_->failing()) {
    if (!last_tile_retry_s_ || *now_s - *last_tile_retry_s_ >= kTileRetryS || *now_s < *last_tile_retry_s_) {
      tiles_->flush(pipeline_.map());
      last_tile_retry_s_ = *now_s;
    }
    return;
  }
  last_tile_retry_s_.reset();
  if (interval_s <= 0.0) return;
  if (!last_tile_save_s_) {
    last_tile_save_s_ = *now_s;
  } else if (*now_s - *last_tile_save_s_ >= interval_s) {
    // Rare (once a save_interval_s of scans): writing files allocates.
    tiles_->flush(pipeline_.map());  // a read: the clean-up keeps its maxima
    last_tile_save_s_ = *now_s;
  }
}

std::size_t ScanMapper::expire(double before_s) {
  const std::size_t skipped = pipeline_.expire(before_s);
  stats_ = pipeline_.stats();
  return skipped;
}

void ScanMapper::finish() {
  pipeline_.finish();
  if (tiles_) tiles_->flush(pipeline_.map());
  stats_ = pipeline_.stats();
}

std::vector<std::string> ScanMapper::take_tile_notices() {
  return tiles_ ? tiles_->take_notices() : std::vector<std::string>{};
}

ExportedMap ScanMapper::filled_layers() const { return export_map(pipeline_.filtered_map()); }

}  // namespace stridemap
