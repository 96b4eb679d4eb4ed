#include "stridemap/live/scan_mapper.hpp"

#include "stridemap/core/error.hpp"
#include "stridemap/core/weighted_median_fill.hpp"

namespace stridemap {

ScanMapper::ScanMapper(const ScanMapperOptions& options, const UrgParameters& sensor)
    : options_(options),
      sensor_(sensor, options.config.calibration),
      mapper_(options.config.mapper, options.config.mount),
      filters_(options.filters, options.filter_options) {
  WeightedMedianFill check(options.config.fill);  // invalid fill options fail now, not at the first save
  (void)check;
}

void ScanMapper::add(const UrgRawScan& raw, double arrival_s) {
  ++stats_.scans;
  Waiting& w = queue_.emplace_back();
  w.raw = raw;
  w.arrival_s = arrival_s;
}

std::size_t ScanMapper::process(PoseTrack& poses, bool poses_complete) {
  std::size_t integrated = 0;
  TrunkPose pose;
  while (!queue_.empty()) {
    const UrgRawScan& raw = queue_.front().raw;
    switch (poses.interpolate(raw.time_s, pose)) {
      case PoseLookup::ok:
        integrate(raw, pose);
        ++integrated;
        poses.drop_before(raw.time_s);
        break;
      case PoseLookup::before_first: ++stats_.before_first_pose; break;
      case PoseLookup::gap_too_large:
        ++stats_.pose_gap;
        poses.drop_before(raw.time_s);
        break;
      case PoseLookup::empty:
      case PoseLookup::after_last:
        if (!poses_complete) return integrated;
        ++stats_.after_last_pose;
        poses.drop_before(raw.time_s);
        break;
    }
    queue_.pop_front();
  }
  return integrated;
}

std::size_t ScanMapper::expire(double before_s) {
  std::size_t skipped = 0;
  while (!queue_.empty() && queue_.front().arrival_s <= before_s) {
    queue_.pop_front();
    ++stats_.after_last_pose;
    ++skipped;
  }
  return skipped;
}

void ScanMapper::integrate(const UrgRawScan& raw, const TrunkPose& pose) {
  UrgConversionStats converted;
  try {
    converted = sensor_.to_planar_scan(raw, scan_);
  } catch (const InputError&) {
    ++stats_.rejected;  // steps the sensor's parameters do not have: not this sensor's scan
    return;
  }
  stats_.beams.valid += converted.valid;
  stats_.beams.error_codes += converted.error_codes;
  stats_.beams.beyond_max_range += converted.beyond_max_range;
  // The chain may hand back the previous scan: it gets the previous pose.
  const TrunkPose previous = held_pose_;
  held_pose_ = pose;
  bool out = false;
  try {
    out = filters_.push(scan_, filtered_);
  } catch (const InputError&) {
    filters_.reset();  // e.g. a scan of another length after a reconnection: start the sequence anew
    ++stats_.rejected;
    return;
  }
  if (out) {
    mapper_.integrate(filtered_, filters_.delay_scans() == 0 ? pose : previous);
    ++stats_.integrated;
  }
}

void ScanMapper::finish() {
  if (filters_.flush(filtered_)) {
    mapper_.integrate(filtered_, held_pose_);
    ++stats_.integrated;
  }
}

io::MapLayers ScanMapper::filled_layers() const {
  ElevationMap copy = mapper_.map();
  WeightedMedianFill(options_.config.fill).apply(copy);
  return io::export_map_layers(copy);
}

}  // namespace stridemap
