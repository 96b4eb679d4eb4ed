#include "stridemap/sim/trunk_motion.hpp"

#include <algorithm>
#include <cmath>

#include <Eigen/Dense>

#include "stridemap/core/error.hpp"

namespace stridemap {
namespace {

double segment_duration_s(const WalkSegment& s, const GaitOptions& g) {
  if (s.kind == WalkSegment::Kind::straight) return s.length_m / g.forward_speed_m_per_s;
  const double in_place = std::abs(s.turn_rad) / g.turn_rate_rad_per_s;
  if (s.radius_m == 0.0) return in_place;
  return std::max(s.radius_m * std::abs(s.turn_rad) / g.forward_speed_m_per_s, in_place);
}

}  // namespace

std::array<Eigen::Vector2d, 6> GaitOptions::foot_offsets() const {
  return {Eigen::Vector2d(foot_forward_m, foot_lateral_m),   Eigen::Vector2d(0.0, middle_foot_lateral_m),
          Eigen::Vector2d(-foot_forward_m, foot_lateral_m),  Eigen::Vector2d(foot_forward_m, -foot_lateral_m),
          Eigen::Vector2d(0.0, -middle_foot_lateral_m),      Eigen::Vector2d(-foot_forward_m, -foot_lateral_m)};
}

std::optional<std::string> GaitOptions::first_problem() const {
  using namespace scene_rules;
  const std::pair<const char*, double> positives[] = {
      {"forward_speed_m_per_s", forward_speed_m_per_s}, {"turn_rate_rad_per_s", turn_rate_rad_per_s},
      {"gait_cycle_s", gait_cycle_s},                   {"foot_forward_m", foot_forward_m},
      {"foot_lateral_m", foot_lateral_m},               {"middle_foot_lateral_m", middle_foot_lateral_m}};
  for (const auto& [field, value] : positives) {
    if (auto m = positive(value)) return std::string(field) + ": " + *m;
  }
  const std::pair<const char*, double> non_negatives[] = {{"bob_amplitude_m", bob_amplitude_m},
                                                          {"pitch_amplitude_rad", pitch_amplitude_rad},
                                                          {"roll_amplitude_rad", roll_amplitude_rad},
                                                          {"step_height_m", step_height_m}};
  for (const auto& [field, value] : non_negatives) {
    if (auto m = non_negative(value)) return std::string(field) + ": " + *m;
  }
  if (!(stance_fraction > 0.5 && stance_fraction < 1.0)) {
    return "stance_fraction: expected a number above 0.5 and below 1, got " + format_number(stance_fraction);
  }
  if (!(terrain_attitude_gain >= 0.0 && terrain_attitude_gain <= 1.0)) {
    return "terrain_attitude_gain: expected a number from 0 to 1, got " + format_number(terrain_attitude_gain);
  }
  return std::nullopt;
}

void GaitOptions::validate() const {
  if (auto problem = first_problem()) throw InputError("gait options: " + *problem);
}

std::array<Eigen::Vector2d, 6> foot_positions(const GaitOptions& gait, double x_m, double y_m, double yaw_rad) {
  const double c = std::cos(yaw_rad), s = std::sin(yaw_rad);
  std::array<Eigen::Vector2d, 6> feet = gait.foot_offsets();
  for (Eigen::Vector2d& f : feet) f = Eigen::Vector2d(x_m + c * f.x() - s * f.y(), y_m + s * f.x() + c * f.y());
  return feet;
}

TrunkMotion::TrunkMotion(const Scene& scene, const WalkPath& path, const GaitOptions& gait)
    : scene_(scene), path_(path), gait_(gait) {
  gait_.validate();
  scene_.validate();
  if (auto p = walk_path_extent_problem(path_, scene_.terrain)) throw InputError(p->field_path + ": " + p->message);
  PathPoint at{path_.start_x_m, path_.start_y_m, path_.start_yaw_rad, 0.0, 0.0};
  segment_start_s_.push_back(0.0);
  for (const WalkSegment& s : path_.segments) {
    segment_start_.push_back(at);
    segment_start_s_.push_back(segment_start_s_.back() + segment_duration_s(s, gait_));
    at = advance_along(at, s, 1.0);
  }
  segment_start_.push_back(at);

  const auto offsets = gait_.foot_offsets();
  Eigen::Matrix<double, 6, 3> a;
  for (int k = 0; k < 6; ++k) a.row(k) << 1.0, offsets[k].x(), offsets[k].y();
  plane_fit_ = (a.transpose() * a).inverse() * a.transpose();
}

TrunkMotion::SupportPlane TrunkMotion::support_plane(double x_m, double y_m, double yaw_rad) const {
  const auto feet = foot_positions(gait_, x_m, y_m, yaw_rad);
  Eigen::Matrix<double, 6, 1> z;
  for (int k = 0; k < 6; ++k) z(k) = scene_.surface_height_at(feet[k].x(), feet[k].y());
  const Eigen::Vector3d plane = plane_fit_ * z;
  return {plane(0), plane(1), plane(2)};
}

PathPoint TrunkMotion::point_at(double time_s) const {
  const double t = std::clamp(std::isfinite(time_s) ? time_s : 0.0, 0.0, duration_s());
  const auto next = std::upper_bound(segment_start_s_.begin(), segment_start_s_.end(), t);
  const std::size_t k = static_cast<std::size_t>(next - segment_start_s_.begin()) - 1;
  if (k >= path_.segments.size()) return segment_start_.back();
  const double span = segment_start_s_[k + 1] - segment_start_s_[k];
  const double fraction = span > 0.0 ? (t - segment_start_s_[k]) / span : 1.0;
  return advance_along(segment_start_[k], path_.segments[k], fraction);
}

void TrunkMotion::stepping_feet(double time_s, std::array<FootState, 6>& feet,
                                Eigen::Matrix<double, 6, 1>& support_m) const {
  const auto offsets = gait_.foot_offsets();
  const double cycle_s = gait_.gait_cycle_s;
  // Stance n of a foot of tripod `lag` (0 or 0.5 cycles) spans cycles
  // [n + lag, n + lag + stance); its foothold is the foot's nominal place
  // when the trunk is half way through it, so the foot lands ahead of its
  // nominal place and leaves as far behind.
  const double stance = gait_.stance_fraction;
  const auto foothold = [&](int foot, double lag, double n) {
    const PathPoint p = point_at((n + lag + stance / 2) * cycle_s);
    const double c = std::cos(p.yaw_rad), s = std::sin(p.yaw_rad);
    const Eigen::Vector2d& o = offsets[static_cast<std::size_t>(foot)];
    const double x = p.x_m + c * o.x() - s * o.y(), y = p.y_m + s * o.x() + c * o.y();
    const double z = gait_.follow_terrain ? scene_.surface_height_at(x, y) : scene_.terrain.base_elevation_m;
    return Eigen::Vector3d(x, y, z);
  };
  for (int foot = 0; foot < 6; ++foot) {
    // Left front, right middle and left rear step together (indices 0, 4,
    // 2); the other tripod half a cycle later.
    const double lag = (foot == 1 || foot == 3 || foot == 5) ? 0.5 : 0.0;
    const double phase = time_s / cycle_s - lag;
    const double n = std::floor(phase);
    const double within = phase - n;
    FootState& f = feet[static_cast<std::size_t>(foot)];
    const Eigen::Vector3d from = foothold(foot, lag, n);
    if (within < stance) {
      f = {from, true};
      support_m(foot) = from.z();
      continue;
    }
    const double swing = (within - stance) / (1.0 - stance);
    const Eigen::Vector3d to = foothold(foot, lag, n + 1.0);
    f.position_m = from + swing * (to - from);
    f.in_stance = false;
    support_m(foot) = f.position_m.z();
    f.position_m.z() += gait_.step_height_m * std::sin(std::numbers::pi * swing);
  }
}

TrunkState TrunkMotion::at(double time_s) const {
  const double t = std::clamp(std::isfinite(time_s) ? time_s : 0.0, 0.0, duration_s());
  const auto next = std::upper_bound(segment_start_s_.begin(), segment_start_s_.end(), t);
  std::size_t k = static_cast<std::size_t>(next - segment_start_s_.begin()) - 1;
  if (k >= path_.segments.size()) k = path_.segments.size();
  const PathPoint point = point_at(t);

  TrunkState state;
  state.time_s = t;
  state.segment = k;
  state.distance_m = point.distance_m;
  state.turned_rad = point.turned_rad;
  SupportPlane plane{scene_.terrain.base_elevation_m, 0.0, 0.0};
  if (gait_.feet_stand_in_stance) {
    Eigen::Matrix<double, 6, 1> support;
    stepping_feet(t, state.feet, support);
    if (gait_.follow_terrain) {
      const Eigen::Vector3d fit = plane_fit_ * support;
      plane = {fit(0), fit(1), fit(2)};
    }
  } else {
    const auto feet = foot_positions(gait_, point.x_m, point.y_m, point.yaw_rad);
    for (std::size_t f = 0; f < 6; ++f) {
      const double z = gait_.follow_terrain ? scene_.surface_height_at(feet[f].x(), feet[f].y())
                                            : scene_.terrain.base_elevation_m;
      state.feet[f] = {Eigen::Vector3d(feet[f].x(), feet[f].y(), z), true};
    }
    if (gait_.follow_terrain) plane = support_plane(point.x_m, point.y_m, point.yaw_rad);
  }
  // Cycle phase in turns; the bob and the pitch run at twice the cycle
  // rate (once per step), the roll once per cycle (once per tripod pair).
  const double cycle = 2.0 * std::numbers::pi * t / gait_.gait_cycle_s;
  TrunkPose& pose = state.pose;
  pose.x_m = point.x_m;
  pose.y_m = point.y_m;
  pose.yaw_rad = point.yaw_rad;
  pose.pitch_rad = -gait_.terrain_attitude_gain * std::atan(plane.slope_forward) +
                   gait_.pitch_amplitude_rad * std::sin(2.0 * cycle);
  pose.roll_rad = gait_.terrain_attitude_gain * std::atan(plane.slope_left) + gait_.roll_amplitude_rad * std::sin(cycle);
  pose.reference_elevation_m = plane.height_m;
  pose.height_change_m = -gait_.bob_amplitude_m * std::cos(2.0 * cycle);
  return state;
}

}  // namespace stridemap
