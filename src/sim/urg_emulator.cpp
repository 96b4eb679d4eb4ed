#include "stridemap/sim/urg_emulator.hpp"

#include <algorithm>
#include <limits>

#include "stridemap/core/error.hpp"
#include "stridemap/sensors/scip_reply_encoder.hpp"

namespace stridemap {
namespace {

constexpr int kLastLegalStep = 768;          // spec Table 2: steps 0..768 exist on the URG-04LX
constexpr std::uint32_t kNonMeasurable = 19;  // the dead-zone value (scip.md A.11)
constexpr std::size_t kMaxCommandBytes = 64;

bool starts_with(std::string_view text, std::string_view prefix) { return text.substr(0, prefix.size()) == prefix; }

// The status a sensor gives a command whose parameters parse_command rejected.
std::string_view malformed_status(const scip::Command& c) {
  const std::string_view p = c.problem;
  if (starts_with(p, "tag has")) return "0G";
  if (starts_with(p, "tag character")) return "0H";
  if (scip::is_distance_command(c.type)) {
    if (starts_with(p, "start step")) return "01";
    if (starts_with(p, "end step")) return "02";
    if (starts_with(p, "cluster count")) return "03";
    if (starts_with(p, "scan interval")) return "06";
    if (starts_with(p, "number of scans")) return "07";
    return "0C";
  }
  switch (c.type) {
    case scip::CommandType::time:
    case scip::CommandType::bit_rate:
    case scip::CommandType::motor_speed:
    case scip::CommandType::sensitivity:
    case scip::CommandType::malfunction: return "01";
    default: return "0C";
  }
}

}  // namespace

void UrgEmulatorOptions::validate() const {
  const scip::ScipParameters& p = parameters;
  scip::to_urg_parameters(p).validate();
  if (60000 % p.motor_speed_rpm != 0) {
    throw InputError("URG emulator: SCAN " + std::to_string(p.motor_speed_rpm) +
                     " rpm does not give a whole number of milliseconds per scan (60000 / SCAN)");
  }
  if (p.last_step > kLastLegalStep) {
    throw InputError("URG emulator: AMAX " + std::to_string(p.last_step) + " is beyond the last step 768");
  }
  if (timestamp_start_ms >= (1u << 24)) {
    throw InputError("URG emulator: timestamp_start_ms " + std::to_string(timestamp_start_ms) +
                     " does not fit the sensor's 24-bit clock");
  }
}

UrgEmulator::UrgEmulator(const UrgEmulatorOptions& options, UrgScanSource& source, std::int64_t now_ms)
    : options_(options), source_(source) {
  options_.validate();
  period_ms_ = 60000 / options_.parameters.motor_speed_rpm;
  scip::VersionInfo& v = options_.version;
  const bool ug01 = options_.variant == UrgVariant::ug01;
  if (ug01 && options_.parameters.model == scip::ScipParameters{}.model) {
    options_.parameters.model = "URG-04LX-UG01(Simple-URG)(Hokuyo Automatic Co.,Ltd.)";  // as a real UG01's PP
  }
  if (v.vendor.empty()) v.vendor = "Hokuyo Automatic Co.,Ltd.";
  if (v.product.empty()) v.product = ug01 ? "SOKUIKI Sensor URG-04LX-UG01(Simple-URG)" : "SOKUIKI Sensor URG-04LX";
  if (v.firmware.empty()) v.firmware = ug01 ? "3.4.03(17/Dec./2012)" : "3.3.00(emulated)";
  if (v.protocol.empty()) v.protocol = "SCIP 2.0";
  if (v.serial.empty()) v.serial = "EMULATED";
  power_cycle(now_ms);
}

void UrgEmulator::power_cycle(std::int64_t now_ms) {
  power_on_ms_ = now_ms;
  timer_zero_ms_ = now_ms;
  scip2_ = options_.variant == UrgVariant::ug01;
  laser_on_ = false;
  time_adjust_ = false;
  partial_line_.clear();
  stop_stream();
  single_scans_.clear();
}

std::int64_t UrgEmulator::unwrapped_sensor_time_ms(std::int64_t now_ms) const {
  return static_cast<std::int64_t>(options_.timestamp_start_ms) + (now_ms - timer_zero_ms_);
}

std::uint32_t UrgEmulator::sensor_time_ms(std::int64_t now_ms) const {
  return static_cast<std::uint32_t>(unwrapped_sensor_time_ms(now_ms) & ((std::int64_t{1} << 24) - 1));
}

std::uint64_t UrgEmulator::first_scan_after(std::int64_t now_ms) const {
  const std::int64_t since = now_ms - power_on_ms_;
  if (since <= 0) return 0;
  return static_cast<std::uint64_t>((since + period_ms_ - 1) / period_ms_);
}

void UrgEmulator::stop_stream() {
  stream_.active = false;
  stream_.remaining = 0;
}

void UrgEmulator::receive(std::string_view bytes, std::int64_t now_ms) {
  for (const char c : bytes) {
    if (c == '\n' || c == '\r') {
      if (!partial_line_.empty()) answer(partial_line_, now_ms);
      partial_line_.clear();
    } else if (partial_line_.size() < kMaxCommandBytes) {
      partial_line_ += c;  // a longer line is cut: the sensor's buffer is small too
    }
  }
}

void UrgEmulator::reply(std::string_view echo, std::string_view status, std::int64_t now_ms) {
  EmulatorOutput& out = output_.emplace_back();
  out.time_ms = now_ms;
  scip::append_status_reply(echo, status, out.bytes);
}

void UrgEmulator::answer(std::string_view received, std::int64_t now_ms) {
  // Bytes outside printable ASCII cannot be echoed raw (a reply line must
  // stay a valid line): they come back as '?', and the command is unknown.
  std::string line(received);
  for (char& c : line) {
    if (c < 0x20 || c > 0x7E) c = '?';
  }
  const bool printable = line == received;
  scip::Command command;
  const bool known = printable && scip::parse_command(line, command);
  if (!scip2_) {
    // SCIP 1.1 mode: only the switch is implemented; a 1.1 unit answers
    // SCIP 2.0 commands with a one-character error status.
    if (known && command.type == scip::CommandType::switch_to_scip2 && line == "SCIP2.0") {
      scip2_ = true;
      laser_on_ = false;
      reply(line, "0", now_ms);
    } else {
      reply(line, "E", now_ms);
    }
    return;
  }
  if (!known) {
    reply(line, "0E", now_ms);
    return;
  }
  if (!command.well_formed) {
    reply(line, malformed_status(command), now_ms);
    return;
  }
  if (time_adjust_ && command.type != scip::CommandType::time) {
    reply(line, "0E", now_ms);  // TM mode refuses everything else (the official library's probe relies on it)
    return;
  }
  answer_scip2(command, line, now_ms);
}

void UrgEmulator::answer_scip2(const scip::Command& command, std::string_view line, std::int64_t now_ms) {
  using scip::CommandType;
  EmulatorOutput* out = nullptr;
  switch (command.type) {
    case CommandType::version:
      out = &output_.emplace_back();
      out->time_ms = now_ms;
      scip::append_info_reply(line, scip::to_info_fields(options_.version), out->bytes);
      return;
    case CommandType::parameters:
      out = &output_.emplace_back();
      out->time_ms = now_ms;
      scip::append_info_reply(line, scip::to_info_fields(options_.parameters), out->bytes);
      return;
    case CommandType::status_info: {
      scip::StatusInfo info;
      info.model = options_.parameters.model;
      info.laser_on = laser_on_;
      info.motor_speed = "Stable " + std::to_string(options_.parameters.motor_speed_rpm) + "[rpm]";
      info.measurement_mode = stream_.active ? "MEASURING" : "IDLE";
      info.bit_rate = "USB";
      info.time_ms = sensor_time_ms(now_ms);
      out = &output_.emplace_back();
      out->time_ms = now_ms;
      scip::append_info_reply(line, scip::to_info_fields(info), out->bytes);
      return;
    }
    case CommandType::laser_on:
      reply(line, laser_on_ ? "02" : "00", now_ms);
      laser_on_ = true;
      return;
    case CommandType::laser_off:
      stop_stream();
      single_scans_.clear();
      laser_on_ = false;
      reply(line, "00", now_ms);
      return;
    case CommandType::reset:
      stop_stream();
      single_scans_.clear();
      laser_on_ = false;
      timer_zero_ms_ = now_ms;
      reply(line, "00", now_ms);
      return;
    case CommandType::time:
      if (command.code == 0) {
        reply(line, time_adjust_ ? "02" : "00", now_ms);
        stop_stream();
        laser_on_ = false;
        time_adjust_ = true;
      } else if (command.code == 2) {
        reply(line, time_adjust_ ? "00" : "03", now_ms);
        time_adjust_ = false;
      } else if (!time_adjust_) {
        reply(line, "04", now_ms);
      } else {
        out = &output_.emplace_back();
        out->time_ms = now_ms;
        scip::append_time_reply(line, sensor_time_ms(now_ms), out->bytes);
      }
      return;
    case CommandType::bit_rate: reply(line, "00", now_ms); return;      // accepted, meaningless on USB
    case CommandType::motor_speed: reply(line, "04", now_ms); return;   // not emulated: the period stays
    case CommandType::sensitivity: reply(line, "03", now_ms); return;   // not emulated
    case CommandType::malfunction: reply(line, "0E", now_ms); return;   // not emulated
    case CommandType::switch_to_scip2: reply(line, "0E", now_ms); return;  // already SCIP 2.0 (as a UG01 answers)
    case CommandType::scan_3char:
    case CommandType::scan_2char:
    case CommandType::stream_3char:
    case CommandType::stream_2char: answer_distance(command, line, now_ms); return;
    case CommandType::unknown: reply(line, "0E", now_ms); return;
  }
}

void UrgEmulator::answer_distance(const scip::Command& command, std::string_view line, std::int64_t now_ms) {
  if (command.end_step > kLastLegalStep) {
    reply(line, "04", now_ms);
    return;
  }
  if (command.end_step < command.start_step) {
    reply(line, "05", now_ms);
    return;
  }
  if (scip::is_stream_command(command.type)) {
    laser_on_ = true;  // MD/MS switch the laser on themselves
    reply(line, "00", now_ms);
    stream_.active = true;
    stream_.command = command;
    stream_.next_scan = first_scan_after(now_ms);
    stream_.unlimited = command.scan_count == 0;
    stream_.remaining = command.scan_count;
    return;
  }
  if (!laser_on_) {
    reply(line, "10", now_ms);
    return;
  }
  single_scans_.emplace_back(command, first_scan_after(now_ms));
}

std::int64_t UrgEmulator::next_due_ms() const {
  std::int64_t due = std::numeric_limits<std::int64_t>::max();
  if (stream_.active) due = scan_start_ms(stream_.next_scan) + period_ms_;
  if (!single_scans_.empty()) due = std::min(due, scan_start_ms(single_scans_.front().second) + period_ms_);
  return due;
}

void UrgEmulator::advance(std::int64_t now_ms) {
  while (true) {
    const std::int64_t due = next_due_ms();
    if (due > now_ms) return;
    const bool single_first = !single_scans_.empty() &&
                              scan_start_ms(single_scans_.front().second) + period_ms_ == due;
    if (single_first) {
      const auto [command, index] = single_scans_.front();
      single_scans_.pop_front();
      send_scan(command, "00", index, due);
      continue;
    }
    scip::Command echo = stream_.command;
    if (!stream_.unlimited) {
      --stream_.remaining;
      const std::string count = std::to_string(stream_.remaining);
      echo.text.replace(13, 2, (count.size() < 2 ? "0" : "") + count);  // the echo counts the scans left
      echo.scan_count = stream_.remaining;
    }
    const std::uint64_t index = stream_.next_scan;
    stream_.next_scan += static_cast<std::uint64_t>(stream_.command.scan_interval + 1);
    send_scan(echo, "99", index, due);
    if (!stream_.unlimited && stream_.remaining <= 0) {
      stop_stream();
      laser_on_ = false;  // the laser goes off after the last requested scan
    }
  }
}

void UrgEmulator::send_scan(const scip::Command& echo, std::string_view status, std::uint64_t index,
                            std::int64_t send_ms) {
  const scip::ScipParameters& p = options_.parameters;
  const std::int64_t start_ms = scan_start_ms(index);
  source_.scan(index, static_cast<double>(start_ms) * 1e-3, step_values_);
  // Steps outside AMIN..AMAX carry the dead-zone code; a cluster sends the
  // smallest valid value, or the smallest code when none is valid.
  const int cluster = std::max(1, echo.cluster);
  values_.clear();
  for (int first = echo.start_step; first <= echo.end_step; first += cluster) {
    std::uint32_t best_valid = std::numeric_limits<std::uint32_t>::max();
    std::uint32_t best_code = std::numeric_limits<std::uint32_t>::max();
    for (int step = first; step < first + cluster && step <= echo.end_step; ++step) {
      const bool measured = step >= p.first_step && step <= p.last_step &&
                            static_cast<std::size_t>(step - p.first_step) < step_values_.size();
      std::uint32_t v = measured ? step_values_[static_cast<std::size_t>(step - p.first_step)] : kNonMeasurable;
      if (scip::chars_per_value(echo.type) == 2) v = std::min<std::uint32_t>(v, 4095);
      if (v >= static_cast<std::uint32_t>(p.min_distance_mm)) {
        best_valid = std::min(best_valid, v);
      } else {
        best_code = std::min(best_code, v);
      }
    }
    values_.push_back(best_valid != std::numeric_limits<std::uint32_t>::max() ? best_valid : best_code);
  }
  EmulatorOutput& out = output_.emplace_back();
  out.time_ms = send_ms;
  out.is_scan = true;
  out.scan_index = index;
  out.scan_start_ms = start_ms;
  out.timestamp_ms = sensor_time_ms(start_ms);
  scip::append_distance_frame(echo.text, status, out.timestamp_ms, values_, scip::chars_per_value(echo.type),
                              out.bytes);
}

}  // namespace stridemap
