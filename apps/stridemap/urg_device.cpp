#include "urg_device.hpp"

#include <fcntl.h>
#include <sys/resource.h>
#include <sys/stat.h>
#include <unistd.h>

#include <atomic>
#include <cerrno>
#include <chrono>
#include <csignal>
#include <cstdio>
#include <cstring>

#include "cli_parsing.hpp"
#include "stridemap/core/error.hpp"
#include "stridemap/core/printable_text.hpp"
#include "stridemap/devices/serial_port.hpp"

namespace stridemap::cli {
namespace {

std::atomic<bool> g_stop{false};

extern "C" void on_stop_signal(int) { g_stop.store(true); }

// What a device path is when it is certainly no URG ("a folder"), empty when
// it may be one or may become one. Only problems no wait can cure: a missing
// path, a folder, a file or a character device that is not a terminal. A busy
// device or one that does not answer yet is the driver's to retry.
std::string permanent_device_problem(const std::string& device) {
  struct stat status {};
  if (::stat(device.c_str(), &status) != 0) {
    const int error_number = errno;
    std::string problem = std::string("cannot open the device: ") + std::strerror(error_number);
    if (error_number == ENOENT) problem += " (is the sensor plugged in, or the emulator's --link running?)";
    return problem;
  }
  if (S_ISDIR(status.st_mode)) return "it is a folder, not a serial device";
  if (S_ISREG(status.st_mode)) return "it is a regular file, not a serial device (a scan log is read by 'map --log')";
  if (!S_ISCHR(status.st_mode)) return "it is not a serial device (not a character device)";
  const int fd = ::open(device.c_str(), O_RDWR | O_NOCTTY | O_NONBLOCK | O_CLOEXEC);
  if (fd < 0) {
    const int error_number = errno;
    if (error_number == EACCES || error_number == EPERM) {
      return std::string("cannot open the device: ") + std::strerror(error_number);
    }
    return {};
  }
  const bool terminal = ::isatty(fd) != 0;
  ::close(fd);
  if (!terminal) return "it is not a serial device (not a terminal)";
  return {};
}

}  // namespace

void add_device_options(CLI::App& command, DeviceArgs& args) {
  command.add_option("--device", args.device, "The URG's serial device (e.g. /dev/ttyACM0) or an emulator's link")
      ->required();
  command.add_option("--start-step", args.start_step, "First step to measure (-1: the sensor's AMIN)")
      ->capture_default_str()
      ->check(whole_from_to(-1, 65535));
  command.add_option("--end-step", args.end_step, "Last step to measure (-1: the sensor's AMAX)")
      ->capture_default_str()
      ->check(whole_from_to(-1, 65535));
  command.add_option("--cluster", args.cluster, "Adjacent steps merged into one value (1..99)")->capture_default_str()
      ->check(whole_from_to(1, 99));
  command.add_option("--connect-timeout-s", args.connect_timeout_s,
                     "Give up when no URG streams within this time after start")
      ->capture_default_str()
      ->check(number_from_to(0.001, 3600.0, "s"));
  command.add_option("--stall-timeout-s", args.stall_timeout_s,
                     "No scan for this long is a stall (0: five scan periods, at least 0.5 s)")
      ->capture_default_str()
      ->check(number_from_to(0.0, 3600.0, "s"));
  command.add_option("--duration-s", args.duration_s, "Stop after this many seconds (0: at SIGINT/SIGTERM)")
      ->capture_default_str()
      ->check(number_from_to(0.0, 31536000.0, "s"));
  command.add_option("--max-scans", args.max_scans, "Stop after this many scans (0: no limit)")
      ->capture_default_str()
      ->check(whole_from_to(0, std::numeric_limits<std::uint64_t>::max()));
}

void install_stop_signals() {
  struct sigaction action{};
  action.sa_handler = on_stop_signal;
  sigemptyset(&action.sa_mask);
  action.sa_flags = 0;  // no SA_RESTART: a blocking poll returns at once
  // SIGHUP too: an ssh session that drops must not lose the map or the log.
  sigaction(SIGINT, &action, nullptr);
  sigaction(SIGTERM, &action, nullptr);
  sigaction(SIGHUP, &action, nullptr);
  // A pose pipe whose reader went away must give a write error, not kill us.
  std::signal(SIGPIPE, SIG_IGN);
}

bool stop_requested() { return g_stop.load(); }

const std::atomic<bool>& stop_flag() { return g_stop; }

void print_fault(const UrgDriverEvent& event) {
  std::fprintf(stderr, "stridemap: %s: %s\n", std::string(fault_name(event.fault)).c_str(),
               printable_text(event.message).c_str());
}

std::unique_ptr<UrgDriver> start_driver(const DeviceArgs& args, UrgDriverEvent& connected) {
  if (!(args.connect_timeout_s > 0.0)) throw InputError("--connect-timeout-s must be positive");
  // Fail now rather than after the connect timeout when waiting cannot help.
  if (const std::string problem = permanent_device_problem(args.device); !problem.empty()) {
    throw InputError(args.device + ": " + problem);
  }
  UrgDriverOptions options;
  options.start_step = args.start_step;
  options.end_step = args.end_step;
  options.cluster = args.cluster;
  options.stall_timeout_s = args.stall_timeout_s;
  auto driver = std::make_unique<UrgDriver>(io::SerialPort::opener(args.device), options);
  const double deadline = monotonic_seconds() + args.connect_timeout_s;
  std::string last_fault;
  while (!stop_requested()) {
    const double left = deadline - monotonic_seconds();
    if (left <= 0.0) break;
    if (!driver->next(connected, std::min(left, 0.2))) continue;
    if (connected.kind == UrgDriverEvent::Kind::connected) return driver;
    if (connected.kind == UrgDriverEvent::Kind::fault) {
      print_fault(connected);
      last_fault = connected.message;
    }
  }
  if (stop_requested()) throw InputError(args.device + ": stopped before the sensor streamed");
  throw InputError(args.device + ": no URG streaming within " + std::to_string(args.connect_timeout_s) + " s" +
                   (last_fault.empty() ? std::string() : "; last problem: " + last_fault));
}

double process_cpu_seconds() {
  rusage usage{};
  getrusage(RUSAGE_SELF, &usage);
  const auto seconds = [](const timeval& t) { return static_cast<double>(t.tv_sec) + 1e-6 * static_cast<double>(t.tv_usec); };
  return seconds(usage.ru_utime) + seconds(usage.ru_stime);
}

double host_seconds() {
  return std::chrono::duration<double>(std::chrono::system_clock::now().time_since_epoch()).count();
}

}  // namespace stridemap::cli

namespace stridemap::cli {

double monotonic_seconds() {
  return std::chrono::duration<double>(std::chrono::steady_clock::now().time_since_epoch()).count();
}

}  // namespace stridemap::cli
