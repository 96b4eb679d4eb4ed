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
#include <fstream>
#include <functional>
#include <string>
#include <string_view>
#include <cstdint>
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

/// Lines skipped as unusable: how many, and the first few as
/// "<source>:<line>: <what>".
struct PoseLineProblems {
  std::size_t count = 0;
  std::vector<std::string> first;
  static constexpr std::size_t kListed = 20;
  void add(std::string message);
};

/// Every usable pose of a file, in order. A bad line, an overlong line or a
/// time not after the previous pose is skipped and reported in `problems`
/// (when given): one bad record never costs the others. Throws InputError
/// naming the file for a missing file or a file with no usable pose.
std::vector<TimedPose> read_pose_file(const std::string& path, PoseLineProblems* problems = nullptr);
/// The same from the file's bytes; `source` stands for the file in messages.
std::vector<TimedPose> parse_pose_text(std::string_view text, const std::string& source,
                                       PoseLineProblems* problems = nullptr);

/// Longest pose line [bytes, without its LF]: nine numbers need far less,
/// and a stream must not buffer a line that never ends.
inline constexpr std::size_t kMaxPoseLineBytes = 4096;

/// Cuts bytes that arrive in any pieces into lines and parses each complete
/// one, numbering the lines; what the pieces were changes nothing. A bad
/// line, a line longer than kMaxPoseLineBytes, or a line whose pose `use`
/// refuses with InputError (a time out of order) is skipped and added to
/// problems() as "<source>:<line>: ...".
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
  const PoseLineProblems& problems() const { return problems_; }

 private:
  void complete_line(std::string_view line, const std::function<void(const TimedPose&)>& use);
  void too_long(std::size_t line_number);
  std::string source_;
  std::string partial_;
  bool discarding_ = false;  // inside an overlong line, until its LF
  std::size_t line_number_ = 0;
  PoseLineProblems problems_;
};

/// A pose file read in step with a replay: poses are appended to the
/// track only as far as the scans need them, so a long run holds the poses
/// just ahead of its scans, not the file. The poses and the skipped lines
/// are those read_pose_file gives.
class PoseFileCursor {
 public:
  /// Opens the file and reads up to its first usable pose. Throws
  /// InputError as read_pose_file does for a missing file or a folder, or
  /// for a file with no usable pose.
  explicit PoseFileCursor(const std::string& path);
  PoseFileCursor(const PoseFileCursor&) = delete;
  PoseFileCursor& operator=(const PoseFileCursor&) = delete;

  /// Appends poses to `track` until its last pose is at or after `time_s`
  /// or the file ends. `track` takes every pose from this cursor and no
  /// other. Throws InputError naming the file on a read error.
  void read_to(double time_s, PoseTrack& track);
  /// Reads what is left for the counts and the time range only.
  void read_rest();
  bool ended() const { return ended_; }
  std::size_t poses() const { return poses_; }
  double first_time_s() const { return first_time_s_; }
  double last_time_s() const { return last_time_s_; }
  const PoseLineProblems& problems() const { return lines_.problems(); }

 private:
  // Reads one block, keeping its poses in ahead_ when `keep`; false at the
  // end of the file.
  bool read_block(bool keep);

  std::string path_;
  std::ifstream file_;
  PoseLineBuffer lines_;
  PoseTrack order_check_;  // the order read_pose_file enforces
  std::vector<char> block_;
  std::vector<TimedPose> ahead_;  // read, not yet handed to a track
  bool ended_ = false;
  std::size_t poses_ = 0;
  double first_time_s_ = 0.0, last_time_s_ = 0.0;
};

/// Reads a pose file or named pipe as it grows, without blocking: poll()
/// appends the complete lines that have arrived to a PoseTrack. A partial
/// last line waits for its LF. Opening a named pipe does not wait for a
/// writer; a writer that closes and a new one that opens are both fine.
/// A file replaced under the reader (another inode at the path: a restarted
/// publisher rewrote it) or cut shorter than what was read is reopened and
/// read from its start; poses not after the last one kept are then skipped
/// quietly, as they are known already. Bad lines are skipped and reported.
class PoseStreamReader {
 public:
  /// Throws InputError naming the path when it cannot be opened, or is a
  /// folder or a device.
  explicit PoseStreamReader(const std::string& path);
  ~PoseStreamReader();
  PoseStreamReader(const PoseStreamReader&) = delete;
  PoseStreamReader& operator=(const PoseStreamReader&) = delete;

  /// Appends the poses read now; returns how many. Throws InputError only
  /// when the source cannot be read at all.
  std::size_t poll(PoseTrack& track);
  /// What happened since the last call, one message each: skipped lines
  /// ("<path>:<line>: ..."), reopenings ("<path>: replaced ...").
  std::vector<std::string> take_notices();
  std::size_t skipped_lines() const { return skipped_before_ + lines_.problems().count; }
  std::size_t reopened() const { return reopened_; }
  /// The file descriptor, for a caller that wants to poll() it.
  int fd() const { return fd_; }
  std::size_t lines_read() const { return lines_.lines(); }
  bool is_pipe() const { return is_pipe_; }

 private:
  bool source_changed(std::string& why);
  void reopen();

  std::string path_;
  int fd_ = -1;
  bool is_pipe_ = false;
  PoseLineBuffer lines_;
  std::uint64_t offset_ = 0;         // bytes read from the current file
  std::size_t skipped_before_ = 0;   // skipped lines of files read before a reopening
  std::size_t reported_problems_ = 0;
  std::size_t reopened_ = 0;
  bool after_reopen_ = false;
  std::vector<std::string> notices_;
};

}  // namespace stridemap::io
