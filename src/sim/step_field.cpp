#include "stridemap/sim/step_field.hpp"

#include <cmath>
#include <random>

#include "stridemap/core/error.hpp"

namespace stridemap {

std::optional<std::string> StepFieldOptions::first_problem() const {
  using namespace scene_rules;
  for (const auto& [field, value] : {std::pair<const char*, double>{"min_x_m", min_x_m}, {"min_y_m", min_y_m},
                                     {"max_x_m", max_x_m}, {"max_y_m", max_y_m}}) {
    if (auto m = finite(value)) return std::string(field) + ": " + *m;
  }
  if (!(max_x_m > min_x_m) || !(max_y_m > min_y_m)) return "max_x_m, max_y_m: expected an area of positive size";
  if (auto m = positive(block_size_m)) return "block_size_m: " + *m;
  if ((max_x_m - min_x_m) / block_size_m * (max_y_m - min_y_m) / block_size_m > 1e6) {
    return "block_size_m: more than a million blocks over the area";
  }
  if (auto m = non_negative(min_height_m)) return "min_height_m: " + *m;
  if (auto m = positive(max_height_m)) return "max_height_m: " + *m;
  if (max_height_m < min_height_m) return "max_height_m: expected a number >= min_height_m";
  if (!(empty_fraction >= 0.0 && empty_fraction < 1.0)) {
    return "empty_fraction: expected a number in [0, 1), got " + format_number(empty_fraction);
  }
  if (auto m = non_negative(margin_m)) return "margin_m: " + *m;
  if (auto m = scene_rules::reflectance(reflectance)) return "reflectance: " + *m;
  return std::nullopt;
}

Scene make_step_field(const StepFieldOptions& o, std::uint64_t seed) {
  if (auto problem = o.first_problem()) throw InputError("step field options: " + *problem);
  Scene scene;
  scene.terrain.min_x_m = o.min_x_m - o.margin_m;
  scene.terrain.min_y_m = o.min_y_m - o.margin_m;
  scene.terrain.max_x_m = o.max_x_m + o.margin_m;
  scene.terrain.max_y_m = o.max_y_m + o.margin_m;
  scene.terrain.reflectance = o.reflectance;
  std::mt19937_64 rng(seed);
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  const int nx = static_cast<int>(std::floor((o.max_x_m - o.min_x_m) / o.block_size_m + 1e-9));
  const int ny = static_cast<int>(std::floor((o.max_y_m - o.min_y_m) / o.block_size_m + 1e-9));
  for (int i = 0; i < nx; ++i) {
    for (int j = 0; j < ny; ++j) {
      // Draw both numbers for every place, so that the heights of a seed do
      // not depend on the empty fraction's decisions elsewhere.
      const double empty = unit(rng), height = unit(rng);
      if (empty < o.empty_fraction) continue;
      BoxObject box;
      box.name = "block_" + std::to_string(i) + "_" + std::to_string(j);
      box.center_x_m = o.min_x_m + (i + 0.5) * o.block_size_m;
      box.center_y_m = o.min_y_m + (j + 0.5) * o.block_size_m;
      box.length_m = box.width_m = o.block_size_m;
      box.height_m = std::max(1e-3, o.min_height_m + (o.max_height_m - o.min_height_m) * height);
      box.reflectance = o.reflectance;
      scene.boxes.push_back(box);
    }
  }
  scene.validate();
  return scene;
}

}  // namespace stridemap
