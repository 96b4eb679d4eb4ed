#include "stridemap/live/log_replay.hpp"

#include <utility>

namespace stridemap {

LogReplay::LogReplay(const std::string& log_path, const ScanMapperOptions& options, LiveClock clock)
    : LogReplay(io::ScanLogReader(log_path), options, clock) {}

LogReplay::LogReplay(io::ScanLogReader reader, const ScanMapperOptions& options, LiveClock clock)
    : reader_(std::move(reader)), clock_(clock) {
  // A scan comes only after a complete sensor block, and a block with other
  // parameters ends the reading: the first scan's parameters are the log's.
  scan_ = reader_.next();
  mapper_ = std::make_unique<ScanMapper>(options, scip::to_urg_parameters(reader_.log().parameters));
}

bool LogReplay::step(PoseTrack& poses) {
  if (scan_ == nullptr) {
    if (!finished_) mapper_->finish();
    finished_ = true;
    return false;
  }
  raw_ = scan_->raw;
  raw_.time_s = clock_ == LiveClock::sensor ? sensor_time_seconds(scan_->sensor_time_ms) : scan_->host_time_s;
  scan_times_.add(raw_.time_s);
  if (poses_up_to_) poses_up_to_(raw_.time_s, poses);
  mapper_->add(raw_);
  mapper_->process(poses, true);
  scan_ = reader_.next();
  return true;
}

void LogReplay::run(PoseTrack& poses, const std::function<void(std::size_t scans)>& progress) {
  while (step(poses)) {
    if (progress) progress(reader_.scans());
  }
}

}  // namespace stridemap
