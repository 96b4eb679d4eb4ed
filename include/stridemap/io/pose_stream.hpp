#pragma once
// Timestamped poses as text, one per line (docs/live.md, "Pose format"):
//
//   # time_s x_m y_m yaw_rad pitch_rad roll_rad [reference_elevation_m [height_change_m [z_m]]]
//   1733065200.100 0.250 0.000 0.0000 0.0000 0.0000
//
// The ninth column, the trunk's height from a 6-DoF estimator, makes the
// mapper place the sensor by the full mount transform (TrunkPose::z_m);
// files of 6 to 8 columns read as before, with no z.
//
// Fields are separated by spaces or tabs; blank lines and lines starting
// with '#' are skipped; times increase strictly. Read as a whole file
// (replay) or incrementally from a file or named pipe that another process
// is writing (live mapping).
#include <cstddef>
#include <functional>
#include <string>
#include <string_view>
#include <vector>

#include "stridemap/core/pose_track.hpp"

namespace stridemap::io {

/// Parses one line. Returns false for a blank or comment line. Throws
/// InputError "<source>:<line>: <what>" for a wrong field count or a field
/// that is not a finite number.
bool parse_pose_line(std::string_view line, const std::string& source, std::size_t line_number, TimedPose& out);
/// One line (no LF), numbers in the shortest form that reads back exactly.
std::string format_pose_line(const TimedPose& pose);
/// The header comment naming the columns (with its LF).
std::string pose_file_header();

/// Every pose of a file, in order. Throws InputError naming the file and
/// line for a missing file, a bad line, a time not after the previous one,
/// or a file with no pose.
std::vector<TimedPose> read_pose_file(const std::string& path);
/// The same from the file's bytes; `source` stands for the file in messages.
std::vector<TimedPose> parse_pose_text(std::string_view text, const std::string& source);

/// Longest pose line [bytes, without its LF]: nine numbers need far less,
/// and a stream must not buffer a line that never ends.
inline constexpr std::size_t kMaxPoseLineBytes = 4096;

/// Cuts bytes that arrive in any pieces into lines and parses each complete
/// one, numbering the lines; what the pieces were changes nothing. Throws
/// InputError "<source>:<line>: ..." for a bad line, a line longer than
/// kMaxPoseLineBytes, or what `use` throws (a time out of order).
class PoseLineBuffer {
 public:
  explicit PoseLineBuffer(std::string source) : source_(std::move(source)) {}
  /// Parses every line completed by `bytes` and hands each pose to `use`;
  /// an unfinished last line is kept for the next call.
  void feed(std::string_view bytes, const std::function<void(const TimedPose&)>& use);
  /// The end of the input: an unfinished last line counts as a line.
  void finish(const std::function<void(const TimedPose&)>& use);
  std::size_t lines() const { return line_number_; }
  std::size_t pending_bytes() const { return partial_.size(); }

 private:
  void complete_line(std::string_view line, const std::function<void(const TimedPose&)>& use);
  [[noreturn]] void too_long(std::size_t line_number) const;
  std::string source_;
  std::string partial_;
  std::size_t line_number_ = 0;
};

/// Reads a pose file or named pipe as it grows, without blocking: poll()
/// appends the complete lines that have arrived to a PoseTrack. A partial
/// last line waits for its LF. Opening a named pipe does not wait for a
/// writer; a writer that closes and a new one that opens are both fine.
class PoseStreamReader {
 public:
  /// Throws InputError naming the path when it cannot be opened, or is a
  /// folder or a device.
  explicit PoseStreamReader(const std::string& path);
  ~PoseStreamReader();
  PoseStreamReader(const PoseStreamReader&) = delete;
  PoseStreamReader& operator=(const PoseStreamReader&) = delete;

  /// Appends the poses read now; returns how many. Throws InputError
  /// "<path>:<line>: ..." for a bad line or a time out of order.
  std::size_t poll(PoseTrack& track);
  /// The file descriptor, for a caller that wants to poll() it.
  int fd() const { return fd_; }
  std::size_t lines_read() const { return lines_.lines(); }
  bool is_pipe() const { return is_pipe_; }

 private:
  std::string path_;
  int fd_ = -1;
  bool is_pipe_ = false;
  PoseLineBuffer lines_;
};

}  // namespace stridemap::io
