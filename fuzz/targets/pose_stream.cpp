// Timestamped pose text (recordings/pose_stream.hpp, docs/live.md "Pose format"),
// read whole as `stridemap map --poses` does and as a live stream in pieces
// chosen by the input (a named pipe delivers whatever the writer flushed):
// both must keep the same poses and skip the same lines with the same
// messages naming them (a bad line, an overlong one, a time at or before
// the previous pose); only a text with no usable pose is an error. Every pose
// kept is finite, in strictly increasing time, written back exactly by
// format_pose_line, and interpolates to finite poses.
#include <cmath>
#include <limits>
#include <string>
#include <vector>

#include "fuzz_target.hpp"
#include "stridemap/core/error.hpp"
#include "stridemap/core/pose_track.hpp"
#include "stridemap/recordings/pose_stream.hpp"

namespace {

using namespace stridemap;
using fuzz::check;

const std::string kName = "fuzz.poses";

bool finite_pose(const TrunkPose& p) {
  return std::isfinite(p.x_m) && std::isfinite(p.y_m) && std::isfinite(p.yaw_rad) && std::isfinite(p.pitch_rad) &&
         std::isfinite(p.roll_rad) && std::isfinite(p.reference_elevation_m) && std::isfinite(p.height_change_m) &&
         (!p.z_m || std::isfinite(*p.z_m));
}

bool same_pose(const TimedPose& a, const TimedPose& b) {
  return a.time_s == b.time_s && a.pose.x_m == b.pose.x_m && a.pose.y_m == b.pose.y_m &&
         a.pose.yaw_rad == b.pose.yaw_rad && a.pose.pitch_rad == b.pose.pitch_rad &&
         a.pose.roll_rad == b.pose.roll_rad && a.pose.reference_elevation_m == b.pose.reference_elevation_m &&
         a.pose.height_change_m == b.pose.height_change_m && a.pose.z_m == b.pose.z_m;
}

struct Result {
  std::vector<TimedPose> poses;
  std::string error;
  io::PoseLineProblems problems;
};

Result read_whole(std::string_view text) {
  Result r;
  try {
    r.poses = io::parse_pose_text(text, kName, &r.problems);
  } catch (const InputError& e) {
    r.error = e.what();
  }
  return r;
}

Result read_streamed(std::string_view text, std::uint32_t seed) {
  Result r;
  PoseTrack track(std::numeric_limits<double>::infinity());
  io::PoseLineBuffer lines(kName);
  const auto use = [&](const TimedPose& pose) {
    track.append(pose);
    r.poses.push_back(pose);
  };
  try {
    std::size_t pos = 0;
    while (pos < text.size()) {
      seed = seed * 1664525u + 1013904223u;
      const std::size_t chunk = (seed >> 28) < 12 ? 1 + (seed >> 16) % 9 : 1 + (seed >> 8) % 5000;
      lines.feed(text.substr(pos, chunk), use);
      pos += std::min(chunk, text.size() - pos);
      check(lines.pending_bytes() <= io::kMaxPoseLineBytes, "the stream holds more than a line");
    }
    lines.finish(use);
  } catch (const InputError& e) {
    fuzz::failure(std::string("a stream stopped instead of skipping the line: ") + e.what());
  }
  r.problems = lines.problems();
  return r;
}

}  // namespace

STRIDEMAP_FUZZ_TARGET(pose_stream) {
  if (data.size() < 2) return;
  const std::uint32_t seed = 1u + (data[0] | (data[1] << 8));
  const std::string_view text = fuzz::as_text(data.subspan(2));
  const Result whole = read_whole(text);
  const Result streamed = read_streamed(text, seed);

  if (!whole.error.empty()) {
    check(whole.error.rfind(kName + ": no usable pose", 0) == 0, "an error other than 'no usable pose': " + whole.error);
    check(streamed.poses.empty(), "a file without poses gives poses as a stream");
  }
  check(whole.problems.count == streamed.problems.count, "whole and streamed skip different numbers of lines");
  check(whole.problems.first == streamed.problems.first, "whole and streamed skip different lines");
  for (const std::string& problem : whole.problems.first) {
    check(problem.rfind(kName + ":", 0) == 0, "a skipped line not named with the file: " + problem);
  }
  // Up to the error, the stream has appended exactly the poses before it.
  if (whole.error.empty()) {
    check(whole.poses.size() == streamed.poses.size(), "whole and streamed keep different numbers of poses");
    for (std::size_t i = 0; i < whole.poses.size(); ++i) {
      check(same_pose(whole.poses[i], streamed.poses[i]), "pose " + std::to_string(i) + " differs when streamed");
    }
  }

  const std::vector<TimedPose>& poses = streamed.poses;
  PoseTrack track(1.0);
  for (std::size_t i = 0; i < poses.size(); ++i) {
    const TimedPose& p = poses[i];
    check(std::isfinite(p.time_s) && finite_pose(p.pose), "a pose that is not finite");
    if (i > 0) check(p.time_s > poses[i - 1].time_s, "a pose not later than the one before");
    TimedPose back;
    check(io::parse_pose_line(io::format_pose_line(p), kName, 1, back) && same_pose(p, back),
          "format_pose_line does not read back exactly: " + io::format_pose_line(p));
    track.append(p);
  }
  for (std::size_t i = 0; i + 1 < poses.size() && i < 64; ++i) {
    TrunkPose at;
    if (track.interpolate(poses[i].time_s, at) == PoseLookup::ok) {
      check(at.x_m == poses[i].pose.x_m && at.yaw_rad == poses[i].pose.yaw_rad, "a sample's time does not give the sample");
    }
    const double middle = poses[i].time_s + 0.5 * (poses[i + 1].time_s - poses[i].time_s);
    const PoseLookup lookup = track.interpolate(middle, at);
    if (lookup == PoseLookup::ok) check(finite_pose(at), "an interpolated pose that is not finite");
  }
}
