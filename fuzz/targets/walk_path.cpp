// Walk path files (config/walk_path_yaml.hpp, schema in docs/walking.md), read
// on their own and against a 4 x 4 m terrain. Errors name the file; a path
// accepted against the terrain is accepted without it too, and the same; the
// gait walks every path the reader accepts (TrunkMotion refuses nothing the
// reader let through) with finite poses inside the terrain; sampling an
// accepted path gives finite points.
#include <cmath>
#include <string>

#include "fuzz_target.hpp"
#include "stridemap/config/walk_path_yaml.hpp"
#include "stridemap/core/error.hpp"
#include "stridemap/sim/scene.hpp"
#include "stridemap/sim/trunk_motion.hpp"

namespace walk_path_fuzz {
namespace {

using namespace stridemap;
using fuzz::check;

const std::string kName = "fuzz.yaml";

bool same_path(const WalkPath& a, const WalkPath& b) {
  if (a.start_x_m != b.start_x_m || a.start_y_m != b.start_y_m || a.start_yaw_rad != b.start_yaw_rad ||
      a.segments.size() != b.segments.size()) {
    return false;
  }
  for (std::size_t i = 0; i < a.segments.size(); ++i) {
    const WalkSegment &s = a.segments[i], &t = b.segments[i];
    if (s.kind != t.kind || s.length_m != t.length_m || s.turn_rad != t.turn_rad || s.radius_m != t.radius_m) return false;
  }
  return true;
}

std::optional<WalkPath> read(const std::string& text, const HeightField* terrain) {
  try {
    return parse_walk_path_yaml(text, kName, terrain);
  } catch (const InputError& e) {
    check(std::string(e.what()).rfind(kName + ":", 0) == 0, std::string("an error that does not name the file: ") + e.what());
    return std::nullopt;
  }
}

}  // namespace

STRIDEMAP_FUZZ_TARGET(walk_path) {
  const std::string text(fuzz::as_text(data));
  static const Scene scene = [] {
    Scene s;
    s.terrain.min_x_m = -2.0;
    s.terrain.min_y_m = -2.0;
    s.terrain.max_x_m = 2.0;
    s.terrain.max_y_m = 2.0;
    return s;
  }();
  const std::optional<WalkPath> alone = read(text, nullptr);
  const std::optional<WalkPath> inside = read(text, &scene.terrain);
  if (inside) check(alone && same_path(*alone, *inside), "a path accepted against a terrain is refused or differs alone");
  if (!alone) return;

  for (const PathPoint& p : sample_walk_path(*alone, 10.0, 1.0)) {
    check(std::isfinite(p.x_m) && std::isfinite(p.y_m) && std::isfinite(p.yaw_rad) && std::isfinite(p.distance_m),
          "a sampled path point that is not finite");
  }
  if (!inside) return;
  try {
    const TrunkMotion motion(scene, *inside, GaitOptions{});
    const double duration = motion.duration_s();
    check(std::isfinite(duration) && duration > 0.0, "a walk that takes no time or forever");
    for (int k = 0; k <= 16; ++k) {
      const TrunkState state = motion.at(duration * k / 16.0);
      const TrunkPose& pose = state.pose;
      check(std::isfinite(pose.x_m) && std::isfinite(pose.y_m) && std::isfinite(pose.yaw_rad) &&
                std::isfinite(pose.pitch_rad) && std::isfinite(pose.roll_rad) &&
                std::isfinite(pose.reference_elevation_m) && std::isfinite(pose.height_change_m),
            "a trunk pose that is not finite");
      check(scene.terrain.in_extent(pose.x_m, pose.y_m), "the trunk leaves the terrain the reader checked");
    }
  } catch (const InputError& e) {
    fuzz::failure(std::string("the reader accepted a path the gait refuses: ") + e.what());
  }
}

}  // namespace walk_path_fuzz
