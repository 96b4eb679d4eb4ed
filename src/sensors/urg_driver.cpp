#include "stridemap/sensors/urg_driver.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <thread>

#include "stridemap/core/error.hpp"
#include "stridemap/sensors/scip_status.hpp"

namespace stridemap {
namespace {

constexpr std::size_t kReadChunk = 4096;

std::chrono::milliseconds to_ms(double seconds) {
  // Rounded up, so that a wait never turns into a busy loop of zero timeouts.
  return std::chrono::milliseconds(static_cast<long long>(std::ceil(std::max(0.0, seconds) * 1000.0)));
}

std::string format_s(double seconds) {
  char text[32];
  std::snprintf(text, sizeof text, "%.2f s", seconds);
  return text;
}

bool positive_finite(double v) { return std::isfinite(v) && v > 0.0; }

}  // namespace

void UrgDriverOptions::validate() const {
  const auto bad = [](const std::string& field, const std::string& what) {
    throw InputError("URG driver options: " + field + " " + what);
  };
  if (start_step < -1 || start_step > 9999) bad("start_step", "must be -1 (AMIN) or 0..9999");
  if (end_step < -1 || end_step > 9999) bad("end_step", "must be -1 (AMAX) or 0..9999");
  if (start_step >= 0 && end_step >= 0 && end_step < start_step) bad("end_step", "must not be below start_step");
  if (cluster < 0 || cluster > 99) bad("cluster", "must be 0..99");
  if (scan_interval < 0 || scan_interval > 9) bad("scan_interval", "must be 0..9");
  if (!positive_finite(reply_timeout_s)) bad("reply_timeout_s", "must be a positive number of seconds");
  if (probe_attempts < 1) bad("probe_attempts", "must be at least 1");
  if (!(std::isfinite(stall_timeout_s) && stall_timeout_s >= 0.0)) bad("stall_timeout_s", "must be >= 0");
  if (!positive_finite(reconnect_interval_s)) bad("reconnect_interval_s", "must be a positive number of seconds");
  if (clock_window_scans < 1) bad("clock_window_scans", "must be at least 1");
  if (!std::isfinite(send_delay_s)) bad("send_delay_s", "must be finite");
}

std::string_view fault_name(UrgFault fault) {
  switch (fault) {
    case UrgFault::open_failed: return "open_failed";
    case UrgFault::link_lost: return "link_lost";
    case UrgFault::no_reply: return "no_reply";
    case UrgFault::command_failed: return "command_failed";
    case UrgFault::bad_reply: return "bad_reply";
    case UrgFault::corrupt_data: return "corrupt_data";
    case UrgFault::scans_lost: return "scans_lost";
    case UrgFault::duplicate_scan: return "duplicate_scan";
    case UrgFault::stall: return "stall";
    case UrgFault::sensor_reset: return "sensor_reset";
    case UrgFault::sensor_error: return "sensor_error";
  }
  return "unknown";
}

namespace {

constexpr std::size_t kPendingReserved = 64;
constexpr std::size_t kMaxScanValues = 1081;  // the most steps a SCIP 2.0 scanner of this family sends

}  // namespace

UrgDriver::UrgDriver(ByteStreamOpener opener, UrgDriverOptions options)
    : opener_(std::move(opener)), options_(std::move(options)), read_buffer_(kReadChunk),
      clock_(options_.clock_window_scans, 0.1) {
  options_.validate();
  if (!opener_) throw InputError("URG driver: no device opener given");
  urg_parameters_ = scip::to_urg_parameters(parameters_);
  // Scans that arrive together (a host that read late) wait here: room for
  // a burst of them, each with room for a full scan, so that none allocates.
  pending_.reserve(kPendingReserved, [](UrgDriverEvent& e) { e.scan.raw.values_mm.reserve(kMaxScanValues); });
}

UrgDriver::~UrgDriver() { stop(); }

double UrgDriver::now() const {
  if (options_.monotonic_clock) return options_.monotonic_clock();
  return std::chrono::duration<double>(std::chrono::steady_clock::now().time_since_epoch()).count();
}

double UrgDriver::host_now() const {
  if (options_.host_clock) return options_.host_clock();
  return std::chrono::duration<double>(std::chrono::system_clock::now().time_since_epoch()).count();
}

std::string UrgDriver::device() const { return device_name_.empty() ? std::string("URG") : device_name_; }

double UrgDriver::scans_period_s() const {
  return urg_parameters_.scan_period_s * static_cast<double>(options_.scan_interval + 1);
}

double UrgDriver::stall_timeout_s() const {
  if (options_.stall_timeout_s > 0.0) return options_.stall_timeout_s;
  return std::max(0.5, 5.0 * scans_period_s());
}

bool UrgDriver::next(UrgDriverEvent& event, double timeout_s) {
  const double deadline = now() + (std::isfinite(timeout_s) ? std::max(0.0, timeout_s) : 0.0);
  while (true) {
    if (!pending_.empty()) {
      std::swap(event, pending_.front());  // the slot takes the caller's old storage
      pending_.pop_front();
      return true;
    }
    const double t = now();
    if (state_ == UrgDriverState::disconnected) {
      if (t >= next_open_time_) {
        open_device();
        continue;
      }
      if (t >= deadline) return false;
      const double wait = std::min(deadline, next_open_time_) - t;
      if (options_.sleep) {
        options_.sleep(wait);
      } else {
        std::this_thread::sleep_for(std::chrono::duration<double>(wait));
      }
      continue;
    }
    // A deadline that passed while this thread was not running (a loaded
    // host) says nothing about the device until the input that waits is
    // read: a reply or scan may be there. So once per deadline, read first.
    if (state_ == UrgDriverState::starting && t >= reply_deadline_) {
      if (read_what_waits(drained_for_reply_, reply_deadline_)) continue;
      on_reply_timeout();
      continue;
    }
    if (state_ == UrgDriverState::streaming && t >= stall_deadline_) {
      if (read_what_waits(drained_for_stall_, stall_deadline_)) continue;
      ++stats_.stalls;
      restart_stream(UrgFault::stall, device() + ": no scan for " + format_s(stall_timeout_s()) + "; restarting the stream",
                     0);
      continue;
    }
    const double wake = std::min(state_ == UrgDriverState::starting ? reply_deadline_ : stall_deadline_, deadline);
    const std::uint64_t before = stats_.bytes_received;
    read_some(t >= deadline ? 0.0 : wake - t);
    if (pending_.empty() && stats_.bytes_received == before && now() >= deadline) return false;
  }
}

void UrgDriver::stop() {
  if (stream_ && state_ == UrgDriverState::streaming) {
    // Best effort, bounded: a sensor left streaming keeps sending into the
    // next session (the next start-up copes with that too).
    stream_->write(scip::laser_off_command(), std::chrono::milliseconds(200));
  }
  close_device();
  next_open_time_ = now();
}

void UrgDriver::open_device() {
  std::string error;
  std::unique_ptr<ByteStream> stream = opener_(error);
  if (!stream) {
    if (error.empty()) error = "the device could not be opened";
    if (error != last_open_error_) report(UrgFault::open_failed, error);
    last_open_error_ = error;
    next_open_time_ = now() + options_.reconnect_interval_s;
    return;
  }
  last_open_error_.clear();
  stream_ = std::move(stream);
  device_name_ = stream_->name();
  begin_start();
}

void UrgDriver::close_device() {
  stream_.reset();
  state_ = UrgDriverState::disconnected;
  decoder_.reset();
}

void UrgDriver::lose_link(UrgFault fault, const std::string& message) {
  report(fault, message);
  close_device();
  // Not at once: a device that vanished needs time to come back (a USB
  // sensor re-enumerates in about a second), and retrying in a loop would
  // turn one fault into thousands.
  next_open_time_ = now() + options_.reconnect_interval_s;
}

void UrgDriver::begin_start() {
  state_ = UrgDriverState::starting;
  probes_sent_ = 0;
  last_decode_error_.clear();
  bytes_at_start_ = stats_.bytes_received;
  ++stream_starts_;
  decoder_.reset();
  stream_->discard_input();
  // A bare LF ends whatever half command the sensor may hold (as the
  // official library does), then QT stops a stream left running.
  if (!send("\n")) return;
  send_step(Step::probe);
}

bool UrgDriver::send(const std::string& command) {
  const StreamResult result = stream_->write(command, to_ms(options_.reply_timeout_s));
  if (result.status == StreamStatus::ok) return true;
  lose_link(UrgFault::link_lost, result.status == StreamStatus::closed
                                     ? result.message
                                     : device() + ": cannot write a command within " +
                                           format_s(options_.reply_timeout_s));
  return false;
}

void UrgDriver::send_step(Step step) {
  step_ = step;
  std::string command;
  switch (step) {
    case Step::probe:
      ++probes_sent_;
      command = scip::laser_off_command();
      break;
    case Step::switch_scip2: command = scip::switch_to_scip2_command(); break;
    case Step::leave_time_mode: command = scip::time_command(scip::TimeMode::adjust_off); break;
    case Step::version: command = scip::version_command(); break;
    case Step::parameters: command = scip::parameters_command(); break;
    case Step::laser_on: command = scip::laser_on_command(); break;
    case Step::start_stream: command = stream_command_.text + "\n"; break;
  }
  if (!send(command)) return;
  reply_deadline_ = now() + options_.reply_timeout_s;
}

void UrgDriver::on_reply_timeout() {
  if (step_ == Step::probe && probes_sent_ < options_.probe_attempts) {
    send_step(Step::probe);
    return;
  }
  std::string message = device() + ": no reply to " +
                        std::string(step_ == Step::probe ? "QT" : step_ == Step::switch_scip2 ? "SCIP2.0"
                                    : step_ == Step::leave_time_mode                       ? "TM2"
                                    : step_ == Step::version                               ? "VV"
                                    : step_ == Step::parameters                            ? "PP"
                                    : step_ == Step::laser_on                              ? "BM"
                                                                                           : stream_command_.text) +
                        " within " + format_s(options_.reply_timeout_s);
  if (step_ == Step::probe) message += " (" + std::to_string(probes_sent_) + " tries): is it a URG, and powered?";
  const std::uint64_t received = stats_.bytes_received - bytes_at_start_;
  if (!last_decode_error_.empty()) {
    message += "; it sent bytes that are not SCIP 2.0: " + last_decode_error_;
  } else if (received > 0) {
    message += "; it sent " + std::to_string(received) + " bytes, none of them a SCIP 2.0 reply";
  }
  report(UrgFault::no_reply, message);
  close_device();
  next_open_time_ = now() + options_.reconnect_interval_s;
}

// Reads, without waiting, what the port holds (a bounded amount: a device
// cannot outpace this loop), once for `deadline`; true when that got bytes
// or lost the link (the caller looks at the state again).
bool UrgDriver::read_what_waits(double& drained_for, double deadline) {
  if (drained_for == deadline) return false;
  drained_for = deadline;
  constexpr int kMaxChunks = 256;
  const std::uint64_t before = stats_.bytes_received;
  for (int k = 0; k < kMaxChunks && stream_; ++k) {
    const std::uint64_t at = stats_.bytes_received;
    read_some(0.0);
    if (stats_.bytes_received == at) break;
  }
  return !stream_ || stats_.bytes_received != before;
}

void UrgDriver::read_some(double wait_s) {
  const StreamResult result = stream_->read(read_buffer_, to_ms(wait_s));
  if (result.status == StreamStatus::closed) {
    lose_link(UrgFault::link_lost, result.message);
    return;
  }
  if (result.bytes == 0) return;
  stats_.bytes_received += result.bytes;
  last_read_host_s_ = host_now();
  decoder_.feed(std::string_view(read_buffer_.data(), result.bytes));
  while (stream_ && decoder_.next(event_)) handle(event_);
}

void UrgDriver::handle(const scip::Event& event) {
  if (state_ == UrgDriverState::starting) {
    handle_start_reply(event);
  } else if (state_ == UrgDriverState::streaming) {
    handle_stream_event(event);
  }
}

void UrgDriver::report(UrgFault fault, std::string message, std::uint64_t count) {
  ++stats_.faults;
  UrgDriverEvent& e = push_event(UrgDriverEvent::Kind::fault);
  e.fault = fault;
  e.message = std::move(message);
  e.count = count;
}

void UrgDriver::restart_stream(UrgFault fault, const std::string& message, std::uint64_t count) {
  report(fault, message, count);
  begin_start();
}

}  // namespace stridemap
