#pragma once
// The URG emulator in real time on a pseudo-terminal (`stridemap
// emulate-urg`): a UrgEmulator answers the host through a PseudoTerminal
// whose symlink looks like /dev/ttyACM0, scans go out when the sensor's
// turn ends, and faults are injected on request: corrupted bytes, dropped
// frames, a stall (the sensor falls silent and deaf, then carries on), a
// disconnect (the link vanishes, the sensor loses power, and both come back)
// and a reset (the sensor restarts on a live link). A trace file says what
// happened to every scan, so tests can check that the driver missed none
// silently; a pose file gives the true pose of every scan.
#include <atomic>
#include <cstdint>
#include <functional>
#include <string>
#include <vector>

#include "stridemap/sim/motion_source.hpp"
#include "stridemap/sim/urg_emulator.hpp"

namespace stridemap {

enum class EmulatorFaultKind : std::uint8_t { corrupt, drop, stall, disconnect, reset };

std::string_view emulator_fault_name(EmulatorFaultKind kind);

/// A fault at scan frame `at_frame` (frames counted from 1 over the whole
/// run, every frame the sensor produced, sent or not).
struct EmulatorFault {
  EmulatorFaultKind kind = EmulatorFaultKind::drop;
  std::uint64_t at_frame = 1;
  double duration_s = 1.0;  ///< stall and disconnect
};

/// "corrupt@20", "drop@30", "stall@40:1.5", "disconnect@60:1", "reset@80".
/// Throws InputError quoting the text and saying what is wrong.
EmulatorFault parse_emulator_fault(const std::string& text);

/// Clock of the times in the pose file.
enum class PoseClock : std::uint8_t {
  host,    ///< the host's system clock (Unix time) at the scan's step 0
  sensor,  ///< the sensor's millisecond clock at step 0, unwrapped, in seconds
};

struct EmulatorServerOptions {
  std::string link_path;
  std::vector<EmulatorFault> faults;
  /// Chance per frame of a corrupted byte / of a dropped frame, drawn from a
  /// generator seeded with fault_seed.
  double corrupt_probability = 0.0;
  double drop_probability = 0.0;
  std::uint64_t fault_seed = 1;
  /// Empty: none. Trace lines are documented in docs/emulator.md.
  std::string trace_path;
  /// Empty: none. The true pose of every scan frame, in the pose format.
  std::string poses_path;
  PoseClock pose_clock = PoseClock::host;
  /// Poses per second, as a pose estimator publishes them, each written when
  /// its time has come; 0: one pose per scan frame, at the scan's step 0
  /// (exact poses for the scans, for tests that compare maps).
  double poses_rate_hz = 0.0;
  /// Stop after this many frames (0: no limit) or seconds (0: no limit).
  std::uint64_t max_frames = 0;
  double max_duration_s = 0.0;
  /// Output that the host has not read beyond this is not sent (the
  /// frame is traced as `overflow`): a host that stops reading loses scans.
  std::size_t max_unread_bytes = 64 * 1024;

  void validate() const;
};

struct EmulatorServerStats {
  std::uint64_t frames = 0;     ///< scan frames the sensor produced
  std::uint64_t sent = 0;       ///< sent intact
  std::uint64_t corrupted = 0;  ///< sent with a damaged byte
  std::uint64_t dropped = 0;    ///< not sent (drop fault)
  std::uint64_t lost = 0;       ///< not sent: stalled, disconnected, reset, overflow
  std::uint64_t commands_bytes = 0;
  std::uint64_t disconnects = 0;
  std::uint64_t resets = 0;
  std::uint64_t stalls = 0;
};

/// Runs until `stop` becomes true or a limit is reached; `motion` (may be
/// null, e.g. when replaying) gives the poses for the pose file. `log`
/// receives one line per event worth telling a user (faults, connections).
/// Throws InputError when the pseudo-terminal or an output file cannot be made.
EmulatorServerStats run_emulator_server(UrgEmulator& emulator, const MotionSource* motion,
                                        const EmulatorServerOptions& options, const std::atomic<bool>& stop,
                                        const std::function<void(const std::string&)>& log = {});

}  // namespace stridemap
