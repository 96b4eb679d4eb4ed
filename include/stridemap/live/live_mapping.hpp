#pragma once
// The real-time mapping loop, for any program that has a URG (or a source
// like it) and a pose stream: `stridemap live` is a thin wrapper round it,
// and a ROS node or a Python binding runs the same loop. Scans come from a
// LiveScanSource, poses from a LivePoseSource; each scan waits for the poses
// around its time (ScanMapper), the map is saved every save_every_s (by a
// MapSaver, or through a callback), and everything worth telling (faults,
// reconnections, skipped pose lines, a failed save, a pose file replaced)
// is an event, never an end of the run. Only a stop request, the duration
// or scan limit, or another sensor answering after a reconnection ends it.
#include <atomic>
#include <cstdint>
#include <functional>
#include <string>
#include <vector>

#include "stridemap/core/map_filter.hpp"
#include "stridemap/core/pose_track.hpp"
#include "stridemap/core/ring_queue.hpp"
#include "stridemap/live/map_report.hpp"
#include "stridemap/live/map_saver.hpp"
#include "stridemap/live/scan_mapper.hpp"
#include "stridemap/recordings/pose_stream.hpp"
#include "stridemap/sensors/urg_driver.hpp"

namespace stridemap {

/// Where scans come from: UrgDriverSource for a URG, or anything that
/// produces the driver's events (a test's scripted source, a ROS topic).
class LiveScanSource {
 public:
  virtual ~LiveScanSource() = default;
  /// The next event within `timeout_s`; false when none came.
  virtual bool next(UrgDriverEvent& event, double timeout_s) = 0;
  /// The connected sensor's description (PP, VV).
  virtual scip::ScipParameters parameters() const = 0;
  virtual scip::VersionInfo version() const = 0;
  virtual UrgDriverStats stats() const = 0;
  virtual void stop() = 0;
};

/// A connected UrgDriver as a scan source (the driver must outlive it).
class UrgDriverSource final : public LiveScanSource {
 public:
  explicit UrgDriverSource(UrgDriver& driver) : driver_(driver) {}
  bool next(UrgDriverEvent& event, double timeout_s) override { return driver_.next(event, timeout_s); }
  scip::ScipParameters parameters() const override { return driver_.parameters(); }
  scip::VersionInfo version() const override { return driver_.version(); }
  UrgDriverStats stats() const override { return driver_.stats(); }
  void stop() override { driver_.stop(); }

 private:
  UrgDriver& driver_;
};

/// Where poses come from.
class LivePoseSource {
 public:
  virtual ~LivePoseSource() = default;
  /// Appends the poses that arrived; returns how many. Bad records are
  /// skipped by the source and told through take_notices().
  virtual std::size_t poll(PoseTrack& track) = 0;
  virtual std::vector<std::string> take_notices() { return {}; }
  virtual std::size_t skipped_lines() const { return 0; }
  virtual std::size_t reopened() const { return 0; }
};

/// A pose file or named pipe (io::PoseStreamReader).
class PoseStreamSource final : public LivePoseSource {
 public:
  explicit PoseStreamSource(const std::string& path) : reader_(path) {}
  std::size_t poll(PoseTrack& track) override { return reader_.poll(track); }
  std::vector<std::string> take_notices() override { return reader_.take_notices(); }
  std::size_t skipped_lines() const override { return reader_.skipped_lines(); }
  std::size_t reopened() const override { return reader_.reopened(); }

 private:
  io::PoseStreamReader reader_;
};

/// Which clock a scan's time is read on; the poses must use the same.
enum class LiveClock : std::uint8_t {
  host,    ///< the driver's estimate of the host time of step 0 (Unix seconds)
  sensor,  ///< the URG's millisecond counter, unwrapped, in seconds
};

struct LiveMappingOptions {
  ScanMapperOptions mapper{};
  LiveClock clock = LiveClock::host;
  /// Poses farther apart than this are not interpolated between [s].
  double max_pose_gap_s = 1.0;
  /// The map is saved this often, and at the end [s] (> 0).
  double save_every_s = 5.0;
  /// After a failed save the next try comes this soon [s] (> 0).
  double save_retry_s = 1.0;
  /// A scan whose poses have not come this long after it arrived is skipped [s] (>= 0).
  double pose_wait_s = 0.5;
  /// A status event this often [s] (> 0).
  double status_every_s = 1.0;
  /// Stop after this long [s] / this many scans (0: no limit).
  double duration_s = 0.0;
  std::uint64_t max_scans = 0;
  /// What runs on a copy of the map before it is saved.
  MapFilter map_filter = MapFilter::fill;
  /// More poses than this with no scan among them: the clocks differ; the
  /// oldest are dropped (memory stays bounded) and it is said once.
  std::size_t max_poses_ahead = 200000;

  /// Throws InputError naming the field.
  void validate() const;
};

struct LiveEvent {
  enum class Kind : std::uint8_t {
    fault,          ///< the driver's fault (driver_event set)
    connected,      ///< the sensor (re)connected (driver_event set)
    status,         ///< the periodic status line
    pose_notice,    ///< a pose line skipped, the pose file reopened
    save_failed,    ///< a save failed; it is retried, mapping goes on
    save_recovered, ///< a save worked again after failures
    warning,        ///< e.g. the clocks of poses and scans differ
  };
  Kind kind = Kind::status;
  std::string message;
  const UrgDriverEvent* driver_event = nullptr;
};

struct LiveMappingHooks {
  /// Writes the map (e.g. write_map_outputs); `run` is null for the periodic
  /// saves and set for the last one. An InputError it throws is reported as
  /// save_failed and the save retried.
  std::function<void(const ScanMapper& mapper, const LiveRunStats* run)> save;
  std::function<void(const LiveEvent& event)> on_event;
  /// Every scan as it arrives (before mapping): e.g. a scan log.
  std::function<void(const UrgScan& scan)> on_scan;
};

struct LiveMappingResult {
  LiveRunStats run;
  /// Empty unless the run had to end early (another sensor answered); the
  /// map up to then is saved all the same.
  std::string fatal;
  /// The last save failed too (its message); the run's map is not on disk.
  std::string last_save_error;
};

class LiveMapping {
 public:
  /// The source must be connected (its parameters known). Throws InputError
  /// for invalid options.
  LiveMapping(const LiveMappingOptions& options, LiveScanSource& scans, LivePoseSource& poses,
              LiveMappingHooks hooks);
  /// As above, the map saved by `saver` (hooks.save is not called); its run
  /// information's skipped pose lines are brought up to date at each save.
  LiveMapping(const LiveMappingOptions& options, LiveScanSource& scans, LivePoseSource& poses, MapSaver& saver,
              LiveMappingHooks hooks);

  /// Runs until `stop` is set or a limit is reached, then maps what the
  /// poses complete allow and saves. The last save is tried a few times.
  LiveMappingResult run(const std::atomic<bool>& stop);

  const ScanMapper& mapper() const { return mapper_; }
  const PoseTrack& poses() const { return track_; }
  const scip::ScipParameters& sensor() const { return sensor_; }
  /// Times of the scans received and of the poses seen, on the clock.
  const TimeRange& scan_times() const { return scan_times_; }
  const TimeRange& pose_times() const { return pose_times_; }
  /// Time of a scan on the configured clock.
  double scan_time(const UrgScan& scan) const;

 private:
  void emit(LiveEvent::Kind kind, std::string message, const UrgDriverEvent* event = nullptr);
  void poll_poses();
  void tell_tile_notices();  // the global map's problems, as warnings
  bool try_save(const LiveRunStats* run);
  void account(std::size_t integrated_before);
  LiveRunStats run_stats() const;

  LiveMappingOptions options_;
  LiveScanSource& scans_;
  LivePoseSource& poses_;
  LiveMappingHooks hooks_;
  MapSaver* saver_ = nullptr;
  scip::ScipParameters sensor_;
  ScanMapper mapper_;
  PoseTrack track_;
  UrgRawScan raw_;  // the scan being queued, its storage reused

  RingQueue<double> receive_times_;  // of the scans queued in the mapper, oldest first
  // Latencies as a histogram of 1 % wide bins (1 us .. 1000 s), so that a
  // run of any length keeps fixed memory and allocates nothing per scan.
  std::vector<std::uint64_t> latency_bins_;
  std::uint64_t latency_count_ = 0;
  double latency_sum_s_ = 0.0, latency_max_s_ = 0.0;
  double start_s_ = 0.0;
  double cpu_start_s_ = 0.0;
  std::uint64_t saves_ = 0, save_failures_ = 0;
  bool save_failing_ = false;
  std::string last_save_error_;
  bool warned_clock_ = false;
  TimeRange scan_times_, pose_times_;
};

/// Wall-clock (system) and monotonic seconds, and CPU seconds of the process.
double live_host_seconds();
double live_monotonic_seconds();
double live_process_cpu_seconds();

}  // namespace stridemap
