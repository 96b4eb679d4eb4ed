#include "stridemap/live/scan_recorder.hpp"

#include "stridemap/core/error.hpp"

namespace stridemap {

ScanRecorder::ScanRecorder(const std::string& path, const std::string& device, bool append,
                           const LiveScanSource& sensor)
    : log_(std::make_unique<io::ScanLogWriter>(path, device, append)) {
  log_->write_sensor(live_host_seconds(), sensor.version(), sensor.parameters());
}

template <typename Write>
bool ScanRecorder::attempt(Write&& write) {
  if (!recording()) return true;
  try {
    write(*log_);
  } catch (const InputError& e) {
    error_ = e.what();
    return false;
  }
  return true;
}

bool ScanRecorder::scan(const UrgScan& scan) {
  return attempt([&](io::ScanLogWriter& log) { log.write_scan(scan); });
}

bool ScanRecorder::event(const LiveEvent& event, const LiveScanSource& sensor) {
  switch (event.kind) {
    case LiveEvent::Kind::fault:
      return attempt([&](io::ScanLogWriter& log) {
        log.write_fault(live_host_seconds(), event.driver_event->fault, event.driver_event->count, event.message);
      });
    case LiveEvent::Kind::connected:
      return attempt([&](io::ScanLogWriter& log) {
        log.write_sensor(live_host_seconds(), sensor.version(), sensor.parameters());
      });
    default:
      return true;
  }
}

bool ScanRecorder::flush() {
  return attempt([](io::ScanLogWriter& log) { log.flush(); });
}

}  // namespace stridemap
