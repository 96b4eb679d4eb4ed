#include "live_console.hpp"

#include <unistd.h>

#include <algorithm>
#include <cstdio>

#include "terminal_output.hpp"
#include "urg_device.hpp"
#include "stridemap/core/printable_text.hpp"

namespace stridemap::cli {

LiveConsole::LiveConsole(const UrgDriver& driver, const LivePoseSource& poses)
    : driver_(driver), poses_(poses), tty_(::isatty(STDERR_FILENO) != 0), start_s_(monotonic_seconds()) {}

void LiveConsole::status(const ScanMapper& mapper) const {
  if (verbosity().quiet) return;
  const UrgDriverStats& d = driver_.stats();
  const double now = monotonic_seconds();
  std::fprintf(stderr,
               "%slive: %.1f scans/s, %llu scans, %llu lost, %llu faults, %zu mapped, %zu waiting for poses, "
               "%zu pose lines skipped%s",
               tty_ ? "\r" : "", static_cast<double>(d.scans) / std::max(1e-9, now - start_s_),
               static_cast<unsigned long long>(d.scans), static_cast<unsigned long long>(d.scans_lost),
               static_cast<unsigned long long>(d.faults), mapper.stats().integrated, mapper.waiting(),
               poses_.skipped_lines(), tty_ ? "\x1b[K" : "\n");
}

void LiveConsole::show(const LiveEvent& e, const ScanMapper& mapper) const {
  switch (e.kind) {
    case LiveEvent::Kind::status:
      status(mapper);
      break;
    case LiveEvent::Kind::fault:
      if (tty_) std::fputc('\n', stderr);
      print_fault(*e.driver_event);
      break;
    case LiveEvent::Kind::connected:
      break;
    case LiveEvent::Kind::pose_notice:
      std::fprintf(stderr, "%sstridemap: warning: pose skipped or reopened: %s\n", line_break(), printable_text(e.message).c_str());
      break;
    case LiveEvent::Kind::save_failed:
      std::fprintf(stderr, "%sstridemap: warning: saving the map failed, retrying while mapping goes on: %s\n",
                   line_break(), printable_text(e.message).c_str());
      break;
    case LiveEvent::Kind::save_recovered:
      std::fprintf(stderr, "%sstridemap: %s\n", line_break(), printable_text(e.message).c_str());
      break;
    case LiveEvent::Kind::warning:
      warn(e.message);
      break;
  }
}

void LiveConsole::warn(const std::string& text) const {
  std::fprintf(stderr, "%sstridemap: warning: %s\n", line_break(), printable_text(text).c_str());
}

void LiveConsole::finish() const {
  if (tty_) std::fputc('\n', stderr);
}

}  // namespace stridemap::cli
