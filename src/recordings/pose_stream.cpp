#include "stridemap/recordings/pose_stream.hpp"

#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

#include <array>
#include <cerrno>
#include <charconv>
#include <cmath>
#include <cstring>
#include <fstream>
#include <iterator>
#include <limits>
#include <utility>

#include "stridemap/core/error.hpp"
#include "stridemap/io/text_file.hpp"

namespace stridemap::io {
namespace {

constexpr const char* kColumns =
    "time_s x_m y_m yaw_rad pitch_rad roll_rad [reference_elevation_m [height_change_m [z_m]]]";

[[noreturn]] void throw_no_usable_pose(const std::string& source, const PoseLineProblems& problems) {
  const std::string why = problems.first.empty() ? "" : "; the first bad line: " + problems.first.front();
  throw InputError(source + ": no usable pose in the file (expected lines of " + kColumns + ")" + why);
}

std::string located(const std::string& source, std::size_t line, const std::string& what) {
  return source + ":" + std::to_string(line) + ": " + what;
}

void append_pose_number(double value, std::string& out) {
  char text[32];
  const auto [end, error] = std::to_chars(text, text + sizeof text, value);
  out.append(text, error == std::errc() ? end : text);
}

}  // namespace

bool parse_pose_line(std::string_view line, const std::string& source, std::size_t line_number, TimedPose& out) {
  if (!line.empty() && line.back() == '\r') line.remove_suffix(1);
  std::array<double, 9> values{};
  std::size_t count = 0;
  std::size_t pos = 0;
  while (true) {
    while (pos < line.size() && (line[pos] == ' ' || line[pos] == '\t')) ++pos;
    if (pos >= line.size()) break;
    if (count == 0 && line[pos] == '#') return false;
    std::size_t end = pos;
    while (end < line.size() && line[end] != ' ' && line[end] != '\t') ++end;
    const std::string_view field = line.substr(pos, end - pos);
    if (count == values.size()) {
      throw InputError(located(source, line_number, "more than 9 fields; expected " + std::string(kColumns)));
    }
    double value = 0.0;
    const auto [stop, error] = std::from_chars(field.data(), field.data() + field.size(), value);
    if (error != std::errc() || stop != field.data() + field.size() || !std::isfinite(value)) {
      throw InputError(located(source, line_number,
                               "field " + std::to_string(count + 1) + " '" + std::string(field) +
                                   "' is not a finite number"));
    }
    values[count++] = value;
    pos = end;
  }
  if (count == 0) return false;
  if (count < 6) {
    throw InputError(located(source, line_number,
                             std::to_string(count) + " fields; expected at least 6: " + std::string(kColumns)));
  }
  out.time_s = values[0];
  out.pose = TrunkPose{};
  out.pose.x_m = values[1];
  out.pose.y_m = values[2];
  out.pose.yaw_rad = values[3];
  out.pose.pitch_rad = values[4];
  out.pose.roll_rad = values[5];
  if (count > 6) out.pose.reference_elevation_m = values[6];
  if (count > 7) out.pose.height_change_m = values[7];
  if (count > 8) out.pose.z_m = values[8];
  return true;
}

std::string format_pose_line(const TimedPose& p) {
  std::string line;
  const double fields[] = {p.time_s,       p.pose.x_m,       p.pose.y_m,
                           p.pose.yaw_rad, p.pose.pitch_rad, p.pose.roll_rad,
                           p.pose.reference_elevation_m, p.pose.height_change_m, p.pose.z_m.value_or(0.0)};
  for (std::size_t i = 0; i < 9; ++i) {
    if (i == 6 && fields[6] == 0.0 && fields[7] == 0.0 && !p.pose.z_m) break;
    if (i == 8 && !p.pose.z_m) break;
    if (i) line += ' ';
    append_pose_number(fields[i], line);
  }
  return line;
}

std::string pose_file_header() { return std::string("# stridemap poses: ") + kColumns + "\n"; }

void PoseLineProblems::add(std::string message) {
  ++count;
  if (first.size() < kListed) first.push_back(std::move(message));
}

std::vector<TimedPose> parse_pose_text(std::string_view text, const std::string& source, PoseLineProblems* problems) {
  PoseTrack order_check(std::numeric_limits<double>::infinity());
  PoseLineBuffer lines(source);
  std::vector<TimedPose> poses;
  // The same line assembly as a live stream, so that a file and the same
  // bytes through a pipe are read alike; a last line without LF counts here
  // (the file is complete), unlike in a stream, where it waits.
  const auto keep = [&](const TimedPose& pose) {
    order_check.append(pose);
    order_check.drop_before(pose.time_s);
    poses.push_back(pose);
  };
  lines.feed(text, keep);
  lines.finish(keep);
  if (problems != nullptr) *problems = lines.problems();
  if (poses.empty()) throw_no_usable_pose(source, lines.problems());
  return poses;
}

std::vector<TimedPose> read_pose_file(const std::string& path, PoseLineProblems* problems) {
  refuse_folder(path, "the pose file");
  std::ifstream file(path, std::ios::binary);
  if (!file) throw InputError(path + ": cannot open the pose file: " + std::strerror(errno));
  const std::string text{std::istreambuf_iterator<char>(file), std::istreambuf_iterator<char>()};
  if (file.bad()) throw InputError(path + ": read error");
  return parse_pose_text(text, path, problems);
}

void PoseLineBuffer::complete_line(std::string_view line, const std::function<void(const TimedPose&)>& use) {
  ++line_number_;
  if (line.size() > kMaxPoseLineBytes) {
    too_long(line_number_);
    return;
  }
  TimedPose pose;
  try {
    if (!parse_pose_line(line, source_, line_number_, pose)) return;
  } catch (const InputError& e) {
    problems_.add(e.what());
    return;
  }
  try {
    use(pose);
  } catch (const InputError& e) {
    problems_.add(located(source_, line_number_, e.what()));
  }
}

void PoseLineBuffer::too_long(std::size_t line_number) {
  problems_.add(located(source_, line_number,
                        "line longer than " + std::to_string(kMaxPoseLineBytes) + " bytes: not a pose line"));
}

void PoseLineBuffer::feed(std::string_view bytes, const std::function<void(const TimedPose&)>& use) {
  while (!bytes.empty()) {
    const std::size_t lf = bytes.find('\n');
    if (discarding_) {
      // The rest of an overlong line, already reported: dropped up to its LF.
      if (lf == std::string_view::npos) return;
      discarding_ = false;
      bytes.remove_prefix(lf + 1);
      continue;
    }
    if (lf == std::string_view::npos) {
      // Held until its LF comes; never more than a line may hold.
      if (partial_.size() + bytes.size() > kMaxPoseLineBytes) {
        ++line_number_;
        too_long(line_number_);
        partial_.clear();
        discarding_ = true;
        return;
      }
      partial_.append(bytes);
      return;
    }
    if (partial_.empty()) {
      complete_line(bytes.substr(0, lf), use);
    } else {
      if (partial_.size() + lf > kMaxPoseLineBytes) {
        ++line_number_;
        too_long(line_number_);
      } else {
        partial_.append(bytes.substr(0, lf));
        complete_line(partial_, use);
      }
      partial_.clear();
    }
    bytes.remove_prefix(lf + 1);
  }
}

void PoseLineBuffer::finish(const std::function<void(const TimedPose&)>& use) {
  if (discarding_) {
    discarding_ = false;
    return;
  }
  if (partial_.empty()) return;
  const std::string line = std::move(partial_);
  partial_.clear();
  complete_line(line, use);
}

PoseStreamReader::PoseStreamReader(const std::string& path) : path_(path), lines_(path) {
  struct stat st{};
  if (::stat(path.c_str(), &st) != 0) throw InputError(path + ": cannot open the pose source: " + std::strerror(errno));
  if (!S_ISREG(st.st_mode) && !S_ISFIFO(st.st_mode)) {
    throw InputError(path + ": the pose source must be a regular file or a named pipe");
  }
  is_pipe_ = S_ISFIFO(st.st_mode);
  // Non-blocking: opening a pipe must not wait for its writer.
  fd_ = ::open(path.c_str(), O_RDONLY | O_NONBLOCK | O_CLOEXEC);
  if (fd_ < 0) throw InputError(path + ": cannot open the pose source: " + std::strerror(errno));
}

PoseStreamReader::~PoseStreamReader() {
  if (fd_ >= 0) ::close(fd_);
}

// A publisher that restarts either writes a new file (rename over, or
// delete and create: another inode) or truncates the old one (a size below
// what was read). Both mean: read it anew from its start.
bool PoseStreamReader::source_changed(std::string& why) {
  if (is_pipe_) return false;
  struct stat open_file {}, at_path {};
  if (::fstat(fd_, &open_file) != 0) return false;
  if (::stat(path_.c_str(), &at_path) != 0) return false;  // removed: keep the old one until a new file appears
  if (at_path.st_dev != open_file.st_dev || at_path.st_ino != open_file.st_ino) {
    why = "replaced by a new file";
    return S_ISREG(at_path.st_mode);
  }
  if (static_cast<std::uint64_t>(open_file.st_size) < offset_) {
    why = "cut to " + std::to_string(open_file.st_size) + " bytes after " + std::to_string(offset_) + " were read";
    return true;
  }
  return false;
}

void PoseStreamReader::reopen() {
  const int fd = ::open(path_.c_str(), O_RDONLY | O_NONBLOCK | O_CLOEXEC);
  if (fd < 0) return;  // try again at the next poll
  ::close(fd_);
  fd_ = fd;
  offset_ = 0;
  skipped_before_ += lines_.problems().count;
  reported_problems_ = 0;
  lines_ = PoseLineBuffer(path_);
  after_reopen_ = true;
  ++reopened_;
}

std::size_t PoseStreamReader::poll(PoseTrack& track) {
  if (std::string why; source_changed(why)) {
    reopen();
    notices_.push_back(path_ + ": " + why + " (a restarted pose publisher?); reading it again from the start, "
                       "poses before the last one kept are skipped");
  }
  // One pointer captured: std::function keeps it inline, so a poll allocates nothing.
  struct Sink {
    bool after_reopen;
    PoseTrack& track;
    std::size_t added = 0;
  } sink{after_reopen_, track};
  std::size_t& added = sink.added;
  char buffer[4096];
  const auto use = [s = &sink](const TimedPose& pose) {
    if (s->after_reopen && s->track.size() > 0 && !(pose.time_s > s->track.last_time_s())) return;  // known already
    s->track.append(pose);
    ++s->added;
  };
  while (true) {
    const ssize_t got = ::read(fd_, buffer, sizeof buffer);
    if (got < 0 && errno == EINTR) continue;
    if (got < 0 && (errno == EAGAIN || errno == EWOULDBLOCK)) break;
    if (got < 0) throw InputError(path_ + ": cannot read the pose source: " + std::strerror(errno));
    if (got == 0) break;  // nothing more now (end of file, or a pipe without writer)
    offset_ += static_cast<std::uint64_t>(got);
    lines_.feed(std::string_view(buffer, static_cast<std::size_t>(got)), use);
  }
  const PoseLineProblems& problems = lines_.problems();
  for (; reported_problems_ < problems.first.size(); ++reported_problems_) {
    notices_.push_back(problems.first[reported_problems_]);
  }
  return added;
}

std::vector<std::string> PoseStreamReader::take_notices() { return std::exchange(notices_, {}); }

PoseFileCursor::PoseFileCursor(const std::string& path)
    : path_(path), lines_(path), order_check_(std::numeric_limits<double>::infinity()), block_(64 * 1024) {
  refuse_folder(path, "the pose file");
  file_.open(path, std::ios::binary);
  if (!file_) throw InputError(path + ": cannot open the pose file: " + std::strerror(errno));
  while (poses_ == 0 && read_block(true)) {
  }
  if (poses_ == 0) throw_no_usable_pose(path, lines_.problems());
}

bool PoseFileCursor::read_block(bool keep) {
  if (ended_) return false;
  const auto take = [&](const TimedPose& pose) {
    order_check_.append(pose);  // throws for a pose out of order: the line is skipped and told
    order_check_.drop_before(pose.time_s);
    if (poses_ == 0) first_time_s_ = pose.time_s;
    last_time_s_ = pose.time_s;
    ++poses_;
    if (keep) ahead_.push_back(pose);
  };
  file_.read(block_.data(), static_cast<std::streamsize>(block_.size()));
  const auto got = static_cast<std::size_t>(file_.gcount());
  if (file_.bad()) throw InputError(path_ + ": read error");
  lines_.feed(std::string_view(block_.data(), got), take);
  if (got < block_.size()) {
    lines_.finish(take);  // the file is complete: a last line without LF counts
    ended_ = true;
  }
  return !ended_;
}

void PoseFileCursor::read_to(double time_s, PoseTrack& track) {
  while (true) {
    for (const TimedPose& pose : ahead_) track.append(pose);
    ahead_.clear();
    if (ended_ || (!track.empty() && track.last_time_s() >= time_s)) return;
    read_block(true);
  }
}

void PoseFileCursor::read_rest() {
  while (read_block(false)) {
  }
}

}  // namespace stridemap::io
