#pragma once
// `stridemap map --log`: a recorded scan log mapped against a complete pose
// track (given whole, or read in step with the scans), as live mapping
// would have mapped it, reading the log as a stream (io::ScanLogReader): memory stays flat in the log's length, and nothing is
// allocated per scan once the first scans have sized the buffers.
#include <cstddef>
#include <functional>
#include <memory>
#include <string>
#include <utility>
#include <vector>

#include "stridemap/core/pose_track.hpp"
#include "stridemap/live/live_mapping.hpp"
#include "stridemap/live/map_report.hpp"
#include "stridemap/live/scan_mapper.hpp"
#include "stridemap/recordings/scan_log.hpp"

namespace stridemap {

class LogReplay {
 public:
  /// Opens the log and reads up to its first scan, which tells the sensor's
  /// parameters the mapper is made for. Throws InputError naming the log as
  /// io::read_scan_log does, or for `options` as ScanMapper does.
  LogReplay(const std::string& log_path, const ScanMapperOptions& options, LiveClock clock);
  /// The same from a log's bytes in memory (they must outlive the replay).
  LogReplay(io::ScanLogReader reader, const ScanMapperOptions& options, LiveClock clock);

  /// Maps one scan (read before) and reads the next; false when the log is
  /// read to its end. The poses are complete: a scan after the last is skipped.
  bool step(PoseTrack& poses);
  /// Poses read in step with the scans (io::PoseFileCursor::read_to): told
  /// each scan's time before it is mapped, it brings `poses` up to that
  /// time or to the end of the poses, so a scan after the last pose is one.
  using PosesUpTo = std::function<void(double time_s, PoseTrack& poses)>;
  void read_poses_with(PosesUpTo poses_up_to) { poses_up_to_ = std::move(poses_up_to); }
  /// Every scan left, then the end of the stream (ScanMapper::finish);
  /// `progress` is told the scans read after each one.
  void run(PoseTrack& poses, const std::function<void(std::size_t scans)>& progress = {});

  const ScanMapper& mapper() const { return *mapper_; }
  /// The global map's problems so far (ScanMapper::take_tile_notices).
  std::vector<std::string> take_tile_notices() { return mapper_->take_tile_notices(); }
  /// The log's sensor, damage and faults (no scans: they were streamed).
  const io::ScanLog& log() const { return reader_.log(); }
  std::size_t scans_read() const { return reader_.scans(); }
  const TimeRange& scan_times() const { return scan_times_; }

 private:
  io::ScanLogReader reader_;
  LiveClock clock_;
  const UrgScan* scan_ = nullptr;  // read, not yet mapped
  std::unique_ptr<ScanMapper> mapper_;
  UrgRawScan raw_;  // the scan on the mapping clock; its storage reused
  TimeRange scan_times_;
  PosesUpTo poses_up_to_;
  bool finished_ = false;
};

}  // namespace stridemap
