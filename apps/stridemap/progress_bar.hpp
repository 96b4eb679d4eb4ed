#pragma once
// A one-line progress bar with rate and time left, for commands that run
// longer than a second. Drawn only on a terminal: to a file or a pipe (a
// script, a test capturing stderr) it writes nothing at all, so logs hold
// only the messages that matter.
#include <chrono>
#include <cstddef>
#include <cstdio>
#include <string>

#include "stridemap/core/progress.hpp"

namespace stridemap::io {

/// The bar's text for `done` of `total` after `elapsed_s`, e.g.
/// "rocky-walk  42% [########           ] 420/1000 scans, 83.1 scans/s, 0:07 left".
/// total 0 (unknown): no bar, no time left. Rate and time left appear once
/// something is done.
std::string progress_line(const std::string& label, std::size_t done, std::size_t total, const std::string& unit,
                          double elapsed_s);
/// "0:07", "12:05", "1:02:03"; "?" for a negative or non-finite time.
std::string duration_text(double seconds);

class ProgressBar {
 public:
  /// Draws on `out` only when `enabled`; for_stderr() decides that. Nothing
  /// is drawn before `show_after_s`: a short command shows no bar.
  ProgressBar(std::string label, std::string unit, std::FILE* out, bool enabled, double show_after_s = 1.0);
  /// A bar on stderr, enabled when stderr is a terminal and `quiet` is off.
  static ProgressBar for_stderr(std::string label, std::string unit, bool quiet);
  /// Ends the line, if one was drawn.
  ~ProgressBar();
  ProgressBar(const ProgressBar&) = delete;
  ProgressBar& operator=(const ProgressBar&) = delete;

  /// Redraws at most ten times a second (and on the last step).
  void update(std::size_t done, std::size_t total);
  /// Clears the bar's line, so that a message can be printed; the next
  /// update() draws it again.
  void clear();
  /// update() as a ProgressCallback for a library options struct; the bar
  /// must outlive it.
  ProgressCallback callback();
  bool enabled() const { return enabled_; }

 private:
  using Clock = std::chrono::steady_clock;
  std::string label_, unit_;
  std::FILE* out_;
  bool enabled_;
  double show_after_s_;
  bool drawn_ = false;
  Clock::time_point start_ = Clock::now();
  Clock::time_point last_draw_{};
};

}  // namespace stridemap::io
