// The driver's reactions to decoded replies: the start-up sequence, and the
// stream's scans, gaps, errors and resets.
#include <cmath>
#include <cstdio>

#include "stridemap/core/error.hpp"
#include "stridemap/sensors/scip_status.hpp"
#include "stridemap/sensors/urg_driver.hpp"

namespace stridemap {
namespace {

std::string status_text(const scip::Reply& reply) {
  return "status '" + reply.status + "' (" + std::string(scip::status_meaning(reply.echo.type, reply.status)) + ")";
}

}  // namespace

void UrgDriver::refuse_start(UrgFault fault, const std::string& what) {
  report(fault, device() + ": " + what);
  close_device();
  next_open_time_ = now() + options_.reconnect_interval_s;
}

void UrgDriver::take_version_reply(const scip::Event& event) {
  if (event.kind != scip::EventKind::info) {
    refuse_start(UrgFault::command_failed, "VV answered with " + status_text(event.reply));
    return;
  }
  try {
    version_ = scip::parse_version(event.info);
  } catch (const InputError& e) {
    refuse_start(UrgFault::bad_reply, e.what());
    return;
  }
  send_step(Step::parameters);
}

void UrgDriver::take_parameters_reply(const scip::Event& event) {
  if (event.kind != scip::EventKind::info) {
    refuse_start(UrgFault::command_failed, "PP answered with " + status_text(event.reply));
    return;
  }
  try {
    const scip::ScipParameters parameters = scip::parse_parameters(event.info);
    const UrgParameters urg = scip::to_urg_parameters(parameters);
    urg.validate();
    scip::ScanRequest request;
    request.start_step = options_.start_step >= 0 ? options_.start_step : urg.first_step;
    request.end_step = options_.end_step >= 0 ? options_.end_step : urg.last_step;
    request.cluster = options_.cluster;
    request.two_char_values = options_.two_char_values;
    if (request.start_step < urg.first_step || request.end_step > urg.last_step ||
        request.end_step < request.start_step) {
      refuse_start(UrgFault::bad_reply, "requested steps " + std::to_string(request.start_step) + ".." +
                                            std::to_string(request.end_step) + " are outside the sensor's AMIN..AMAX " +
                                            std::to_string(urg.first_step) + ".." + std::to_string(urg.last_step));
      return;
    }
    parameters_ = parameters;
    urg_parameters_ = urg;
    std::string command = scip::stream_command(request, options_.scan_interval, 0);
    command.pop_back();  // the LF
    stream_command_ = scip::parse_command(command);
  } catch (const InputError& e) {
    refuse_start(UrgFault::bad_reply, e.what());
    return;
  }
  clock_.set_fixed_delay(options_.send_delay_s >= 0.0 ? options_.send_delay_s : urg_parameters_.scan_period_s);
  send_step(Step::laser_on);
}

void UrgDriver::take_stream_start_reply(const scip::Event& event) {
  const scip::Reply& reply = event.reply;
  // A data frame of our stream before its acknowledgement means the ack
  // was lost on the way: the stream runs, so take it (frames of an older
  // stream came before the QT reply and are behind us).
  const bool data_first = event.kind == scip::EventKind::distance && scip::echo_matches(stream_command_, reply.echo);
  if (!data_first && (event.kind != scip::EventKind::status_reply || reply.status != "00")) {
    if (event.kind == scip::EventKind::distance) return;  // another command's frame
    refuse_start(UrgFault::command_failed, stream_command_.text + " answered with " + status_text(reply));
    return;
  }
  state_ = UrgDriverState::streaming;
  stall_deadline_ = now() + stall_timeout_s();
  ++stats_.connects;
  UrgDriverEvent& connected = push_event(UrgDriverEvent::Kind::connected);
  connected.message = device() + ": " + version_.product + ", serial " + version_.serial + ", firmware " +
                      version_.firmware + "; steps " + std::to_string(stream_command_.start_step) + ".." +
                      std::to_string(stream_command_.end_step) + ", cluster " +
                      std::to_string(std::max(1, stream_command_.cluster)) + ", " +
                      std::to_string(parameters_.motor_speed_rpm) + " rpm";
  if (data_first) deliver_scan(event);
}

void UrgDriver::handle_start_reply(const scip::Event& event) {
  if (event.kind == scip::EventKind::error) {
    // Stale bytes from before the start (a stream left running, a half
    // frame): expected, but kept for the message if nothing sensible follows.
    last_decode_error_ = event.error.message;
    return;
  }
  const scip::Reply& reply = event.reply;
  const scip::CommandType type = reply.echo.type;
  // A one-character status to anything but QT or SCIP2.0 means the sensor
  // fell back to SCIP 1.1 (it restarted) while we were starting it.
  if (scip::is_scip11_status(reply.status) && step_ != Step::probe && step_ != Step::switch_scip2) {
    begin_start();
    return;
  }
  switch (step_) {
    case Step::probe:
      if (type != scip::CommandType::laser_off) return;  // a running stream's frames, stale replies
      if (reply.status == "00") {
        send_step(Step::version);
      } else if (scip::is_scip11_status(reply.status)) {
        send_step(Step::switch_scip2);
      } else if (reply.status == "0E") {
        send_step(Step::leave_time_mode);  // TM adjust mode refuses QT (official library's probe)
      } else {
        refuse_start(UrgFault::command_failed, "QT answered with " + status_text(reply));
      }
      return;
    case Step::switch_scip2:
      if (type != scip::CommandType::switch_to_scip2) return;
      if (scip::switched_to_scip2(reply)) {
        send_step(Step::version);
      } else {
        refuse_start(UrgFault::command_failed, "SCIP2.0 answered with " + status_text(reply));
      }
      return;
    case Step::leave_time_mode:
      if (type != scip::CommandType::time) return;
      if (scip::succeeded(reply)) {
        send_step(Step::version);
      } else {
        refuse_start(UrgFault::command_failed, "TM2 answered with " + status_text(reply));
      }
      return;
    case Step::version:
      if (type == scip::CommandType::version) take_version_reply(event);
      return;
    case Step::parameters:
      if (type == scip::CommandType::parameters) take_parameters_reply(event);
      return;
    case Step::laser_on:
      if (type != scip::CommandType::laser_on) return;
      if (scip::succeeded(reply)) {
        send_step(Step::start_stream);
      } else {
        refuse_start(UrgFault::command_failed, "BM answered with " + status_text(reply));
      }
      return;
    case Step::start_stream:
      if (scip::is_stream_command(type)) take_stream_start_reply(event);
      return;
  }
}

void UrgDriver::handle_stream_event(const scip::Event& event) {
  switch (event.kind) {
    case scip::EventKind::error:
      ++stats_.corrupt_frames;
      report(UrgFault::corrupt_data, device() + ": " + event.error.message);
      return;
    case scip::EventKind::distance:
      if (scip::is_stream_command(event.reply.echo.type) && scip::echo_matches(stream_command_, event.reply.echo)) {
        deliver_scan(event);
      }
      return;
    case scip::EventKind::status_reply: {
      const scip::Reply& reply = event.reply;
      if (scip::is_scip11_status(reply.status)) {
        ++stats_.resets;
        restart_stream(UrgFault::sensor_reset, device() + ": the sensor answers in SCIP 1.1 again: it restarted", 0);
        return;
      }
      if (!scip::echo_matches(stream_command_, reply.echo) || reply.status == "00" || reply.status == "98") return;
      report(UrgFault::sensor_error, device() + ": " + reply.echo.text + " frame with " + status_text(reply));
      return;
    }
    case scip::EventKind::info:
    case scip::EventKind::time: return;
  }
}

void UrgDriver::deliver_scan(const scip::Event& event) {
  const std::uint32_t raw_ms = event.distance.timestamp_ms;
  const double receive_s = last_read_host_s_;
  bool first = !have_previous_scan_;
  std::uint64_t lost = 0;
  if (have_previous_scan_) {
    const std::uint32_t delta_ms = (raw_ms - previous_raw_ms_) & (scip::TimestampUnwrapper::kPeriodMs - 1);
    const double host_ms = (receive_s - previous_receive_s_) * 1000.0;
    if (delta_ms == 0) {
      report(UrgFault::duplicate_scan,
             device() + ": scan with the timestamp " + std::to_string(raw_ms) + " ms of the previous one; dropped");
      return;
    }
    // The two clocks run at the same rate; a sensor time step far from the
    // host's means the sensor's counter restarted (RS, power loss). But a
    // sensor that restarts stops streaming, so between two scans of one
    // stream the sensor's clock cannot have fallen behind: a host time step
    // longer than the sensor's there is the host reading late (a loaded
    // machine; the scans waited in the port), not a reset.
    const bool same_stream = previous_scan_start_ == stream_starts_;
    const bool consistent = delta_ms <= host_ms * 1.05 + 500.0 && (same_stream || delta_ms + 500.0 >= host_ms * 0.95);
    if (!consistent) {
      ++stats_.resets;
      const auto missed = static_cast<std::uint64_t>(
          std::max(0.0, std::floor(host_ms / 1000.0 / scans_period_s() + 0.5) - 1.0));
      char text[200];
      std::snprintf(text, sizeof text,
                    ": the sensor's clock went from %u to %u ms while %.3f s passed here: it restarted; "
                    "about %llu scans missed (from host time)",
                    previous_raw_ms_, raw_ms, host_ms / 1000.0, static_cast<unsigned long long>(missed));
      // The scans of the outage are lost as surely as those a timestamp gap
      // shows; only their number is an estimate.
      stats_.scans_lost += missed;
      stats_.scans_lost_by_host_time += missed;
      report(UrgFault::sensor_reset, device() + text, missed);
      unwrapper_.reset();
      clock_.reset();
      first = true;
    } else {
      const double expected_ms = scans_period_s() * 1000.0;
      const double periods = std::floor(static_cast<double>(delta_ms) / expected_ms + 0.5);
      if (periods > 1.0) {
        lost = static_cast<std::uint64_t>(periods) - 1;
        stats_.scans_lost += lost;
        report(UrgFault::scans_lost,
               device() + ": " + std::to_string(lost) + " scan(s) missing between sensor times " +
                   std::to_string(previous_raw_ms_) + " and " + std::to_string(raw_ms) + " ms",
               lost);
      }
    }
  }
  previous_raw_ms_ = raw_ms;
  previous_receive_s_ = receive_s;
  previous_scan_start_ = stream_starts_;
  have_previous_scan_ = true;
  stall_deadline_ = now() + stall_timeout_s();

  UrgDriverEvent& e = push_event(UrgDriverEvent::Kind::scan);
  UrgScan& scan = e.scan;
  scan.sensor_timestamp_ms = raw_ms;
  scan.sensor_time_ms = unwrapper_.unwrap(raw_ms);
  scan.host_receive_time_s = receive_s;
  scan.host_time_s = clock_.add(static_cast<double>(scan.sensor_time_ms) * 1e-3, receive_s);
  scan.lost_before = lost;
  scan.first_after_start = first;
  scan.sequence = stats_.scans++;
  scip::to_urg_raw_scan(event, scan.host_time_s, scan.raw);
}

}  // namespace stridemap
