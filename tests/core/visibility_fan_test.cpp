// VisibilityClearing::trace_fan() (core/visibility_clearing.hpp) against
// trace() beam by beam, the reference: on random terrain and fans with
// invalid beams among them (NaN and infinite hits, non-finite errors,
// range errors below 0 and beyond the range), the same beams thinned and
// traced, every layer, count and cleared cell the same bit for bit; and
// the same map and counts as the full walk (core/visibility_full_walk.hpp).
#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <random>
#include <vector>

#include "core/visibility_full_walk.hpp"
#include "stridemap/core/visibility_clearing.hpp"

namespace stridemap {
namespace {

using test::FullWalk;
using test::expect_same_maps;

ElevationMap random_floor_with_blocks(std::mt19937_64& rng, int n, double cell_m) {
  ElevationMap map(GridOptions{n, cell_m});
  std::uniform_int_distribution<int> corner(-2 * n, 2 * n);
  map.move_corner_to({corner(rng), corner(rng)});
  std::uniform_real_distribution<double> u(0.0, 1.0);
  const CellIndex lo = map.min_cell();
  for (int i = 0; i < n; ++i) {
    for (int j = 0; j < n; ++j) {
      if (u(rng) < 0.1) continue;  // unknown
      const bool block = (i / 6 + j / 7) % 5 == 0;
      const std::size_t s = map.slot({lo.x + i, lo.y + j});
      map.elevation_data()[s] = static_cast<float>(0.004 * (u(rng) - 0.5) + (block ? 0.12 : 0.0));
      map.state_data()[s] = static_cast<std::uint8_t>(CellState::measured);
      map.certainty_data()[s] = static_cast<float>(1 + std::uniform_int_distribution<int>(0, 9)(rng));
    }
  }
  return map;
}

// A fan's beams as arrays: given to trace_fan() at once, or one by one.
struct FanBeams {
  Eigen::Vector3d origin = Eigen::Vector3d::Zero();
  std::vector<double> x, y, z, range_error, height_error;

  VisibilityFan fan() const {
    return {origin, x.size(), x.data(), y.data(), z.data(), height_error.data(), range_error.data()};
  }
  template <typename Trace>
  void each(Trace&& trace) const {
    for (std::size_t k = 0; k < x.size(); ++k) {
      VisibilityBeam beam;
      beam.origin_m = origin;
      beam.hit_m = {x[k], y[k], z[k]};
      beam.range_error_m = range_error[k];
      beam.height_error_m = height_error[k];
      trace(beam);
    }
  }
};

// The fan traced at once against the same beams one by one: maps, account,
// cells crossed and where the thinning goes on from.
void expect_fan_as_beams(const VisibilityClearing& by_fan, const ElevationMap& fan_map,
                         const VisibilityClearing& by_beam, const ElevationMap& beam_map, const FanBeams& beams) {
  expect_same_maps(fan_map, beam_map);
  test::expect_same_account(by_fan, by_beam);
  EXPECT_EQ(by_fan.stats().cells_crossed, by_beam.stats().cells_crossed);
  EXPECT_EQ(by_fan.thinned(beams.x[0], beams.y[0]), by_beam.thinned(beams.x[0], beams.y[0]));
}

TEST(VisibilityFan, TracesTheSameBeamsAsTraceOneByOne) {
  constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();
  constexpr double kInf = std::numeric_limits<double>::infinity();
  std::size_t traced = 0, contradicted = 0;
  for (std::uint64_t seed = 1; seed <= 30; ++seed) {
    SCOPED_TRACE("seed " + std::to_string(seed));
    std::mt19937_64 rng(seed);
    std::uniform_real_distribution<double> u(0.0, 1.0);
    const int n = 48;
    const double cell = 0.01;
    ElevationMap fan_map = random_floor_with_blocks(rng, n, cell);
    ElevationMap beam_map = fan_map, full_map = fan_map;
    VisibilityOptions options;
    options.beam_spacing_cells = seed % 3 == 0 ? 0.0 : 0.5;
    VisibilityClearing by_fan(fan_map, options), by_beam(beam_map, options);
    FullWalk full(full_map, options);
    const Eigen::Vector2d lo(fan_map.min_cell().x * cell, fan_map.min_cell().y * cell);
    for (int scan = 0; scan < 3; ++scan) {
      const Eigen::Vector3d origin(lo.x() + n * cell * u(rng), lo.y() + n * cell * u(rng), 0.05 + 0.3 * u(rng));
      FanBeams beams;
      beams.origin = origin;
      auto &x = beams.x, &y = beams.y, &z = beams.z, &range_error = beams.range_error,
           &height_error = beams.height_error;
      for (int k = 0; k < 400; ++k) {
        const double angle = 2.0 * M_PI * k / 400.0, reach = n * cell * (0.1 + 0.8 * u(rng));
        x.push_back(origin.x() + reach * std::cos(angle));
        y.push_back(origin.y() + reach * std::sin(angle));
        const double kind = u(rng);
        z.push_back(kind < 0.1 ? origin.z() + 0.1 * u(rng) : kind < 0.15 ? origin.z() : 0.15 * u(rng) - 0.02);
        const double range = std::sqrt(reach * reach + (z.back() - origin.z()) * (z.back() - origin.z()));
        range_error.push_back(u(rng) < 0.05 ? -0.01 * u(rng) : u(rng) < 0.05 ? range * (1.0 + u(rng)) : 0.01);
        height_error.push_back(0.005 * u(rng));
        const double broken = u(rng);  // now and then an invalid beam
        if (broken < 0.01) x.back() = kNaN;
        else if (broken < 0.02) z.back() = kInf;
        else if (broken < 0.03) range_error.back() = kNaN;
        else if (broken < 0.04) height_error.back() = kInf;
        else if (broken < 0.05) x.back() = origin.x(), y.back() = origin.y(), z.back() = origin.z();
      }
      by_fan.begin_scan(fan_map);
      by_beam.begin_scan(beam_map);
      full.begin_scan();
      by_fan.trace_fan(fan_map, beams.fan());
      beams.each([&](const VisibilityBeam& beam) {
        by_beam.trace(beam_map, beam);
        full.trace(full_map, beam);
      });
      expect_fan_as_beams(by_fan, fan_map, by_beam, beam_map, beams);
      expect_same_maps(fan_map, full_map);
      EXPECT_EQ(by_fan.stats().beams_traced, full.stats().beams_traced);
      EXPECT_EQ(by_fan.stats().cells_contradicted, full.stats().cells_contradicted);
      EXPECT_EQ(by_fan.stats().cells_cleared, full.stats().cells_cleared);
      traced += by_fan.stats().beams_traced;
      contradicted += by_fan.stats().cells_contradicted;
    }
  }
  EXPECT_GT(traced, 10000u);
  EXPECT_GT(contradicted, 100u);
}

// trace_fan() screens its traced beams together, in batches and vectors of
// four, before walking the rest in order: fans of every length around
// those sizes, from origins that settle nearly every beam (high above the
// floor) or almost none (among the blocks), level and rising beams, stops
// beyond the hit (a range error below 0), an empty window and one far from
// the origin, all against trace() beam by beam.
TEST(VisibilityFan, ScreenedBeamsAgreeWithBeamByBeam) {
  std::size_t traced = 0, contradicted = 0;
  for (std::uint64_t seed = 1; seed <= 40; ++seed) {
    SCOPED_TRACE("seed " + std::to_string(seed));
    std::mt19937_64 rng(seed);
    std::uniform_real_distribution<double> u(0.0, 1.0);
    const int n = 40;
    const double cell = 0.02;
    ElevationMap fan_map = seed % 10 == 0 ? ElevationMap(GridOptions{n, cell}) : random_floor_with_blocks(rng, n, cell);
    ElevationMap beam_map = fan_map;
    VisibilityOptions options;
    options.beam_spacing_cells = seed % 2 == 0 ? 0.0 : 0.25;
    VisibilityClearing by_fan(fan_map, options), by_beam(beam_map, options);
    const Eigen::Vector2d lo(fan_map.min_cell().x * cell, fan_map.min_cell().y * cell);
    for (int scan = 0; scan < 4; ++scan) {
      const double height = scan == 0 ? 2.0 : scan == 1 ? 0.13 : 0.02 + 0.4 * u(rng);
      const double away = seed % 7 == 0 ? 3.0 * n * cell : 0.0;  // an origin outside the window
      const Eigen::Vector3d origin(lo.x() + away + n * cell * u(rng), lo.y() + n * cell * u(rng), height);
      const std::size_t count = 120 + 3 * seed + static_cast<std::size_t>(scan) * 61;
      FanBeams beams;
      beams.origin = origin;
      auto &x = beams.x, &y = beams.y, &z = beams.z, &range_error = beams.range_error,
           &height_error = beams.height_error;
      for (std::size_t k = 0; k < count; ++k) {
        const double angle = 2.0 * M_PI * static_cast<double>(k) / static_cast<double>(count);
        const double reach = n * cell * (0.05 + 1.2 * u(rng));
        x.push_back(origin.x() + reach * std::cos(angle));
        y.push_back(origin.y() + reach * std::sin(angle));
        const double kind = u(rng);
        z.push_back(kind < 0.1 ? origin.z() + 0.2 * u(rng) : kind < 0.2 ? origin.z() : 0.15 * u(rng) - 0.02);
        const double error = u(rng);
        range_error.push_back(error < 0.1 ? -0.05 * u(rng) : error < 0.15 ? 0.0 : 0.02 * u(rng));
        height_error.push_back(u(rng) < 0.1 ? 0.0 : 0.01 * u(rng));
        if (u(rng) < 0.02) z.back() = std::numeric_limits<double>::quiet_NaN();
      }
      by_fan.begin_scan(fan_map);
      by_beam.begin_scan(beam_map);
      by_fan.trace_fan(fan_map, beams.fan());
      beams.each([&](const VisibilityBeam& beam) { by_beam.trace(beam_map, beam); });
      expect_fan_as_beams(by_fan, fan_map, by_beam, beam_map, beams);
      traced += by_fan.stats().beams_traced;
      contradicted += by_fan.stats().cells_contradicted;
    }
  }
  EXPECT_GT(traced, 10000u);
  EXPECT_GT(contradicted, 100u);
}

// A range error of any finite size is a number a caller may pass; one that
// puts the stop more than a thousand ranges past the hit is no sensor's,
// and such a beam is left out by both ways of tracing.
TEST(VisibilityFan, AStopFarPastTheHitIsNotTraced) {
  ElevationMap map(GridOptions{20, 0.01});
  VisibilityClearing clearing(map, VisibilityOptions{});
  const Eigen::Vector3d origin(0.02, 0.1, 0.3);
  const double x = 0.15, y = 0.1, z = 0.0, height_error = 0.005;
  const double range = (Eigen::Vector3d(x, y, z) - origin).norm();
  for (const double range_error : {-1001.0 * range, -1e300}) {
    clearing.begin_scan(map);
    clearing.trace_fan(map, {origin, 1, &x, &y, &z, &height_error, &range_error});
    clearing.trace(map, {origin, {x, y, z}, range_error, height_error});
    EXPECT_EQ(clearing.stats().beams_traced, 0u) << range_error;
  }
  clearing.begin_scan(map);
  const double near_limit = -999.0 * range;
  clearing.trace_fan(map, {origin, 1, &x, &y, &z, &height_error, &near_limit});
  EXPECT_EQ(clearing.stats().beams_traced, 1u);
}

TEST(VisibilityFan, AnOriginNotFiniteTracesNothing) {
  ElevationMap map(GridOptions{20, 0.01});
  VisibilityClearing clearing(map, VisibilityOptions{});
  clearing.begin_scan(map);
  const double x = 0.1, y = 0.1, z = 0.0, range_error = 0.01, height_error = 0.005;
  const Eigen::Vector3d origin(std::numeric_limits<double>::quiet_NaN(), 0.0, 0.3);
  clearing.trace_fan(map, {origin, 1, &x, &y, &z, &height_error, &range_error});
  EXPECT_EQ(clearing.stats().beams_traced, 0u);
  EXPECT_FALSE(clearing.thinned(x, y));
}

}  // namespace
}  // namespace stridemap
