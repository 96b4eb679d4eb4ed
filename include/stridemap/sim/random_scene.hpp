#pragma once
// Random scenes to measure on: the shipped scenes have boxes a
// whole number of 10 mm cells wide, square to the rail, of middling
// reflectance, and a method tuned on them can look better than it is. These
// scenes draw sizes off the grid, square and turned boxes, reflectances from
// 0.1 to 0.9, tall and flat objects. The generator writes scene YAML (the
// schema of docs/scenes.md) so that a scene can be saved, read, edited and
// loaded like any other; it is deterministic for (kind, seed) on every
// platform (its own uniform numbers from std::mt19937_64's raw output).
#include <cstdint>
#include <string>
#include <string_view>

#include "stridemap/core/enum_names.hpp"

namespace stridemap {

enum class RandomSceneKind : std::uint8_t {
  boxes,  ///< flat floor, 2-4 boxes (and at times a can) lined up on a cart rail
  rocky,  ///< procedural ground with rocks and a walk path (the rocky mock-up's kind)
  steps,  ///< flat floor, a field of blocks of random size, height and yaw, a cart rail
};

inline constexpr EnumNameTable<RandomSceneKind, 3> kRandomSceneKindNames{{
    {RandomSceneKind::boxes, "boxes"},
    {RandomSceneKind::rocky, "rocky"},
    {RandomSceneKind::steps, "steps"},
}};
constexpr std::string_view name(RandomSceneKind kind) { return enum_name_in(kRandomSceneKindNames, kind); }
template <>
inline RandomSceneKind parse_enum_name<RandomSceneKind>(std::string_view text) {
  return enum_value_in(kRandomSceneKindNames, text, "a scene kind");
}

/// The scene as YAML text, with a comment naming kind and seed; loads with
/// parse_scene_yaml (config/scene_yaml.hpp).
///
/// boxes: the objects stand on the rail's line (centres within 30 mm of
/// it), so that the structured-light sensor's narrow view holds each whole
/// at its height; box sides 50-200 mm, 60 % of them turned by up to
/// 45 deg; 30 % flat (15-40 mm high), the rest 50-160 mm; every object and
/// the floor of reflectance 0.1-0.9.
///
/// With `bystanders` (boxes only): the same scene plus one or two tall
/// boxes (80-160 mm) beside the line, 100-250 mm from it where the
/// objects on the line leave room, each white (reflectance 0.75-0.9) or
/// black (0.05-0.2): in the structured-light camera's view but mostly
/// outside the stripe's, named kBystanderPrefix + k. They come from their
/// own draw, so the objects on the line are those of the scene without.
std::string random_scene_yaml(RandomSceneKind kind, std::uint64_t seed, bool bystanders = false);

/// Name prefix of the bystander boxes: figures of measured objects leave
/// them out (the stripe sees them only in part).
inline constexpr std::string_view kBystanderPrefix = "bystander_";

}  // namespace stridemap
