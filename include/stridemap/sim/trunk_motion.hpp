#pragma once
// How a hexapod's trunk moves along a WalkPath with a tripod gait (paper
// sections 5.1, 6.2; docs/walking.md). The model is kinematic, not a
// dynamics simulation: it produces the disturbances the mapper has to live
// with, at the sizes a walking robot shows them.
//
// - Along the path at a constant speed (forward_speed_m_per_s on straights
//   and arcs, turn_rate_rad_per_s in place; an arc is slowed down so its yaw
//   rate stays within the turn rate).
// - The two tripods alternate; each step lasts half a gait cycle. Per step
//   the trunk bobs (height) and pitches once; per cycle it rolls once, to
//   the side of the tripod that carries it.
// - The feet step (feet_stand_in_stance, the default): each tripod stands
//   on its footholds for stance_fraction of a cycle while the trunk moves
//   over them, then swings to the next ones; the tripods overlap briefly. A foothold is the foot's nominal place around
//   the trunk at mid-stance, on the scene's surface, so a stance foot's
//   world position does not move. Off: the feet slide with the trunk at
//   their nominal places (the simpler model).
// - The trunk follows the terrain under its feet: its reference height is
//   the support plane of the six feet's support heights (a stance foot's
//   foothold; a swinging foot's blend of the foothold it left and the one it
//   lands on, so the trunk does not jump at a tripod switch), and the trunk
//   takes terrain_attitude_gain of that plane's slope as pitch and roll (a
//   gain of 1 lies flat on it, 0 keeps the trunk level).
//
// The sensor rides on the trunk, so its height above the map's zero is
// ground + SensorMount::height_m + bob: the true TrunkPose carries the
// ground as reference_elevation_m and the bob as height_change_m, exactly
// as core/sensor_transform.hpp composes them.
#include <array>
#include <cstddef>
#include <numbers>
#include <optional>
#include <string>
#include <vector>

#include <Eigen/Core>

#include "stridemap/core/pose.hpp"
#include "stridemap/sim/scene.hpp"
#include "stridemap/sim/walk_path.hpp"

namespace stridemap {

struct GaitOptions {
  /// Speed of the trunk along straights and arcs [m/s]. 0.1 m/s with the
  /// URG's 10 Hz gives 10 mm of travel per scan, the rail's step (6.1).
  double forward_speed_m_per_s = 0.10;
  /// Yaw rate when turning in place, and the most an arc may ask for
  /// [rad/s]. 10 deg/s: 1 deg per URG scan.
  double turn_rate_rad_per_s = 10.0 * std::numbers::pi / 180.0;
  /// One gait cycle: both tripods swing once [s]. 1.2 s at 0.1 m/s is a
  /// 6 cm step, a typical tripod gait for a robot of Messor's size.
  double gait_cycle_s = 1.2;
  /// Half the peak-to-peak height oscillation, once per step [m].
  double bob_amplitude_m = 0.004;
  /// Pitch oscillation, once per step [rad].
  double pitch_amplitude_rad = 0.5 * std::numbers::pi / 180.0;
  /// Roll oscillation, once per cycle as the support shifts between the
  /// tripods [rad].
  double roll_amplitude_rad = 1.0 * std::numbers::pi / 180.0;
  /// Share of the support plane's slope the trunk takes as pitch and roll,
  /// in [0, 1]. 0.5: the legs level the trunk half way.
  double terrain_attitude_gain = 0.5;
  /// Off: the trunk glides at its height above the terrain's base
  /// elevation whatever is under the feet (no support plane, no slope), as
  /// for the sensor-mount comparison, where the mount's height is meant
  /// above the floor of the step field.
  bool follow_terrain = true;
  /// Feet relative to the trunk reference point, forward / left [m]: front
  /// and rear pairs at +-foot_forward_m, +-foot_lateral_m; the middle pair
  /// at 0, +-middle_foot_lateral_m. Defaults: a trunk of Messor's size.
  double foot_forward_m = 0.18;
  double foot_lateral_m = 0.17;
  double middle_foot_lateral_m = 0.23;
  /// On: a stance foot stands still on its foothold and a swinging foot
  /// steps to the next (a tripod gait). Off: the feet slide along with the
  /// trunk at their nominal places.
  bool feet_stand_in_stance = true;
  /// Share of a gait cycle a foot stands, in (0.5, 1): above a half, both
  /// tripods stand for a moment at each switch (double support), as a
  /// tripod gait's duty factor has it. 0.6: 0.12 s at each switch, longer
  /// than the URG's 0.1 s between scans.
  double stance_fraction = 0.6;
  /// How high a swinging foot lifts at mid-swing [m]; only the feet's
  /// positions show it (the support uses the footholds).
  double step_height_m = 0.03;

  /// The six feet in the trunk frame (x forward, y left): left front, left
  /// middle, left rear, right front, right middle, right rear.
  std::array<Eigen::Vector2d, 6> foot_offsets() const;

  /// First unusable option ("gait options: <field>: <problem>"), if any.
  std::optional<std::string> first_problem() const;
  /// Throws InputError with first_problem().
  void validate() const;
};

/// The feet of a trunk at (x, y, yaw) in the map frame.
std::array<Eigen::Vector2d, 6> foot_positions(const GaitOptions& gait, double x_m, double y_m, double yaw_rad);

/// Where a foot is and whether it bears weight. The two tripods are left
/// front, right middle, left rear (indices 0, 4, 2: stance from the start of
/// each gait cycle) and right front, left middle, right rear (3, 1, 5: half a
/// cycle later).
struct FootState {
  Eigen::Vector3d position_m = Eigen::Vector3d::Zero();  ///< the sole, map frame [m]
  bool in_stance = true;
};

/// The truth at one instant.
struct TrunkState {
  double time_s = 0.0;
  /// The true pose: x, y, yaw on the path; pitch and roll from terrain and
  /// gait; reference_elevation_m = ground under the feet; height_change_m
  /// = the gait's bob.
  TrunkPose pose;
  /// Index of the segment being walked (segments.size() once finished).
  std::size_t segment = 0;
  double distance_m = 0.0;  ///< track walked so far [m]
  double turned_rad = 0.0;  ///< heading turned so far, as a magnitude [rad]
  /// The six feet, in GaitOptions::foot_offsets() order. What leg
  /// kinematics would measure (pose_estimate.hpp's `legs` reference).
  std::array<FootState, 6> feet{};
};

class TrunkMotion {
 public:
  /// Copies the scene. Throws InputError when the gait options or the path
  /// have a problem, or when the path leaves the scene's terrain extent, so
  /// that no work starts on a walk that cannot be done.
  TrunkMotion(const Scene& scene, const WalkPath& path, const GaitOptions& gait);

  /// Time to walk the whole path [s].
  double duration_s() const { return segment_start_s_.back(); }
  /// The truth at a time in [0, duration_s()] (clamped).
  TrunkState at(double time_s) const;

  const WalkPath& path() const { return path_; }
  const GaitOptions& gait() const { return gait_; }
  const Scene& scene() const { return scene_; }

  /// Support plane of the feet of a trunk at (x, y, yaw): height under the
  /// trunk and slopes along its forward and left axes [m/m].
  struct SupportPlane {
    double height_m = 0.0, slope_forward = 0.0, slope_left = 0.0;
  };
  SupportPlane support_plane(double x_m, double y_m, double yaw_rad) const;

 private:
  PathPoint point_at(double time_s) const;
  /// The feet at a time (feet_stand_in_stance) and their support heights.
  void stepping_feet(double time_s, std::array<FootState, 6>& feet, Eigen::Matrix<double, 6, 1>& support_m) const;

  Scene scene_;
  WalkPath path_;
  GaitOptions gait_;
  std::vector<double> segment_start_s_;  ///< one more than segments: the last is the end
  std::vector<PathPoint> segment_start_;  ///< where each segment begins
  /// Least-squares plane through the feet: (A^T A)^-1 A^T for the rows
  /// (1, forward, left) of the foot layout.
  Eigen::Matrix<double, 3, 6> plane_fit_;
};

}  // namespace stridemap
