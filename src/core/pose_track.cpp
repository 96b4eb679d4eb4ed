#include "stridemap/core/pose_track.hpp"

#include <algorithm>
#include <cmath>
#include <numbers>
#include <charconv>
#include <string>

#include "stridemap/core/error.hpp"

namespace stridemap {
namespace {

// a + t (b - a) keeps a exactly when b == a; for values so far apart that
// b - a overflows (finite poses of 1e308 m), the form that stays finite.
double lerp(double a, double b, double t) {
  const double d = b - a;
  return std::isfinite(d) ? a + t * d : (1.0 - t) * a + t * b;
}

// The shortest text that reads back to the same double: what the file said.
std::string shortest(double value) {
  char text[32];
  const auto [end, error] = std::to_chars(text, text + sizeof text, value);
  return std::string(text, error == std::errc() ? end : text);
}

// b - a wrapped into [-pi, pi).
double angle_difference(double a, double b) {
  const double two_pi = 2.0 * std::numbers::pi;
  // Headings so large that b - a overflows are wrapped one by one first.
  if (!std::isfinite(b - a + std::numbers::pi)) return angle_difference(std::remainder(a, two_pi), std::remainder(b, two_pi));
  double d = std::fmod(b - a + std::numbers::pi, two_pi);
  if (d < 0.0) d += two_pi;
  return d - std::numbers::pi;
}

}  // namespace

TrunkPose interpolate_pose(const TrunkPose& from, const TrunkPose& to, double a) {
  if (a == 0.0) return from;
  TrunkPose p;
  p.x_m = lerp(from.x_m, to.x_m, a);
  p.y_m = lerp(from.y_m, to.y_m, a);
  p.yaw_rad = from.yaw_rad + a * angle_difference(from.yaw_rad, to.yaw_rad);
  p.pitch_rad = lerp(from.pitch_rad, to.pitch_rad, a);
  p.roll_rad = lerp(from.roll_rad, to.roll_rad, a);
  p.reference_elevation_m = lerp(from.reference_elevation_m, to.reference_elevation_m, a);
  p.height_change_m = lerp(from.height_change_m, to.height_change_m, a);
  // A z known at only one end is not known in between.
  if (from.z_m && to.z_m) p.z_m = lerp(*from.z_m, *to.z_m, a);
  return p;
}

PoseTrack::PoseTrack(double max_gap_s) : max_gap_s_(max_gap_s) {
  if (!(max_gap_s > 0.0)) throw InputError("pose track: max_gap_s must be positive");
}

void PoseTrack::append(const TimedPose& p) {
  const double fields[] = {p.time_s,          p.pose.x_m,      p.pose.y_m,
                           p.pose.yaw_rad,    p.pose.pitch_rad, p.pose.roll_rad,
                           p.pose.reference_elevation_m, p.pose.height_change_m};
  for (const double f : fields) {
    if (!std::isfinite(f)) throw InputError("pose fields must be finite numbers");
  }
  if (p.pose.z_m && !std::isfinite(*p.pose.z_m)) throw InputError("pose fields must be finite numbers");
  if (!poses_.empty() && poses_.back().pose.z_m.has_value() != p.pose.z_m.has_value()) {
    // Between such poses the sensor height would jump from h_ref + d_z to
    // the estimator's z: a broken source, not a pose to interpolate.
    throw InputError(std::string("pose at ") + shortest(p.time_s) + " s " + (p.pose.z_m ? "has" : "has no") +
                     " z but the previous pose " + (p.pose.z_m ? "has none" : "has one") +
                     " (a track gives z for every pose or for none)");
  }
  if (!poses_.empty() && !(p.time_s > poses_.back().time_s)) {
    throw InputError("pose time " + shortest(p.time_s) + " s is not later than the previous pose's " +
                     shortest(poses_.back().time_s) + " s (poses must come in increasing time order)");
  }
  poses_.push_back(p);
}

PoseLookup PoseTrack::interpolate(double time_s, TrunkPose& out) const {
  if (poses_.empty()) return PoseLookup::empty;
  if (!(time_s >= poses_.front().time_s)) return PoseLookup::before_first;
  if (time_s > poses_.back().time_s) return PoseLookup::after_last;
  // First pose later than time_s; the one before it is at or before time_s.
  std::size_t lo = 1, hi = poses_.size();  // in [1, size]: the first pose is at or before time_s
  while (lo < hi) {
    const std::size_t mid = lo + (hi - lo) / 2;
    if (time_s < poses_[mid].time_s) {
      hi = mid;
    } else {
      lo = mid + 1;
    }
  }
  const TimedPose& before = poses_[lo - 1];
  if (before.time_s == time_s) {
    out = before.pose;
    return PoseLookup::ok;
  }
  // Not past the end: time_s is below the last pose's time, which equals no earlier time.
  const TimedPose* later = &poses_[lo];
  if (later->time_s - before.time_s > max_gap_s_) return PoseLookup::gap_too_large;
  double span = later->time_s - before.time_s, since = time_s - before.time_s;
  if (!std::isfinite(span)) {  // times of +-1e308 s (a gap of infinity allowed): halves do not overflow
    span = 0.5 * later->time_s - 0.5 * before.time_s;
    since = 0.5 * time_s - 0.5 * before.time_s;
  }
  out = interpolate_pose(before.pose, later->pose, std::clamp(since / span, 0.0, 1.0));
  return PoseLookup::ok;
}

void PoseTrack::drop_before(double time_s) {
  while (poses_.size() >= 2 && poses_[1].time_s <= time_s) poses_.pop_front();
}

}  // namespace stridemap
