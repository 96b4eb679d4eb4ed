#pragma once
// Driver for a Hokuyo URG-04LX over any ByteStream: starts the sensor
// (stops a stream left running, switches SCIP 1.1 units to SCIP 2.0, leaves
// time-adjust mode, reads VV and PP, turns the laser on, starts MD), then
// delivers scans with host timestamps and reports every fault: undecodable
// bytes, scans missing from the sensor's timestamps, stalls, sensor resets,
// a lost link. It recovers by itself: a stalled stream is restarted, a lost
// device reopened when it comes back. Single-threaded and poll-driven:
// next() returns within its timeout whatever the device does. docs/driver.md.
#include <cstdint>
#include <functional>
#include <memory>
#include <string>
#include <vector>

#include "stridemap/core/ring_queue.hpp"
#include "stridemap/sensors/byte_stream.hpp"
#include "stridemap/sensors/scan_clock.hpp"
#include "stridemap/sensors/scip_decoder.hpp"
#include "stridemap/sensors/scip_parameters.hpp"
#include "stridemap/sensors/scip_scan.hpp"
#include "stridemap/sensors/urg04lx.hpp"

namespace stridemap {

struct UrgDriverOptions {
  /// Steps to measure; -1 takes the sensor's AMIN / AMAX from PP.
  int start_step = -1;
  int end_step = -1;
  /// Adjacent steps merged into one value (1..99); the sensor sends the
  /// smallest valid one.
  int cluster = 1;
  /// Scans skipped between transmitted ones (0..9).
  int scan_interval = 0;
  /// MS (2-character values, at most 4095 mm) instead of MD.
  bool two_char_values = false;
  /// Each start-up command must be answered within this [s].
  double reply_timeout_s = 1.0;
  /// QT probes sent before a silent device is reported (no_reply).
  int probe_attempts = 3;
  /// Streaming with no scan for this long is a stall [s]. 0: five scan
  /// periods (times interval + 1), at least 0.5 s.
  double stall_timeout_s = 0.0;
  /// Wait between attempts to reopen a lost device [s].
  double reconnect_interval_s = 0.5;
  /// Scans over which the clock offset is the minimum (ScanClock).
  std::size_t clock_window_scans = 100;
  /// Time from a scan's step 0 to its sending, subtracted from the host
  /// receive time; negative: one scan period (the sensor sends at the end of
  /// the turn). An assumption, not a documented figure.
  double send_delay_s = -1.0;
  /// Clocks in seconds; empty: std::chrono::steady_clock for timeouts and
  /// system_clock (Unix time) for host timestamps. Tests inject fakes.
  std::function<double()> monotonic_clock;
  std::function<double()> host_clock;
  /// Waits this many seconds while there is no device to read (between
  /// reopening attempts); empty: std::this_thread::sleep_for.
  std::function<void(double)> sleep;

  /// Throws InputError naming the field.
  void validate() const;
};

enum class UrgDriverState : std::uint8_t { disconnected, starting, streaming };

enum class UrgFault : std::uint8_t {
  open_failed,     ///< the device could not be opened (missing, busy, not a terminal)
  link_lost,       ///< reading or writing failed: unplugged, hung up
  no_reply,        ///< a start-up command got no reply in time: not a URG, or not powered
  command_failed,  ///< the sensor refused a start-up command (status in the message)
  bad_reply,       ///< a reply that cannot be used (PP fields inconsistent, ...)
  corrupt_data,    ///< bytes that did not decode (bad checksum, wrong length...): a frame is lost
  scans_lost,      ///< the sensor's timestamps skip `count` scans that never arrived intact
  duplicate_scan,  ///< a scan with the timestamp of the previous one: dropped
  stall,           ///< no scan within the stall timeout while streaming
  sensor_reset,    ///< the sensor's clock jumped or it spoke SCIP 1.1 again: it restarted
  sensor_error,    ///< the sensor reported an error status in the stream (21-97)
};

std::string_view fault_name(UrgFault fault);

struct UrgScan {
  UrgRawScan raw;                       ///< raw.time_s = host_time_s
  std::uint64_t sequence = 0;           ///< scans delivered by this driver, from 0
  std::uint32_t sensor_timestamp_ms = 0;  ///< the sensor's 24-bit stamp of step 0
  std::uint64_t sensor_time_ms = 0;     ///< the stamp unwrapped, counted from the first stamp seen
  double host_time_s = 0.0;             ///< host time of step 0 (ScanClock)
  double host_receive_time_s = 0.0;     ///< host time when the frame's last byte was read
  /// Scans the timestamps say are missing between the previous scan and
  /// this one (also reported as a scans_lost fault).
  std::uint64_t lost_before = 0;
  /// The first scan since the driver (re)started the stream after a reset
  /// or reconnection: the timestamps cannot tell what was missed before it.
  bool first_after_start = false;
};

/// A sensor time in milliseconds as seconds, computed one way everywhere
/// (driver, logs, emulator), so that times on the sensor clock compare bit
/// for bit.
inline double sensor_time_seconds(std::uint64_t sensor_time_ms) { return static_cast<double>(sensor_time_ms) / 1000.0; }

struct UrgDriverEvent {
  enum class Kind : std::uint8_t { connected, scan, fault } kind = Kind::fault;
  UrgScan scan;               ///< Kind::scan
  UrgFault fault = UrgFault::open_failed;
  std::string message;        ///< Kind::fault: names the device and what happened; connected: the sensor
  std::uint64_t count = 0;    ///< scans_lost: scans; sensor_reset/link_lost: scans missed by host time (estimate)
};

struct UrgDriverStats {
  std::uint64_t scans = 0;
  /// Scans that never arrived: the gaps in the sensor's timestamps, plus the
  /// scans an outage (the sensor restarted, the link was lost) swallowed,
  /// estimated from host time and the scan period.
  std::uint64_t scans_lost = 0;
  std::uint64_t scans_lost_by_host_time = 0;  ///< the outages' part of scans_lost
  std::uint64_t corrupt_frames = 0;   ///< decode errors while streaming
  std::uint64_t faults = 0;
  std::uint64_t connects = 0;         ///< successful start-ups
  std::uint64_t stalls = 0;
  std::uint64_t resets = 0;
  std::uint64_t bytes_received = 0;
};

class UrgDriver {
 public:
  /// Throws InputError for invalid options. Nothing is opened until next().
  explicit UrgDriver(ByteStreamOpener opener, UrgDriverOptions options = {});
  ~UrgDriver();
  UrgDriver(const UrgDriver&) = delete;
  UrgDriver& operator=(const UrgDriver&) = delete;

  /// Runs the driver for at most `timeout_s` seconds (plus one write
  /// timeout in the worst case) and returns true with the next event, or
  /// false when none came in time. Never throws for anything the device does.
  bool next(UrgDriverEvent& event, double timeout_s);
  /// Stops the stream (QT, bounded wait) and closes the device; next() opens it again.
  void stop();

  UrgDriverState state() const { return state_; }
  /// The last start-up's VV and PP replies (defaults before the first one).
  const scip::VersionInfo& version() const { return version_; }
  const scip::ScipParameters& parameters() const { return parameters_; }
  /// Beam geometry from PP, for UrgModel.
  const UrgParameters& urg_parameters() const { return urg_parameters_; }
  const UrgDriverStats& stats() const { return stats_; }
  /// The device's name once opened (empty before).
  const std::string& device_name() const { return device_name_; }

 private:
  enum class Step : std::uint8_t { probe, switch_scip2, leave_time_mode, version, parameters, laser_on, start_stream };

  double now() const;
  double host_now() const;
  void open_device();
  void close_device();
  void lose_link(UrgFault fault, const std::string& message);
  void begin_start();
  void send_step(Step step);
  bool send(const std::string& command);
  void on_reply_timeout();
  void read_some(double wait_s);
  bool read_what_waits(double& drained_for, double deadline);
  void handle(const scip::Event& event);
  void handle_start_reply(const scip::Event& event);
  // The start-up steps that do more than check a status.
  void take_version_reply(const scip::Event& event);
  void take_parameters_reply(const scip::Event& event);
  void take_stream_start_reply(const scip::Event& event);
  // Ends a start that went wrong: said, the device closed, a reconnection planned.
  void refuse_start(UrgFault fault, const std::string& what);
  void handle_stream_event(const scip::Event& event);
  void deliver_scan(const scip::Event& event);
  void restart_stream(UrgFault fault, const std::string& message, std::uint64_t count);
  void report(UrgFault fault, std::string message, std::uint64_t count = 0);
  std::string device() const;
  double scans_period_s() const;
  double stall_timeout_s() const;

  ByteStreamOpener opener_;
  UrgDriverOptions options_;
  std::unique_ptr<ByteStream> stream_;
  std::string device_name_;
  UrgDriverState state_ = UrgDriverState::disconnected;
  Step step_ = Step::probe;
  int probes_sent_ = 0;
  double reply_deadline_ = 0.0;
  double stall_deadline_ = 0.0;
  double next_open_time_ = 0.0;
  std::string last_open_error_;
  std::string last_decode_error_;
  std::uint64_t bytes_at_start_ = 0;
  // The deadline for which the waiting input was last read (see next()).
  double drained_for_reply_ = -1.0;
  double drained_for_stall_ = -1.0;
  // Stream starts so far, and the one the previous scan came in.
  std::uint64_t stream_starts_ = 0;
  std::uint64_t previous_scan_start_ = 0;

  scip::Decoder decoder_;
  scip::Event event_;
  std::vector<char> read_buffer_;
  scip::Command stream_command_;
  scip::VersionInfo version_;
  scip::ScipParameters parameters_;
  UrgParameters urg_parameters_;

  scip::TimestampUnwrapper unwrapper_;
  ScanClock clock_;
  bool have_previous_scan_ = false;
  std::uint32_t previous_raw_ms_ = 0;
  double previous_receive_s_ = 0.0;
  double last_read_host_s_ = 0.0;

  // Slots reused (a scan's values keep their storage): no allocation per scan.
  RingQueue<UrgDriverEvent> pending_;
  UrgDriverEvent& push_event(UrgDriverEvent::Kind kind) {
    UrgDriverEvent& e = pending_.push_slot();
    e.kind = kind;
    e.message.clear();
    e.count = 0;
    return e;
  }
  UrgDriverStats stats_;
};

}  // namespace stridemap
