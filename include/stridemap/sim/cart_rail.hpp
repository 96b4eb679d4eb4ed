#pragma once
// Poses of the measuring cart on its rail (paper Fig. 16b): the trunk moves
// in a straight line at constant height, level, one scan every step.
#include <vector>

#include "stridemap/core/pose.hpp"
#include "stridemap/sim/scene.hpp"

namespace stridemap {

/// One pose per step from start_x_m towards end_x_m, both ends included:
/// start, start + step, ... and end itself when the length is not a whole
/// number of steps. Pitch, roll and reference elevation are 0 (the rail lies
/// on the floor); the sensor height comes from the SensorMount. Throws
/// InputError for a non-finite field or a non-positive step.
std::vector<TrunkPose> cart_rail_poses(const CartRailPath& path);

}  // namespace stridemap
