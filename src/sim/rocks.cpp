#include "stridemap/sim/rocks.hpp"

#include <algorithm>
#include <cmath>
#include <numbers>
#include <random>

#include "stridemap/sim/height_field.hpp"
#include "stridemap/sim/scene_problem.hpp"

namespace stridemap {
namespace {

// At most this many rocks in all: more is a typo in a count.
constexpr int kMaxRocks = 100'000;

struct Rock {
  double x = 0, y = 0, cos_yaw = 1, sin_yaw = 0;
  double semi_major = 0, semi_minor = 0, height = 0;
};

}  // namespace

std::optional<SceneProblem> rock_field_problem(const RockFieldOptions& o) {
  using namespace scene_rules;
  const auto problem = [](std::string field, std::string message) {
    return std::optional<SceneProblem>(SceneProblem{std::move(field), "", std::move(message)});
  };
  long long total = 0;
  for (std::size_t k = 0; k < o.classes.size(); ++k) {
    const RockClass& c = o.classes[k];
    const std::string at = "rocks[" + std::to_string(k) + "].";
    if (c.count < 0) return problem(at + "count", "expected a whole number >= 0, got " + std::to_string(c.count));
    total += c.count;
    if (total > kMaxRocks) return problem(at + "count", "more than " + std::to_string(kMaxRocks) + " rocks in all");
    if (auto m = positive(c.min_radius_m)) return problem(at + "min_radius_m", *m);
    if (auto m = positive(c.max_radius_m)) return problem(at + "max_radius_m", *m);
    if (c.max_radius_m < c.min_radius_m) {
      return problem(at + "max_radius_m", "expected a number >= min_radius_m = " + format_number(c.min_radius_m) +
                                              ", got " + format_number(c.max_radius_m));
    }
    if (auto m = positive(c.min_height_m)) return problem(at + "min_height_m", *m);
    if (auto m = positive(c.max_height_m)) return problem(at + "max_height_m", *m);
    if (c.max_height_m < c.min_height_m) {
      return problem(at + "max_height_m", "expected a number >= min_height_m = " + format_number(c.min_height_m) +
                                              ", got " + format_number(c.max_height_m));
    }
  }
  if (o.area) {
    const auto& a = *o.area;
    const char* names[] = {"rocks_area.min_x_m", "rocks_area.min_y_m", "rocks_area.max_x_m", "rocks_area.max_y_m"};
    for (int k = 0; k < 4; ++k) {
      if (auto m = finite(a[k])) return problem(names[k], *m);
    }
    if (!(a[2] > a[0])) return problem(names[2], "expected a number greater than min_x_m = " + format_number(a[0]));
    if (!(a[3] > a[1])) return problem(names[3], "expected a number greater than min_y_m = " + format_number(a[1]));
  }
  if (!(o.min_aspect > 0.0 && o.min_aspect <= 1.0)) {
    return problem("rocks_min_aspect", "expected a number in (0, 1], got " + format_number(o.min_aspect));
  }
  if (!(std::isfinite(o.profile_exponent) && o.profile_exponent >= 1.0)) {
    return problem("rocks_profile_exponent", "expected a number >= 1, got " + format_number(o.profile_exponent));
  }
  if (!(o.buried_fraction >= 0.0 && o.buried_fraction < 1.0)) {
    return problem("rocks_buried_fraction", "expected a number in [0, 1), got " + format_number(o.buried_fraction));
  }
  return std::nullopt;
}

void add_rocks(const RockFieldOptions& options, std::uint64_t seed, HeightField& field) {
  if (options.classes.empty() || field.is_flat()) return;
  // Its own stream, so rocks never change the ground drawn from `seed`.
  std::mt19937_64 rng(seed ^ 0x9E3779B97F4A7C15ULL);
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  const auto between = [&](double lo, double hi) { return lo + (hi - lo) * unit(rng); };
  const std::array<double, 4> area =
      options.area.value_or(std::array<double, 4>{field.min_x_m, field.min_y_m, field.max_x_m, field.max_y_m});

  std::vector<Rock> rocks;
  for (const RockClass& c : options.classes) {
    for (int k = 0; k < c.count; ++k) {
      Rock r;
      r.x = between(area[0], area[2]);
      r.y = between(area[1], area[3]);
      const double yaw = between(0.0, std::numbers::pi);
      r.cos_yaw = std::cos(yaw);
      r.sin_yaw = std::sin(yaw);
      r.semi_major = between(c.min_radius_m, c.max_radius_m);
      r.semi_minor = r.semi_major * between(options.min_aspect, 1.0);
      r.height = between(c.min_height_m, c.max_height_m);
      rocks.push_back(r);
    }
  }
  // The ground under each centre before any rock is added, so that
  // overlapping rocks do not stack on each other's tops.
  std::vector<double> ground(rocks.size());
  for (std::size_t k = 0; k < rocks.size(); ++k) ground[k] = field.height_at(rocks[k].x, rocks[k].y);

  // A cell index limited to [-1, n] while still a double: a rock far off the
  // grid (a rocks area 1e308 m wide in a scene file) would overflow int.
  // -1 and n keep such a rock's range empty, as the unlimited index would.
  const auto cell_index = [](double cell, int n) {
    if (!(cell > -1.0)) return -1;  // NaN too
    return cell < static_cast<double>(n) ? static_cast<int>(cell) : n;
  };
  const double p = options.profile_exponent, s = options.buried_fraction;
  for (std::size_t k = 0; k < rocks.size(); ++k) {
    const Rock& r = rocks[k];
    const int i0 = std::max(0, cell_index(std::floor((r.x - r.semi_major - field.min_x_m) / field.resolution_m), field.nx));
    const int i1 = std::min(field.nx - 1, cell_index(std::ceil((r.x + r.semi_major - field.min_x_m) / field.resolution_m), field.nx));
    const int j0 = std::max(0, cell_index(std::floor((r.y - r.semi_major - field.min_y_m) / field.resolution_m), field.ny));
    const int j1 = std::min(field.ny - 1, cell_index(std::ceil((r.y + r.semi_major - field.min_y_m) / field.resolution_m), field.ny));
    for (int j = j0; j <= j1; ++j) {
      for (int i = i0; i <= i1; ++i) {
        const double dx = field.min_x_m + i * field.resolution_m - r.x;
        const double dy = field.min_y_m + j * field.resolution_m - r.y;
        const double u = (r.cos_yaw * dx + r.sin_yaw * dy) / r.semi_major;
        const double v = (-r.sin_yaw * dx + r.cos_yaw * dy) / r.semi_minor;
        const double rho = std::sqrt(u * u + v * v);
        if (rho >= 1.0) continue;
        const double z = ground[k] - s * r.height + (1.0 + s) * r.height * std::pow(1.0 - std::pow(rho, p), 1.0 / p);
        float& sample = field.samples[static_cast<std::size_t>(j) * static_cast<std::size_t>(field.nx) + i];
        sample = std::max(sample, static_cast<float>(z));
      }
    }
  }
}

}  // namespace stridemap
