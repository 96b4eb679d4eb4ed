// `stridemap record`: scans from a URG (or the emulator) into a scan log,
// with the sensor's parameters, every fault, and timestamps (docs/live.md).
#include <cstdio>
#include <memory>
#include <string>

#include "commands.hpp"
#include "stridemap/core/printable_text.hpp"
#include "output_guard.hpp"
#include "stridemap/recordings/scan_log.hpp"
#include "urg_device.hpp"

namespace stridemap::cli {
namespace {

struct RecordArgs {
  DeviceArgs device;
  std::string out_path;
  bool overwrite = false;
  bool append = false;
};

void run_record(const RecordArgs& args) {
  install_stop_signals();
  const ExistingLog choice = existing_log_choice(args.overwrite, args.append);
  refuse_output_that_is_an_input("--out", args.out_path, {{"--device", args.device.device}});
  check_log_output("--out", args.out_path, choice, "stridemap-urg-log");
  UrgDriverEvent event;
  std::unique_ptr<UrgDriver> driver = start_driver(args.device, event);
  std::fprintf(stderr, "stridemap: connected: %s\n", printable_text(event.message).c_str());
  // Only now, with the sensor streaming, is the log created or opened.
  io::ScanLogWriter log(args.out_path, args.device.device, choice == ExistingLog::append);
  log.write_sensor(host_seconds(), driver->version(), driver->parameters());
  const double start = monotonic_seconds();
  double next_status = start + 1.0;
  std::uint64_t scans = 0;
  while (!stop_requested()) {
    const double now = monotonic_seconds();
    if (args.device.duration_s > 0.0 && now - start >= args.device.duration_s) break;
    if (args.device.max_scans > 0 && scans >= args.device.max_scans) break;
    if (now >= next_status) {
      const UrgDriverStats& s = driver->stats();
      std::fprintf(stderr, "record: %llu scans (%.1f/s), %llu lost, %llu faults\n",
                   static_cast<unsigned long long>(s.scans), static_cast<double>(s.scans) / (now - start),
                   static_cast<unsigned long long>(s.scans_lost), static_cast<unsigned long long>(s.faults));
      next_status = now + 5.0;
    }
    if (!driver->next(event, 0.1)) continue;
    switch (event.kind) {
      case UrgDriverEvent::Kind::scan:
        log.write_scan(event.scan);
        ++scans;
        break;
      case UrgDriverEvent::Kind::fault:
        print_fault(event);
        log.write_fault(host_seconds(), event.fault, event.count, event.message);
        break;
      case UrgDriverEvent::Kind::connected:
        std::fprintf(stderr, "stridemap: connected: %s\n", printable_text(event.message).c_str());
        log.write_sensor(host_seconds(), driver->version(), driver->parameters());
        break;
    }
  }
  driver->stop();
  log.flush();
  const UrgDriverStats& s = driver->stats();
  std::printf("recorded %llu scans into %s (%llu lost, %llu faults)\n", static_cast<unsigned long long>(scans),
              args.out_path.c_str(), static_cast<unsigned long long>(s.scans_lost),
              static_cast<unsigned long long>(s.faults));
}

}  // namespace

void register_record(CLI::App& app) {
  auto args = std::make_shared<RecordArgs>();
  CLI::App* record = app.add_subcommand("record", "Record scans from a URG-04LX into a scan log (docs/live.md)");
  add_device_options(*record, args->device);
  record->add_option("--out", args->out_path, "Scan log to write (text, one record per line)")->required();
  add_existing_log_flags(*record, args->overwrite, args->append);
  record->callback([args] { run_record(*args); });
}

}  // namespace stridemap::cli
