#pragma once
// The flat calibration target of the structured-light sensor (paper section
// 3.2, ref. [14]): a matte wall across the optical axis of a level sensor at
// a known distance, on which the sheet draws a straight stripe whose row
// depends on b and beta alone (eq. 1 with z_c fixed).
#include "stridemap/core/pose.hpp"
#include "stridemap/sensors/structured_light.hpp"
#include "stridemap/sim/scene.hpp"

namespace stridemap {

/// A level bench mount: optical centre 0.5 m above the floor, no pitch.
SensorMount calibration_bench_mount();

/// Reflectance of the simulated target: matte white.
inline constexpr double calibration_target_reflectance = 0.8;

/// Depths z_c whose stripe the camera sees, from the top row to the bottom
/// row (or to infinity when the sheet vanishes inside the image).
struct TargetDepthRange {
  double nearest_m = 0.0;
  double farthest_m = 0.0;
};
TargetDepthRange target_depth_range(const StructuredLightModel& model);

/// A floor and a wall whose face lies distance_m ahead of the optical centre
/// along the optical axis, across it, for the sensor of `parameters` (its
/// mount) at `pose`. Throws InputError when the optical axis is not level
/// (mount pitch, trunk pitch or roll not zero), the distance is not
/// positive, or the stripe on the target would fall outside the image (the
/// message gives the usable range).
Scene calibration_target_scene(const StructuredLightParameters& parameters, const TrunkPose& pose, double distance_m);

}  // namespace stridemap
