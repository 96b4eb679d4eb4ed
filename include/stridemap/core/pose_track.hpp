#pragma once
// Timestamped trunk poses (from an estimator: IMU, leg odometry, a camera)
// and the pose at a scan's time between two of them. Positions, pitch,
// roll and the height terms are interpolated linearly, yaw along the
// shorter way round. A pose is never made up beyond the samples: a time
// before the first or after the last pose, or between two poses farther
// apart than max_gap_s, has no pose.
#include <cstddef>
#include <cstdint>
#include "stridemap/core/pose.hpp"
#include "stridemap/core/ring_queue.hpp"

namespace stridemap {

struct TimedPose {
  double time_s = 0.0;
  TrunkPose pose;
};

enum class PoseLookup : std::uint8_t {
  ok,             ///< interpolated (or exactly a sample)
  empty,          ///< no poses yet
  before_first,   ///< earlier than the first pose
  after_last,     ///< later than the last pose (it may still come)
  gap_too_large,  ///< the two poses around the time are more than max_gap_s apart
};

class PoseTrack {
 public:
  /// Throws InputError unless max_gap_s is positive (infinity allowed).
  explicit PoseTrack(double max_gap_s = 1.0);

  /// Appends a pose. Throws InputError (without a place: callers add the
  /// file and line) when a field is not finite, the time is not later
  /// than the last pose's, or the pose has a z and the last one not (or the
  /// other way round).
  void append(const TimedPose& pose);
  /// The pose at `time_s`; `out` is set only for PoseLookup::ok. At a
  /// sample's time the sample itself is returned, bit for bit.
  PoseLookup interpolate(double time_s, TrunkPose& out) const;
  /// Forgets poses no longer needed for times >= time_s (keeps the last
  /// one at or before it).
  void drop_before(double time_s);

  /// Room for `poses` poses held at once without allocating (a live pose
  /// stream running ahead of the scans).
  void reserve(std::size_t poses) { poses_.reserve(poses); }

  bool empty() const { return poses_.empty(); }
  std::size_t size() const { return poses_.size(); }
  double first_time_s() const { return poses_.front().time_s; }
  double last_time_s() const { return poses_.back().time_s; }
  double max_gap_s() const { return max_gap_s_; }

 private:
  double max_gap_s_;
  RingQueue<TimedPose> poses_;  // reused slots: a live pose stream allocates nothing per pose
};

/// Linear interpolation between two poses at fraction a in [0, 1] (yaw the
/// shorter way round); a = 0 gives `from` exactly. z is present when both
/// ends have it.
TrunkPose interpolate_pose(const TrunkPose& from, const TrunkPose& to, double a);

}  // namespace stridemap
