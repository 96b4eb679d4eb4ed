#include "stridemap/io/pose_stream.hpp"

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

#include "stridemap/core/error.hpp"

namespace stridemap::io {
namespace {

constexpr const char* kColumns =
    "time_s x_m y_m yaw_rad pitch_rad roll_rad [reference_elevation_m [height_change_m [z_m]]]";

std::string located(const std::string& source, std::size_t line, const std::string& what) {
  return source + ":" + std::to_string(line) + ": " + what;
}

void append_number(double value, std::string& out) {
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
    append_number(fields[i], line);
  }
  return line;
}

std::string pose_file_header() { return std::string("# stridemap poses: ") + kColumns + "\n"; }

std::vector<TimedPose> parse_pose_text(std::string_view text, const std::string& source) {
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
  if (poses.empty()) throw InputError(source + ": no pose in the file (expected lines of " + kColumns + ")");
  return poses;
}

std::vector<TimedPose> read_pose_file(const std::string& path) {
  std::ifstream file(path, std::ios::binary);
  if (!file) throw InputError(path + ": cannot open the pose file: " + std::strerror(errno));
  const std::string text{std::istreambuf_iterator<char>(file), std::istreambuf_iterator<char>()};
  if (file.bad()) throw InputError(path + ": read error");
  return parse_pose_text(text, path);
}

void PoseLineBuffer::complete_line(std::string_view line, const std::function<void(const TimedPose&)>& use) {
  ++line_number_;
  if (line.size() > kMaxPoseLineBytes) too_long(line_number_);
  TimedPose pose;
  if (!parse_pose_line(line, source_, line_number_, pose)) return;
  try {
    use(pose);
  } catch (const InputError& e) {
    throw InputError(located(source_, line_number_, e.what()));
  }
}

void PoseLineBuffer::too_long(std::size_t line_number) const {
  throw InputError(located(source_, line_number,
                           "line longer than " + std::to_string(kMaxPoseLineBytes) + " bytes: not a pose line"));
}

void PoseLineBuffer::feed(std::string_view bytes, const std::function<void(const TimedPose&)>& use) {
  while (!bytes.empty()) {
    const std::size_t lf = bytes.find('\n');
    if (lf == std::string_view::npos) {
      // Held until its LF comes; never more than a line may hold.
      if (partial_.size() + bytes.size() > kMaxPoseLineBytes) too_long(line_number_ + 1);
      partial_.append(bytes);
      return;
    }
    if (partial_.empty()) {
      complete_line(bytes.substr(0, lf), use);
    } else {
      if (partial_.size() + lf > kMaxPoseLineBytes) too_long(line_number_ + 1);
      partial_.append(bytes.substr(0, lf));
      complete_line(partial_, use);
      partial_.clear();
    }
    bytes.remove_prefix(lf + 1);
  }
}

void PoseLineBuffer::finish(const std::function<void(const TimedPose&)>& use) {
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

std::size_t PoseStreamReader::poll(PoseTrack& track) {
  std::size_t added = 0;
  char buffer[4096];
  const auto use = [&](const TimedPose& pose) {
    track.append(pose);
    ++added;
  };
  while (true) {
    const ssize_t got = ::read(fd_, buffer, sizeof buffer);
    if (got < 0 && errno == EINTR) continue;
    if (got < 0 && (errno == EAGAIN || errno == EWOULDBLOCK)) break;
    if (got < 0) throw InputError(path_ + ": cannot read the pose source: " + std::strerror(errno));
    if (got == 0) break;  // nothing more now (end of file, or a pipe without writer)
    lines_.feed(std::string_view(buffer, static_cast<std::size_t>(got)), use);
  }
  return added;
}

}  // namespace stridemap::io
