#include "progress_bar.hpp"

#include <unistd.h>

#include <algorithm>
#include <cmath>
#include <utility>

namespace stridemap::io {
namespace {

constexpr int kProgressBarWidth = 20;
constexpr double kRedrawEveryS = 0.1;

}  // namespace

std::string duration_text(double seconds) {
  if (!std::isfinite(seconds) || seconds < 0.0) return "?";
  const auto whole = static_cast<long long>(std::llround(seconds));
  char text[32];
  if (whole >= 3600) {
    std::snprintf(text, sizeof text, "%lld:%02lld:%02lld", whole / 3600, whole / 60 % 60, whole % 60);
  } else {
    std::snprintf(text, sizeof text, "%lld:%02lld", whole / 60, whole % 60);
  }
  return text;
}

std::string progress_line(const std::string& label, std::size_t done, std::size_t total, const std::string& unit,
                          double elapsed_s) {
  std::string line = label;
  const double rate = elapsed_s > 0.0 ? static_cast<double>(done) / elapsed_s : 0.0;
  if (total > 0) {
    const double fraction = std::min(1.0, static_cast<double>(done) / static_cast<double>(total));
    const int filled = static_cast<int>(fraction * kProgressBarWidth);
    char percent[16];
    std::snprintf(percent, sizeof percent, " %3d%% [", static_cast<int>(fraction * 100.0));
    line += percent;
    line += std::string(static_cast<std::size_t>(filled), '#') + std::string(static_cast<std::size_t>(kProgressBarWidth - filled), ' ');
    line += "] " + std::to_string(done) + "/" + std::to_string(total) + " " + unit;
  } else {
    line += " " + std::to_string(done) + " " + unit;
  }
  if (done == 0 || !(rate > 0.0)) return line;
  char rate_text[32];
  std::snprintf(rate_text, sizeof rate_text, rate >= 10.0 ? "%.0f" : "%.2g", rate);
  line += std::string(", ") + rate_text + " " + unit + "/s";
  if (total > done) line += ", " + duration_text(static_cast<double>(total - done) / rate) + " left";
  return line;
}

ProgressBar::ProgressBar(std::string label, std::string unit, std::FILE* out, bool enabled, double show_after_s)
    : label_(std::move(label)),
      unit_(std::move(unit)),
      out_(out),
      enabled_(enabled && out != nullptr),
      show_after_s_(show_after_s) {}

ProgressBar ProgressBar::for_stderr(std::string label, std::string unit, bool quiet) {
  return ProgressBar(std::move(label), std::move(unit), stderr, !quiet && ::isatty(STDERR_FILENO) != 0);
}

ProgressBar::~ProgressBar() {
  if (drawn_) {
    std::fputc('\n', out_);
    std::fflush(out_);
  }
}

void ProgressBar::update(std::size_t done, std::size_t total) {
  if (!enabled_) return;
  const Clock::time_point now = Clock::now();
  const double elapsed_s = std::chrono::duration<double>(now - start_).count();
  if (elapsed_s < show_after_s_) return;
  // Without a total (a streamed input) the end is not known: redrawn at the same pace.
  if (drawn_ && std::chrono::duration<double>(now - last_draw_).count() < kRedrawEveryS && (total == 0 || done < total)) {
    return;
  }
  last_draw_ = now;
  drawn_ = true;
  // \r and erase-to-end: the line is redrawn in place.
  std::fprintf(out_, "\r%s\x1b[K", progress_line(label_, done, total, unit_, elapsed_s).c_str());
  std::fflush(out_);
}

void ProgressBar::clear() {
  if (!drawn_) return;
  std::fputs("\r\x1b[K", out_);
  std::fflush(out_);
  drawn_ = false;
}

ProgressCallback ProgressBar::callback() {
  if (!enabled_) return {};
  return [this](std::size_t done, std::size_t total) { update(done, total); };
}

}  // namespace stridemap::io
