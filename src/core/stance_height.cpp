#include "stridemap/core/stance_height.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <string>
#include <utility>

#include "stridemap/core/error.hpp"

namespace stridemap {
namespace {

/// A sole's reach in cells is bounded so that its cells fit a stack array.
constexpr int kMaxSoleReach = 8;
constexpr int kMaxSoleCells = (2 * kMaxSoleReach + 1) * (2 * kMaxSoleReach + 1);

std::string number(double value) {
  char text[32];
  std::snprintf(text, sizeof text, "%g", value);
  return text;
}

LayerId<float> fused_layer(const ElevationMap& map, const char* name) {
  const std::optional<std::size_t> index = map.find_layer(name);
  if (!index || map.layer_spec(*index).type != LayerType::f32) {
    throw InputError(std::string("stance height: the map needs the layer ") + name +
                     " (f32; HeightFusion or HeightFusionObserver adds it); the map has " + map.layer_names());
  }
  return LayerId<float>{*index};
}

}  // namespace

void StanceHeightOptions::validate() const {
  const auto fail = [](const char* field, const char* expected, double value) {
    throw InputError(std::string("stance height options: ") + field + ": expected " + expected + ", got " +
                     number(value));
  };
  if (!(std::isfinite(sole_radius_m) && sole_radius_m > 0.0)) fail("sole_radius_m", "a positive number", sole_radius_m);
  if (!(min_known_share >= 0.0 && min_known_share <= 1.0)) fail("min_known_share", "a number from 0 to 1", min_known_share);
  if (!(gate_sigmas > 0.0)) fail("gate_sigmas", "a number > 0 (or infinity)", gate_sigmas);
  if (!(std::isfinite(depth_sigma_m) && depth_sigma_m >= 0.0)) fail("depth_sigma_m", "a number >= 0", depth_sigma_m);
}

StanceHeightReader::StanceHeightReader(const ElevationMap& map, const StanceHeightOptions& options)
    : options_(options) {
  options_.validate();
  elevation_ = fused_layer(map, "fused_elevation");
  variance_ = fused_layer(map, "fused_variance");
}

std::optional<SoleGround> StanceHeightReader::ground_under(const ElevationMap& map, double x_m, double y_m) const {
  const CellIndex centre = map.cell_of(x_m, y_m);
  const int reach =
      std::clamp(static_cast<int>(std::lround(options_.sole_radius_m / map.cell_size_m())), 1, kMaxSoleReach);
  const float* elevation = map.data(elevation_);
  const float* variance = map.data(variance_);
  std::array<float, kMaxSoleCells> heights{}, variances{};
  int count = 0, cells = 0;
  for (int dx = -reach; dx <= reach; ++dx) {
    for (int dy = -reach; dy <= reach; ++dy) {
      if (dx * dx + dy * dy > reach * reach) continue;
      ++cells;
      const CellIndex c{centre.x + dx, centre.y + dy};
      if (!map.contains(c)) continue;
      const std::size_t slot = map.slot(c);
      const float h = elevation[slot], v = variance[slot];
      if (!(h == h && v == v)) continue;
      heights[static_cast<std::size_t>(count)] = h;
      variances[static_cast<std::size_t>(count)] = v;
      ++count;
    }
  }
  if (count == 0) return std::nullopt;
  // Medians, so that one stray cell (a mixed pixel the gate let in, a
  // rock's edge) does not move the whole robot.
  SoleGround ground;
  ground.known_share = static_cast<double>(count) / cells;
  std::array<float, kMaxSoleCells> sorted = heights;
  std::nth_element(sorted.begin(), sorted.begin() + count / 2, sorted.begin() + count);
  ground.height_m = sorted[static_cast<std::size_t>(count / 2)];
  double spread = 0.0;
  for (int k = 0; k < count; ++k) {
    const double d = heights[static_cast<std::size_t>(k)] - ground.height_m;
    spread += d * d;
  }
  ground.spread_m2 = spread / count;
  std::nth_element(variances.begin(), variances.begin() + count / 2, variances.begin() + count);
  ground.variance_m2 = variances[static_cast<std::size_t>(count / 2)];
  return ground;
}

StanceHeight StanceHeightReader::read(const ElevationMap& map, std::span<const StanceFoot> feet) const {
  if (feet.size() > StanceHeight::kMaxFeet) {
    throw InputError("stance height: " + std::to_string(feet.size()) + " feet given, at most " +
                     std::to_string(StanceHeight::kMaxFeet));
  }
  for (std::size_t k = 0; k < feet.size(); ++k) {
    const StanceFoot& f = feet[k];
    for (const auto& [field, value] : {std::pair{"x_m", f.x_m}, std::pair{"y_m", f.y_m}, std::pair{"depth_m", f.depth_m}}) {
      if (std::isfinite(value)) continue;
      throw InputError("stance height: foot " + std::to_string(k) + ": " + field + ": expected a finite number, got " +
                       number(value));
    }
  }
  StanceHeight out;
  const double depth_variance = options_.depth_sigma_m * options_.depth_sigma_m;
  for (std::size_t k = 0; k < feet.size(); ++k) {
    const std::optional<SoleGround> ground = ground_under(map, feet[k].x_m, feet[k].y_m);
    if (!ground || ground->known_share < options_.min_known_share) continue;
    StanceFootHeight& foot = out.feet[k];
    foot.read = foot.used = true;
    foot.ground_m = ground->height_m;
    foot.trunk_z_m = ground->height_m + feet[k].depth_m;
    foot.variance_m2 = ground->variance_m2 + ground->spread_m2 + depth_variance;
    ++out.feet_read;
  }
  const std::size_t n_feet = feet.size();
  const auto weighted_mean = [&](std::size_t skip, double& mean, double& variance) {
    double weight_sum = 0.0, sum = 0.0;
    for (std::size_t k = 0; k < n_feet; ++k) {
      const StanceFootHeight& foot = out.feet[k];
      if (!foot.used || k == skip) continue;
      weight_sum += 1.0 / foot.variance_m2;
      sum += foot.trunk_z_m / foot.variance_m2;
    }
    mean = sum / weight_sum;
    variance = 1.0 / weight_sum;
  };
  // Leave one out, as elevation_mapping gates a reading against its cell:
  // drop the foot that disagrees most with the rest while it is beyond the
  // gate and two feet remain.
  const double gate2 = options_.gate_sigmas * options_.gate_sigmas;
  int used = out.feet_read;
  while (used > 2) {
    std::size_t worst = n_feet;
    double worst_d2 = gate2;
    for (std::size_t k = 0; k < n_feet; ++k) {
      const StanceFootHeight& foot = out.feet[k];
      if (!foot.used) continue;
      double mean = 0.0, variance = 0.0;
      weighted_mean(k, mean, variance);
      const double d2 = (foot.trunk_z_m - mean) * (foot.trunk_z_m - mean) / (foot.variance_m2 + variance);
      if (d2 > worst_d2) {
        worst_d2 = d2;
        worst = k;
      }
    }
    if (worst == n_feet) break;
    out.feet[worst].used = false;
    --used;
  }
  out.feet_used = used;
  if (used > 0) weighted_mean(n_feet, out.trunk_z_m, out.variance_m2);
  return out;
}

}  // namespace stridemap
