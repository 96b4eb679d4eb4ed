#pragma once
// What `stridemap live` tells on stderr while it maps: the status line
// (rewritten in place on a terminal) and the loop's events.
#include <string>

#include "stridemap/live/live_mapping.hpp"

namespace stridemap::cli {

class LiveConsole {
 public:
  /// `driver` and `poses` feed the status line and must outlive the console.
  LiveConsole(const UrgDriver& driver, const LivePoseSource& poses);

  void show(const LiveEvent& event, const ScanMapper& mapper) const;
  /// "stridemap: warning: <text>", on a line of its own.
  void warn(const std::string& text) const;
  /// Ends the status line before the summary.
  void finish() const;

 private:
  void status(const ScanMapper& mapper) const;
  const char* line_break() const { return tty_ ? "\n" : ""; }

  const UrgDriver& driver_;
  const LivePoseSource& poses_;
  bool tty_ = false;
  double start_s_ = 0.0;
};

}  // namespace stridemap::cli
