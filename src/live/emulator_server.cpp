#include "stridemap/live/emulator_server.hpp"

#include <algorithm>
#include <cerrno>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <memory>
#include <random>
#include <thread>

#include "stridemap/core/error.hpp"
#include "stridemap/devices/pseudo_terminal.hpp"
#include "stridemap/recordings/pose_stream.hpp"
#include "stridemap/sensors/urg_driver.hpp"

namespace stridemap {
namespace {

using SteadyClock = std::chrono::steady_clock;

class OutputFile {
 public:
  OutputFile(const std::string& path, const char* what) : path_(path) {
    if (path.empty()) return;
    file_ = std::fopen(path.c_str(), "w");
    if (file_ == nullptr) throw InputError(path + ": cannot create the " + what + ": " + std::strerror(errno));
  }
  ~OutputFile() {
    if (file_ != nullptr) std::fclose(file_);
  }
  OutputFile(const OutputFile&) = delete;
  OutputFile& operator=(const OutputFile&) = delete;
  bool open() const { return file_ != nullptr; }
  void line(const std::string& text) {
    if (file_ == nullptr) return;
    std::fputs(text.c_str(), file_);
    std::fputc('\n', file_);
    std::fflush(file_);  // a reader (the pose pipe, a test) sees each line as it happens
  }

 private:
  std::string path_;
  std::FILE* file_ = nullptr;
};

std::string escaped(std::string_view bytes) {
  std::string out;
  for (const char c : bytes) {
    if (c == '\n') {
      out += "\\n";
    } else if (c == '\r') {
      out += "\\r";
    } else if (c < 0x20 || c > 0x7E || c == '"' || c == '\\') {
      char hex[8];
      std::snprintf(hex, sizeof hex, "\\x%02x", static_cast<unsigned char>(c));
      out += hex;
    } else {
      out += c;
    }
  }
  return out;
}

// Replaces one byte of the data lines (after echo, status and timestamp)
// with another data character: the line's checksum no longer matches.
void corrupt_frame(std::string& bytes, std::mt19937_64& rng) {
  std::size_t start = 0;
  for (int line = 0; line < 3 && start != std::string::npos; ++line) {
    start = bytes.find('\n', start);
    if (start != std::string::npos) ++start;
  }
  if (start == std::string::npos || start >= bytes.size()) return;
  std::vector<std::size_t> candidates;
  for (std::size_t i = start; i < bytes.size(); ++i) {
    if (bytes[i] != '\n') candidates.push_back(i);
  }
  if (candidates.empty()) return;
  const std::size_t at = candidates[rng() % candidates.size()];
  const int old_value = static_cast<unsigned char>(bytes[at]) - 0x30;
  const int shift = 1 + static_cast<int>(rng() % 63);
  bytes[at] = static_cast<char>(0x30 + ((old_value + shift) % 64 + 64) % 64);
}

}  // namespace

std::string_view emulator_fault_name(EmulatorFaultKind kind) {
  switch (kind) {
    case EmulatorFaultKind::corrupt: return "corrupt";
    case EmulatorFaultKind::drop: return "drop";
    case EmulatorFaultKind::stall: return "stall";
    case EmulatorFaultKind::disconnect: return "disconnect";
    case EmulatorFaultKind::reset: return "reset";
  }
  return "unknown";
}

EmulatorFault parse_emulator_fault(const std::string& text) {
  const auto bad = [&](const std::string& what) -> EmulatorFault {
    throw InputError("--fault '" + text + "': " + what +
                     " (expected KIND@FRAME[:SECONDS], KIND one of corrupt, drop, stall, disconnect, reset)");
  };
  const std::size_t at = text.find('@');
  if (at == std::string::npos) return bad("no '@'");
  EmulatorFault fault;
  const std::string kind = text.substr(0, at);
  bool found = false;
  for (const auto k : {EmulatorFaultKind::corrupt, EmulatorFaultKind::drop, EmulatorFaultKind::stall,
                       EmulatorFaultKind::disconnect, EmulatorFaultKind::reset}) {
    if (kind == emulator_fault_name(k)) {
      fault.kind = k;
      found = true;
    }
  }
  if (!found) return bad("unknown fault '" + kind + "'");
  const std::size_t colon = text.find(':', at);
  const std::string frame = text.substr(at + 1, colon == std::string::npos ? std::string::npos : colon - at - 1);
  char* end = nullptr;
  errno = 0;
  const unsigned long long n = std::strtoull(frame.c_str(), &end, 10);
  if (frame.empty() || *end != '\0' || errno != 0 || n == 0 || frame[0] == '-') {
    return bad("frame '" + frame + "' is not a whole number >= 1");
  }
  fault.at_frame = n;
  const bool timed = fault.kind == EmulatorFaultKind::stall || fault.kind == EmulatorFaultKind::disconnect;
  if (colon != std::string::npos) {
    if (!timed) return bad("only stall and disconnect take a duration");
    const std::string seconds = text.substr(colon + 1);
    const double d = std::strtod(seconds.c_str(), &end);
    if (seconds.empty() || *end != '\0' || !std::isfinite(d) || d <= 0.0 || d > 3600.0) {
      return bad("duration '" + seconds + "' is not a number of seconds in (0, 3600]");
    }
    fault.duration_s = d;
  }
  return fault;
}

void EmulatorServerOptions::validate() const {
  if (link_path.empty()) throw InputError("emulate-urg: --link is required");
  const auto probability = [](const char* name, double p) {
    if (!(p >= 0.0 && p <= 1.0)) throw InputError(std::string(name) + " must be a probability in [0, 1]");
  };
  probability("--corrupt-probability", corrupt_probability);
  probability("--drop-probability", drop_probability);
  if (!(std::isfinite(max_duration_s) && max_duration_s >= 0.0)) throw InputError("--duration-s must be >= 0");
  if (!(std::isfinite(poses_rate_hz) && poses_rate_hz >= 0.0 && poses_rate_hz <= 1000.0)) {
    throw InputError("--poses-rate-hz must be in [0, 1000]");
  }
}

namespace {

// One run of the server: the link, the emulator's clock and the faults'
// state between turns of its loop.
class EmulatorSession {
 public:
  EmulatorSession(UrgEmulator& emulator, const MotionSource* motion, const EmulatorServerOptions& options,
                  const std::function<void(const std::string&)>& log)
      : emulator_(emulator),
        motion_(motion),
        options_(options),
        log_(log),
        faults_(options.faults),
        trace_(options.trace_path, "trace file"),
        poses_(options.poses_path, "pose file"),
        rng_(options.fault_seed),
        pose_period_ms_(options.poses_rate_hz > 0.0 ? 1000.0 / options.poses_rate_hz : 0.0) {
    std::stable_sort(faults_.begin(), faults_.end(),
                     [](const EmulatorFault& a, const EmulatorFault& b) { return a.at_frame < b.at_frame; });
    if (poses_.open()) {
      std::string header = io::pose_file_header();
      header.pop_back();
      poses_.line(header);
    }
    host_epoch_s_ = std::chrono::duration<double>(std::chrono::system_clock::now().time_since_epoch()).count();
    t0_ = SteadyClock::now();
    pty_ = std::make_unique<io::PseudoTerminal>(options.link_path);
    emulator_.power_cycle(0);
    event(0, "start link=" + options.link_path + " client=" + pty_->client_path());
    say("emulating a URG-04LX on " + options.link_path + " (" + pty_->client_path() + ")");
  }

  // One turn of the loop; false once a limit is reached.
  bool step() {
    std::int64_t now = elapsed_ms();
    write_due_poses(now);
    if (options_.max_duration_s > 0.0 && static_cast<double>(now) >= options_.max_duration_s * 1000.0) return false;
    if (options_.max_frames > 0 && stats_.frames >= options_.max_frames && pending_.empty()) return false;
    if (mode_ == Mode::unplugged) {
      if (now < resume_ms_) {
        std::this_thread::sleep_for(std::chrono::milliseconds(std::min<std::int64_t>(20, resume_ms_ - now)));
        return true;
      }
      reconnect(now);
    }
    if (mode_ == Mode::stalled && now >= resume_ms_) {
      mode_ = Mode::running;
      event(now, "stall end");
      say("stall over");
    }
    now = exchange(now);
    bool discard_rest = false;
    for (EmulatorOutput& out : emulator_.output()) {
      if (discard_rest) break;
      if (!out.is_scan) {
        if (mode_ == Mode::running) pending_ += out.bytes;
        continue;
      }
      discard_rest = frame(out, now);
    }
    emulator_.output().clear();
    if (mode_ == Mode::running && !pending_.empty()) {
      const StreamResult put = pty_->write(pending_, std::chrono::milliseconds(0));
      pending_.erase(0, put.bytes);
    }
    return true;
  }

  EmulatorServerStats finish() {
    event(elapsed_ms(), "end frames=" + std::to_string(stats_.frames) + " sent=" + std::to_string(stats_.sent) +
                            " corrupted=" + std::to_string(stats_.corrupted) + " dropped=" +
                            std::to_string(stats_.dropped) + " lost=" + std::to_string(stats_.lost));
    return stats_;
  }

 private:
  enum class Mode { running, stalled, unplugged };

  std::int64_t elapsed_ms() const {
    return std::chrono::duration_cast<std::chrono::milliseconds>(SteadyClock::now() - t0_).count();
  }
  void event(std::int64_t ms, const std::string& what) { trace_.line(std::to_string(ms) + " " + what); }
  void say(const std::string& text) const {
    if (log_) log_(text);
  }

  void write_pose(std::int64_t at_ms) {
    if (!poses_.open() || motion_ == nullptr) return;
    TimedPose p;
    p.pose = motion_->pose_at(static_cast<double>(at_ms) * 1e-3);
    p.time_s = options_.pose_clock == PoseClock::host
                   ? host_epoch_s_ + static_cast<double>(at_ms) * 1e-3
                   : sensor_time_seconds(static_cast<std::uint64_t>(emulator_.unwrapped_sensor_time_ms(at_ms)));
    poses_.line(io::format_pose_line(p));
  }

  // The estimator's poses, whatever the sensor does (it runs on the robot, not in the URG).
  void write_due_poses(std::int64_t now) {
    for (; pose_period_ms_ > 0.0 && static_cast<double>(poses_written_) * pose_period_ms_ <= static_cast<double>(now);
         ++poses_written_) {
      write_pose(static_cast<std::int64_t>(std::llround(static_cast<double>(poses_written_) * pose_period_ms_)));
    }
  }

  void reconnect(std::int64_t now) {
    emulator_.power_cycle(now);  // power came back with the link: SCIP 1.1, laser off, clock restarted
    pty_ = std::make_unique<io::PseudoTerminal>(options_.link_path);
    mode_ = Mode::running;
    event(now, "reconnect client=" + pty_->client_path());
    say("link back on " + options_.link_path + " (" + pty_->client_path() + "); the sensor restarted");
  }

  // Reads the client's commands (or, stalled, lets time pass); returns the time after.
  std::int64_t exchange(std::int64_t now) {
    const std::int64_t due = emulator_.next_due_ms();
    std::int64_t wait = due == INT64_MAX ? 20 : std::clamp<std::int64_t>(due - now, 0, 20);
    if (!pending_.empty()) wait = std::min<std::int64_t>(wait, 2);
    if (mode_ == Mode::stalled) wait = std::min(wait, std::max<std::int64_t>(0, resume_ms_ - now));
    if (mode_ == Mode::running) {
      const StreamResult got = pty_->read(buffer_, std::chrono::milliseconds(wait));
      now = elapsed_ms();
      emulator_.advance(now);  // scans that ended before the command came
      if (got.bytes > 0) {
        const std::string_view bytes(buffer_, got.bytes);
        stats_.commands_bytes += got.bytes;
        event(now, "recv \"" + escaped(bytes) + "\"");
        emulator_.receive(bytes, now);
      }
    } else {
      // Stalled: deaf and mute, but the mirror turns and the clock runs.
      std::this_thread::sleep_for(std::chrono::milliseconds(wait));
      now = elapsed_ms();
      emulator_.advance(now);
    }
    return now;
  }

  // The faults due at this frame; true when they end the frames of this turn.
  bool apply_faults(std::int64_t now, bool& corrupt, bool& drop, std::string& fate) {
    bool discard_rest = false;
    for (; next_fault_ < faults_.size() && faults_[next_fault_].at_frame <= stats_.frames; ++next_fault_) {
      const EmulatorFault& f = faults_[next_fault_];
      switch (f.kind) {
        case EmulatorFaultKind::corrupt: corrupt = true; break;
        case EmulatorFaultKind::drop: drop = true; break;
        case EmulatorFaultKind::stall:
          mode_ = Mode::stalled;
          resume_ms_ = now + static_cast<std::int64_t>(f.duration_s * 1000.0);
          ++stats_.stalls;
          event(now, "stall begin duration_s=" + std::to_string(f.duration_s));
          say("stall for " + std::to_string(f.duration_s) + " s");
          break;
        case EmulatorFaultKind::disconnect:
          mode_ = Mode::unplugged;
          resume_ms_ = now + static_cast<std::int64_t>(f.duration_s * 1000.0);
          pty_.reset();
          pending_.clear();
          ++stats_.disconnects;
          event(now, "disconnect duration_s=" + std::to_string(f.duration_s));
          say("link gone for " + std::to_string(f.duration_s) + " s");
          discard_rest = true;
          break;
        case EmulatorFaultKind::reset:
          emulator_.power_cycle(now);
          ++stats_.resets;
          event(now, "reset");
          say("sensor reset");
          fate = "reset";
          discard_rest = true;
          break;
      }
    }
    return discard_rest;
  }

  // A scan frame the sensor produced: sent, damaged, dropped or lost, and
  // traced. True when the frames after it in this turn are discarded.
  bool frame(EmulatorOutput& out, std::int64_t now) {
    ++stats_.frames;
    if (pose_period_ms_ == 0.0) write_pose(out.scan_start_ms);
    bool corrupt = options_.corrupt_probability > 0.0 && unit_(rng_) < options_.corrupt_probability;
    bool drop = options_.drop_probability > 0.0 && unit_(rng_) < options_.drop_probability;
    std::string fate;
    const bool discard_rest = apply_faults(now, corrupt, drop, fate);
    if (fate.empty()) {
      if (mode_ == Mode::stalled) {
        fate = "stalled";
      } else if (mode_ == Mode::unplugged) {
        fate = "unplugged";
      } else if (drop) {
        fate = "dropped";
      }
    }
    if (fate.empty()) {
      if (corrupt) corrupt_frame(out.bytes, rng_);
      if (pty_->unread_by_client() + pending_.size() + out.bytes.size() > options_.max_unread_bytes) {
        fate = "overflow";
      } else {
        pending_ += out.bytes;
        fate = corrupt ? "corrupted" : "sent";
      }
    }
    if (fate == "sent") {
      ++stats_.sent;
    } else if (fate == "corrupted") {
      ++stats_.corrupted;
    } else if (fate == "dropped") {
      ++stats_.dropped;
    } else {
      ++stats_.lost;
    }
    event(now, "frame n=" + std::to_string(stats_.frames) + " scan=" + std::to_string(out.scan_index) +
                   " ts=" + std::to_string(out.timestamp_ms) +
                   " sensor_ms=" + std::to_string(emulator_.unwrapped_sensor_time_ms(out.scan_start_ms)) +
                   " fate=" + fate);
    return discard_rest;
  }

  UrgEmulator& emulator_;
  const MotionSource* motion_;
  const EmulatorServerOptions& options_;
  const std::function<void(const std::string&)>& log_;
  std::vector<EmulatorFault> faults_;  // by frame
  OutputFile trace_;
  OutputFile poses_;
  double host_epoch_s_ = 0.0;
  SteadyClock::time_point t0_;
  EmulatorServerStats stats_;
  std::unique_ptr<io::PseudoTerminal> pty_;
  Mode mode_ = Mode::running;
  std::int64_t resume_ms_ = 0;
  std::mt19937_64 rng_;
  std::uniform_real_distribution<double> unit_{0.0, 1.0};
  std::size_t next_fault_ = 0;
  std::string pending_;
  const double pose_period_ms_;
  std::int64_t poses_written_ = 0;
  char buffer_[1024];
};

}  // namespace

EmulatorServerStats run_emulator_server(UrgEmulator& emulator, const MotionSource* motion,
                                        const EmulatorServerOptions& options, const std::atomic<bool>& stop,
                                        const std::function<void(const std::string&)>& log) {
  options.validate();
  EmulatorSession session(emulator, motion, options, log);
  while (!stop.load() && session.step()) {
  }
  return session.finish();
}

}  // namespace stridemap
