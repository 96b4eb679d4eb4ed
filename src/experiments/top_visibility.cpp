#include "stridemap/experiments/top_visibility.hpp"

#include <cmath>
#include <cstdint>
#include <string>
#include <unordered_map>

#include "stridemap/core/error.hpp"

namespace stridemap {

TopVisibility::TopVisibility(const Scene& scene, double reach_m, const TopVisibilityOptions& options)
    : reach_m_(reach_m), options_(options) {
  const auto positive = [](double v, const char* what) {
    if (!(v > 0.0) || !std::isfinite(v)) {
      throw InputError(std::string("top visibility: ") + what + " must be positive and finite, got " +
                       std::to_string(v));
    }
  };
  positive(reach_m, "reach_m");
  positive(options.sample_spacing_m, "sample_spacing_m");
  positive(options.top_tolerance_m, "top_tolerance_m");
  if (!(options.rim_inset_m >= 0.0)) throw InputError("top visibility: rim_inset_m must not be negative");
  for (const BoxObject& box : scene.boxes) {
    tops_.push_back({{box.center_x_m, box.center_y_m}, box.yaw_rad, box.length_m / 2, box.width_m / 2, 0.0,
                     box.top_m()});
  }
  for (const CylinderObject& cylinder : scene.cylinders) {
    tops_.push_back({{cylinder.center_x_m, cylinder.center_y_m}, 0.0, 0.0, 0.0, cylinder.radius_m, cylinder.top_m()});
  }
  hits_.resize(tops_.size());
}

void TopVisibility::add_hit(int object_index, const Eigen::Vector3d& point_m) {
  if (object_index < 0 || static_cast<std::size_t>(object_index) >= tops_.size()) return;
  const auto index = static_cast<std::size_t>(object_index);
  // A hit on a side face says nothing about the top.
  if (!(point_m.z() >= tops_[index].top_m - options_.top_tolerance_m)) return;
  hits_[index].push_back(point_m.head<2>());
}

std::vector<double> TopVisibility::seen_shares() const {
  std::vector<double> shares;
  shares.reserve(tops_.size());
  for (std::size_t k = 0; k < tops_.size(); ++k) shares.push_back(seen_share(tops_[k], hits_[k]));
  return shares;
}

double TopVisibility::seen_share(const Top& top, const std::vector<Eigen::Vector2d>& hits) const {
  // Hits in buckets one reach wide: a sample looks in its own and the eight
  // around it.
  const auto bucket_of = [&](const Eigen::Vector2d& p) {
    const auto bx = static_cast<std::int64_t>(std::floor(p.x() / reach_m_));
    const auto by = static_cast<std::int64_t>(std::floor(p.y() / reach_m_));
    return std::pair{bx, by};
  };
  const auto key = [](std::int64_t bx, std::int64_t by) {
    return (static_cast<std::uint64_t>(bx) * 0x9E3779B97F4A7C15ULL) ^ static_cast<std::uint64_t>(by);
  };
  std::unordered_multimap<std::uint64_t, Eigen::Vector2d> buckets;
  for (const Eigen::Vector2d& h : hits) {
    const auto [bx, by] = bucket_of(h);
    buckets.emplace(key(bx, by), h);
  }
  const double reach_sq = reach_m_ * reach_m_;
  const auto seen = [&](const Eigen::Vector2d& p) {
    const auto [bx, by] = bucket_of(p);
    for (std::int64_t dx = -1; dx <= 1; ++dx) {
      for (std::int64_t dy = -1; dy <= 1; ++dy) {
        const auto [first, last] = buckets.equal_range(key(bx + dx, by + dy));
        for (auto it = first; it != last; ++it)
          if ((it->second - p).squaredNorm() <= reach_sq) return true;
      }
    }
    return false;
  };

  const double step = options_.sample_spacing_m;
  const bool round = top.radius_m > 0.0;
  const double half_u = (round ? top.radius_m : top.half_length_m) - options_.rim_inset_m;
  const double half_v = (round ? top.radius_m : top.half_width_m) - options_.rim_inset_m;
  if (!(half_u > 0.0) || !(half_v > 0.0)) return hits.empty() ? 0.0 : 1.0;  // smaller than the inset
  const Eigen::Vector2d u(std::cos(top.yaw_rad), std::sin(top.yaw_rad));
  const Eigen::Vector2d v(-u.y(), u.x());
  const auto count_u = static_cast<int>(std::floor(half_u / step));
  const auto count_v = static_cast<int>(std::floor(half_v / step));
  std::size_t samples = 0, seen_samples = 0;
  for (int i = -count_u; i <= count_u; ++i) {
    for (int j = -count_v; j <= count_v; ++j) {
      const double a = i * step, b = j * step;
      if (round && a * a + b * b > half_u * half_u) continue;
      ++samples;
      seen_samples += seen(top.centre_m + a * u + b * v);
    }
  }
  return samples ? static_cast<double>(seen_samples) / static_cast<double>(samples) : 0.0;
}

}  // namespace stridemap
