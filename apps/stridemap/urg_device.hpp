#pragma once
// What `record` and `live` share: the device options, starting the driver
// with a bounded wait, stopping cleanly on SIGINT/SIGTERM/SIGHUP, printing faults.
#include <atomic>
#include <memory>
#include <string>

#include <CLI/CLI.hpp>

#include "stridemap/sensors/urg_driver.hpp"

namespace stridemap::cli {

struct DeviceArgs {
  std::string device;
  int start_step = -1;
  int end_step = -1;
  int cluster = 1;
  double connect_timeout_s = 5.0;
  double stall_timeout_s = 0.0;
  /// Stop after this many seconds / scans (0: until SIGINT or SIGTERM).
  double duration_s = 0.0;
  std::uint64_t max_scans = 0;
};

void add_device_options(CLI::App& command, DeviceArgs& args);

/// SIGINT, SIGTERM and SIGHUP set a flag instead of killing the process.
void install_stop_signals();
bool stop_requested();
const std::atomic<bool>& stop_flag();

/// Opens the device and waits until the sensor streams (or the connect
/// timeout passes, or a stop signal). Faults on the way go to stderr.
/// Throws InputError naming the device and the last fault when no URG
/// answered in time.
std::unique_ptr<UrgDriver> start_driver(const DeviceArgs& args, UrgDriverEvent& connected);

/// "stridemap: <device>: <fault>: message" on stderr.
void print_fault(const UrgDriverEvent& event);

/// Wall-clock and CPU seconds of this process since the first call.
double process_cpu_seconds();
double host_seconds();
double monotonic_seconds();

}  // namespace stridemap::cli
