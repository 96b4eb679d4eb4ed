#include "stridemap/sim/random_scene.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <numbers>
#include <random>
#include <vector>

namespace stridemap {
namespace {

// Uniform numbers from the engine's raw 64-bit output: the standard
// distributions may differ between standard libraries, this does not.
class Draw {
 public:
  explicit Draw(std::uint64_t seed) : engine_(seed) {}
  double unit() { return static_cast<double>(engine_() >> 11) * 0x1.0p-53; }
  double between(double lo, double hi) { return lo + (hi - lo) * unit(); }
  bool chance(double p) { return unit() < p; }
  int whole(int lo, int hi) { return lo + static_cast<int>(std::floor(unit() * (hi - lo + 1))); }

 private:
  std::mt19937_64 engine_;
};

std::string num(double value) {
  char text[32];
  std::snprintf(text, sizeof text, "%.4f", value);
  return text;
}

std::string header(RandomSceneKind kind, std::uint64_t seed, const char* what) {
  return "# Random scene, kind " + std::string(name(kind)) + ", seed " + std::to_string(seed) +
         " (stridemap scene random; docs/scenes.md).\n# " + what + "\n\n";
}

std::string flat_terrain(double reflectance) {
  return "terrain:\n  kind: flat\n  extent: {min_x_m: -0.5, min_y_m: -1.0, max_x_m: 2.5, max_y_m: 1.0}\n"
         "  base_elevation_m: 0.0\n  reflectance: " + num(reflectance) + "\n";
}

std::string rail() { return "\ncart_rail:\n  start_x_m: 0.0\n  end_x_m: 1.2\n  y_m: 0.0\n  step_m: 0.01\n"; }

std::string box_yaml(const std::string& box_name, double cx, double cy, double length, double width, double height,
                     double yaw, double reflectance) {
  return "  - {name: " + box_name + ", center_x_m: " + num(cx) + ", center_y_m: " + num(cy) +
         ", length_m: " + num(length) + ", width_m: " + num(width) + ", height_m: " + num(height) +
         ", yaw_rad: " + num(yaw) + ", reflectance: " + num(reflectance) + "}\n";
}

// Ragno's structured-light view across the rail at height h above the
// floor (about 0.40 m on the floor, 0.13 m at 0.2 m; docs/scenes.md), with
// a margin so that a measured object is seen whole.
double view_width_m(double height_m) { return 0.9 * (0.40 - 1.35 * height_m); }

// Where an object on the line occupies the rail's x range [x0, x1] out to
// |y| <= reach.
struct Occupied {
  double x0_m, x1_m, reach_m;
};

// Tall boxes beside the line; see random_scene_yaml.
std::string bystander_boxes(std::uint64_t seed, std::vector<Occupied> line) {
  Draw draw(seed ^ 0xB157A4DE55EEDULL);
  std::string out;
  const int wanted = draw.whole(1, 2);
  for (int k = 0; k < wanted; ++k) {
    const double length = draw.between(0.05, 0.12), width = draw.between(0.05, 0.10);
    const double height = draw.between(0.08, 0.16);
    const bool white = draw.chance(0.5);
    const double reflectance = white ? draw.between(0.75, 0.9) : draw.between(0.05, 0.2);
    const double side = draw.chance(0.5) ? 1.0 : -1.0;
    const double cx = draw.between(0.50, 1.35);
    double inner = draw.between(0.10, 0.15);
    for (const Occupied& o : line) {
      if (o.x1_m + 0.02 > cx - length / 2 && o.x0_m - 0.02 < cx + length / 2) inner = std::max(inner, o.reach_m + 0.03);
    }
    if (inner + width > 0.25) continue;  // no room beside this stretch of the line
    out += box_yaml(std::string(kBystanderPrefix) + std::to_string(k), cx, side * (inner + width / 2), length, width,
                    height, 0.0, reflectance);
    line.push_back({cx - length / 2, cx + length / 2, inner + width});  // the next one stands clear of it
  }
  return out;
}

std::string boxes_scene(std::uint64_t seed, bool bystanders) {
  Draw draw(seed);
  std::vector<Occupied> line;
  std::string boxes = "\nboxes:\n", cylinders;
  // From the paper's mount (0.26 m, 35 deg) the rail 0..1.2 m sweeps the
  // tops of objects up to 0.16 m high between x = 0.4 and 1.4 m.
  double next_x = 0.40 + draw.between(0.0, 0.05);
  const int wanted = draw.whole(2, 4);
  int placed = 0;
  for (int k = 0; k < wanted; ++k) {
    const bool can = k > 0 && draw.chance(0.2);
    const bool flat = draw.chance(0.3);
    double height = flat ? draw.between(0.015, 0.04) : draw.between(0.05, 0.16);
    const double reflectance = draw.between(0.1, 0.9);
    const double cy = draw.between(-0.03, 0.03);
    const std::string object_name = (can ? "can_" : "box_") + std::to_string(k);
    if (can) {
      const double radius = draw.between(0.03, 0.07);
      if (next_x + 2 * radius > 1.40) break;
      height = std::min(height, 0.12);
      cylinders += "  - {name: " + object_name + ", center_x_m: " + num(next_x + radius) + ", center_y_m: " +
                   num(cy) + ", radius_m: " + num(radius) + ", height_m: " + num(height) +
                   ", reflectance: " + num(reflectance) + "}\n";
      line.push_back({next_x, next_x + 2 * radius, std::abs(cy) + radius});
      next_x += 2 * radius;
    } else {
      double length = draw.between(0.05, 0.20), width = draw.between(0.05, 0.20);
      const double yaw = draw.chance(0.4) ? 0.0 : draw.between(-std::numbers::pi / 4, std::numbers::pi / 4);
      const double c = std::abs(std::cos(yaw)), s = std::abs(std::sin(yaw));
      // Narrow the box (keeping its proportions) until the view holds it.
      const double across = s * length + c * width;
      const double room = view_width_m(height) - 2 * std::abs(cy);
      if (across > room) {
        length *= room / across;
        width *= room / across;
      }
      const double along = c * length + s * width;
      if (next_x + along > 1.40) break;
      boxes += box_yaml(object_name, next_x + along / 2, cy, length, width, height, yaw, reflectance);
      line.push_back({next_x, next_x + along, std::abs(cy) + (s * length + c * width) / 2});
      next_x += along;
    }
    ++placed;
    next_x += draw.between(0.08, 0.15);  // room for the shadow's edge and the next top's view
  }
  (void)placed;
  const double floor_reflectance = draw.between(0.1, 0.9);
  if (bystanders) boxes += bystander_boxes(seed, line);
  return header(RandomSceneKind::boxes, seed,
                bystanders ? "Boxes and cans lined up on the rail, seen whole by both sensors; tall boxes beside them."
                           : "Boxes and cans lined up on the rail, seen whole by both sensors.") +
         flat_terrain(floor_reflectance) + boxes + (cylinders.empty() ? "" : "\ncylinders:\n" + cylinders) + rail();
}

std::string steps_scene(std::uint64_t seed) {
  Draw draw(seed);
  // Each block fits its place of the lattice at any yaw (side <= pitch / sqrt 2).
  const double pitch = draw.between(0.14, 0.20);
  const double empty_fraction = draw.between(0.3, 0.6);
  std::string boxes = "\nboxes:\n";
  int count = 0;
  for (int i = 0; 0.45 + (i + 1) * pitch <= 1.40; ++i) {
    for (int j = 0; -0.35 + (j + 1) * pitch <= 0.35; ++j) {
      const double empty = draw.unit();
      const double side_a = draw.between(0.6, 1.0) * pitch / std::numbers::sqrt2 - 0.005;
      const double side_b = draw.between(0.6, 1.0) * pitch / std::numbers::sqrt2 - 0.005;
      const double height = draw.chance(0.3) ? draw.between(0.015, 0.04) : draw.between(0.04, 0.12);
      const double yaw = draw.chance(0.4) ? 0.0 : draw.between(-std::numbers::pi / 4, std::numbers::pi / 4);
      const double reflectance = draw.between(0.1, 0.9);
      if (empty < empty_fraction) continue;
      boxes += box_yaml("block_" + std::to_string(i) + "_" + std::to_string(j), 0.45 + (i + 0.5) * pitch,
                        -0.35 + (j + 0.5) * pitch, side_a, side_b, height, yaw, reflectance);
      ++count;
    }
  }
  std::string text = header(RandomSceneKind::steps, seed, "A field of blocks of random size, height and yaw.") +
                     flat_terrain(draw.between(0.1, 0.9));
  if (count > 0) text += boxes;
  return text + rail();
}

std::string rocky_scene(std::uint64_t seed) {
  Draw draw(seed);
  const auto terrain_seed = static_cast<std::uint64_t>(draw.whole(0, 1000000));
  std::string text = header(RandomSceneKind::rocky, seed,
                            "Uneven ground with boulders in three size classes, and a walk across them.");
  text += "terrain:\n  kind: procedural\n  seed: " + std::to_string(terrain_seed) +
          "\n  extent: {min_x_m: 0.0, min_y_m: -1.0, max_x_m: 2.0, max_y_m: 1.0}\n  resolution_m: 0.005\n"
          "  amplitude_m: " + num(draw.between(0.01, 0.03)) + "\n  wavelength_m: " + num(draw.between(0.3, 0.7)) +
          "\n  octaves: 3\n  reflectance: " + num(draw.between(0.15, 0.7)) +
          "\n  rocks_area: {min_x_m: 0.55, min_y_m: -0.9, max_x_m: 1.95, max_y_m: 0.9}\n  rocks:\n";
  const auto rock_class = [&](int lo, int hi, double r0, double r1, double h0, double h1) {
    text += "    - {count: " + std::to_string(draw.whole(lo, hi)) + ", min_radius_m: " + num(r0) +
            ", max_radius_m: " + num(r1) + ", min_height_m: " + num(h0) + ", max_height_m: " + num(h1) + "}\n";
  };
  rock_class(2, 6, 0.12, 0.20, 0.06, 0.11);
  rock_class(6, 14, 0.05, 0.11, 0.03, 0.07);
  rock_class(15, 35, 0.02, 0.045, 0.01, 0.03);
  // The mock-up's path (known to stay on the patch), mirrored at random and
  // with its lengths varied a little.
  const double side = draw.chance(0.5) ? 1.0 : -1.0;
  const double start_y = side * draw.between(-0.5, -0.4);
  text += "\nwalk_path:\n  start: {x_m: " + num(draw.between(0.2, 0.3)) + ", y_m: " + num(start_y) +
          ", yaw_deg: 0}\n  segments:\n    - straight_m: " + num(draw.between(0.75, 0.9)) +
          "\n    - {turn_deg: " + num(side * 90) + ", radius_m: 0.3}\n    - straight_m: " +
          num(draw.between(0.2, 0.35)) + "\n    - turn_deg: " + num(side * 90) +
          "\n    - straight_m: " + num(draw.between(0.6, 0.75)) + "\n    - {turn_deg: " + num(-side * 60) +
          ", radius_m: 0.4}\n    - straight_m: 0.2\n";
  return text;
}

}  // namespace

std::string random_scene_yaml(RandomSceneKind kind, std::uint64_t seed, bool bystanders) {
  switch (kind) {
    case RandomSceneKind::rocky: return rocky_scene(seed);
    case RandomSceneKind::steps: return steps_scene(seed);
    case RandomSceneKind::boxes: break;
  }
  return boxes_scene(seed, bystanders);
}

}  // namespace stridemap
