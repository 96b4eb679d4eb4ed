#pragma once
// The URG-04LX's side of SCIP, as a state machine with no I/O: host bytes
// in, the sensor's bytes out, each stamped with the simulation time at which
// the sensor sends it. It behaves like the real units where they differ from
// the spec (../shared/research/scip.md): the classic URG-04LX boots in
// SCIP 1.1 and answers `SCIP2.0` with the one-character status `0`; the
// UG01 speaks SCIP 2.0 from power-up and calls `SCIP2.0` an undefined
// command (`0Ee`); the laser is off after power-up and after the switch (GD
// then fails with status 10 until BM); MD/MS turn it on; the 24-bit
// millisecond timestamp wraps. Scans come from a UrgScanSource: one scan per
// motor turn, sent when the turn ends. The real-time loop, the
// pseudo-terminal and fault injection are in live/emulator_server.hpp.
#include <cstdint>
#include <deque>
#include <string>
#include <string_view>
#include <vector>

#include "stridemap/sensors/scip_command.hpp"
#include "stridemap/sensors/scip_parameters.hpp"
#include "stridemap/sim/urg_scan_source.hpp"

namespace stridemap {

enum class UrgVariant : std::uint8_t {
  classic,  ///< URG-04LX: boots in SCIP 1.1
  ug01,     ///< URG-04LX-UG01: SCIP 2.0 from power-up
};

struct UrgEmulatorOptions {
  UrgVariant variant = UrgVariant::classic;
  /// PP reply (a UG01 reports its own MODL unless another is set). SCAN sets the scan period: 60000 / SCAN must be a whole number
  /// of milliseconds (600 rpm: 100 ms). A faster SCAN runs the emulator
  /// faster than a real unit, for tests.
  scip::ScipParameters parameters{};
  /// VV reply; empty fields take the variant's defaults (serial "EMULATED").
  scip::VersionInfo version{};
  /// Sensor clock at power-up [ms]; near 2^24 to see the wrap soon.
  std::uint32_t timestamp_start_ms = 0;

  /// Throws InputError naming the field.
  void validate() const;
};

/// Bytes the sensor sends, and when.
struct EmulatorOutput {
  std::int64_t time_ms = 0;          ///< simulation time of sending [ms]
  std::string bytes;
  bool is_scan = false;              ///< an MD/MS data frame or a GD/GS reply
  std::uint64_t scan_index = 0;      ///< is_scan: the scan's number since power-up
  std::uint32_t timestamp_ms = 0;    ///< is_scan: its 24-bit timestamp
  std::int64_t scan_start_ms = 0;    ///< is_scan: simulation time of its step 0 [ms]
};

class UrgEmulator {
 public:
  /// Keeps a reference to `source`. The sensor is powered up at `now_ms`.
  UrgEmulator(const UrgEmulatorOptions& options, UrgScanSource& source, std::int64_t now_ms = 0);

  /// Host bytes received at `now_ms`; every complete command line (LF, CR
  /// or CRLF) is answered at once.
  void receive(std::string_view bytes, std::int64_t now_ms);
  /// Produces the scans due by `now_ms` (call before receive() with the same time).
  void advance(std::int64_t now_ms);
  /// Output produced so far, in sending order; take it and clear it.
  std::vector<EmulatorOutput>& output() { return output_; }
  /// Time of the next scan to send, or INT64_MAX when none is pending.
  std::int64_t next_due_ms() const;
  /// Power loss and restart at `now_ms`: SCIP 1.1 again (classic), laser
  /// off, no stream, clock restarted at timestamp_start_ms, input dropped.
  void power_cycle(std::int64_t now_ms);

  bool scip2() const { return scip2_; }
  bool laser_on() const { return laser_on_; }
  bool streaming() const { return stream_.active; }
  std::int64_t scan_period_ms() const { return period_ms_; }
  /// Sensor time at `now_ms` (24 bits) [ms].
  std::uint32_t sensor_time_ms(std::int64_t now_ms) const;
  /// Sensor time without the 24-bit wrap, counted from power-up [ms].
  std::int64_t unwrapped_sensor_time_ms(std::int64_t now_ms) const;
  const UrgEmulatorOptions& options() const { return options_; }

 private:
  struct Stream {
    bool active = false;
    scip::Command command;
    std::uint64_t next_scan = 0;
    int remaining = 0;  ///< scans still to send; 0 with unlimited
    bool unlimited = true;
  };
  void answer(std::string_view received, std::int64_t now_ms);
  void answer_scip2(const scip::Command& command, std::string_view line, std::int64_t now_ms);
  void answer_distance(const scip::Command& command, std::string_view line, std::int64_t now_ms);
  void reply(std::string_view echo, std::string_view status, std::int64_t now_ms);
  void send_scan(const scip::Command& echo, std::string_view status, std::uint64_t index, std::int64_t send_ms);
  std::uint64_t first_scan_after(std::int64_t now_ms) const;
  std::int64_t scan_start_ms(std::uint64_t index) const { return power_on_ms_ + static_cast<std::int64_t>(index) * period_ms_; }
  void stop_stream();

  UrgEmulatorOptions options_;
  UrgScanSource& source_;
  std::int64_t period_ms_ = 100;
  std::int64_t power_on_ms_ = 0;
  std::int64_t timer_zero_ms_ = 0;
  bool scip2_ = false;
  bool laser_on_ = false;
  bool time_adjust_ = false;
  std::string partial_line_;
  Stream stream_;
  std::deque<std::pair<scip::Command, std::uint64_t>> single_scans_;  ///< GD/GS waiting for their scan
  std::vector<EmulatorOutput> output_;
  std::vector<std::uint32_t> step_values_, values_;
};

}  // namespace stridemap
