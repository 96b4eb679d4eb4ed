// The visibility clean-up (core/visibility_clearing.hpp) on scans drawn from
// the bytes: a small window of unknown, measured and filled cells, a fan's
// origin and its beams, realistic or any double (NaN, infinities, huge,
// negative errors, a hit on the origin). Scans are device bytes and poses
// turned into points, so nothing in them may crash the clean-up; and
// trace_fan(), which screens its beams together (four to a vector where the
// CPU has AVX2) and walks the rest, must leave the map and the scan's account
// exactly as tracing the same beams one by one does.
#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <numbers>
#include <random>
#include <string>
#include <vector>

#include "fuzz_input.hpp"
#include "stridemap/core/grid_map.hpp"
#include "stridemap/core/visibility_clearing.hpp"

namespace visibility_fan_fuzz {
namespace {

using namespace stridemap;
using fuzz::check;

// A height a map cell may hold: mostly within a walking robot's reach, now
// and then any finite float.
float cell_height(fuzz::ByteReader& in) {
  const std::uint8_t h = in.byte();
  if (h < 240) return static_cast<float>((h - 40) * 0.002);
  const double any = in.any_double();
  if (!std::isfinite(any)) return h % 2 ? 3e38f : -3e38f;
  return static_cast<float>(std::clamp(any, -3e38, 3e38));
}

ElevationMap window_from(fuzz::ByteReader& in) {
  static constexpr std::array<double, 4> kCellSizes{0.005, 0.01, 0.02, 0.1};
  const int n = static_cast<int>(in.in_range(1, 48));
  ElevationMap map(GridOptions{n, kCellSizes[in.byte() % kCellSizes.size()]});
  map.move_corner_to({static_cast<std::int64_t>(in.in_range(0, 400)) - 200,
                      static_cast<std::int64_t>(in.in_range(0, 400)) - 200});
  const CellIndex lo = map.min_cell();
  for (int i = 0; i < n; ++i) {
    for (int j = 0; j < n; ++j) {
      const std::uint8_t kind = in.byte();
      if (kind < 40) continue;  // unknown
      const std::size_t s = map.slot({lo.x + i, lo.y + j});
      map.elevation_data()[s] = cell_height(in);
      const bool filled = kind < 60;
      map.state_data()[s] = static_cast<std::uint8_t>(filled ? CellState::filled : CellState::measured);
      map.certainty_data()[s] = filled ? 0.0f : static_cast<float>(1 + kind % 100);
    }
  }
  return map;
}

VisibilityOptions options_from(fuzz::ByteReader& in) {
  static constexpr std::array<double, 5> kSpacings{0.0, 0.25, 0.5, 1.0, 3.0};
  static constexpr std::array<double, 3> kFactors{1.0, 0.0, 2.5};
  static constexpr std::array<double, 3> kReliefs{1.0, 0.0, 0.5};
  static constexpr std::array<double, 3> kDecrements{3.0, 1.0, 50.0};
  VisibilityOptions o;
  o.enabled = true;
  o.beam_spacing_cells = kSpacings[in.byte() % kSpacings.size()];
  o.uncertainty_factor = kFactors[in.byte() % kFactors.size()];
  o.relief_factor = kReliefs[in.byte() % kReliefs.size()];
  o.certainty_decrement = kDecrements[in.byte() % kDecrements.size()];
  return o;
}

// A fan's beams as arrays, given to trace_fan() at once or to trace() one by one.
struct Fan {
  Eigen::Vector3d origin = Eigen::Vector3d::Zero();
  std::vector<double> x, y, z, range_error, height_error;

  VisibilityFan view() const {
    return {origin, x.size(), x.data(), y.data(), z.data(), height_error.data(), range_error.data()};
  }
  VisibilityBeam beam(std::size_t k) const {
    return {origin, Eigen::Vector3d(x[k], y[k], z[k]), range_error[k], height_error[k]};
  }
};

// Realistic values come from a generator the bytes seed (a whole fan from a
// few bytes); a byte per beam may replace some of them by any double.
Fan fan_from(fuzz::ByteReader& in, const ElevationMap& map) {
  std::mt19937_64 rng(in.integer<std::uint32_t>());
  std::uniform_real_distribution<double> u(0.0, 1.0);
  const double side = map.cell_size_m() * map.cells_per_side();
  const double lo_x = static_cast<double>(map.min_cell().x) * map.cell_size_m();
  const double lo_y = static_cast<double>(map.min_cell().y) * map.cell_size_m();
  Fan fan;
  const std::uint8_t origin_kind = in.byte();
  fan.origin = Eigen::Vector3d(lo_x + side * (1.6 * u(rng) - 0.3), lo_y + side * (1.6 * u(rng) - 0.3), 0.6 * u(rng));
  if (origin_kind >= 240) fan.origin = Eigen::Vector3d(in.any_double(), in.any_double(), in.any_double());
  const std::size_t count = in.in_range(0, 300);
  const double start = 2.0 * std::numbers::pi * u(rng), sweep = 2.0 * std::numbers::pi * u(rng);
  for (std::size_t k = 0; k < count; ++k) {
    const double angle = start + sweep * static_cast<double>(k) / static_cast<double>(std::max<std::size_t>(count, 1));
    const double reach = side * 1.4 * u(rng);
    fan.x.push_back(fan.origin.x() + reach * std::cos(angle));
    fan.y.push_back(fan.origin.y() + reach * std::sin(angle));
    fan.z.push_back(u(rng) < 0.1 ? fan.origin.z() + 0.1 * (u(rng) - 0.5) : 0.3 * u(rng) - 0.05);
    fan.range_error.push_back(u(rng) < 0.1 ? -0.05 * u(rng) : 0.02 * u(rng));
    fan.height_error.push_back(0.01 * u(rng));
    const std::uint8_t kind = in.byte();
    if (kind >= 250) fan.x.back() = in.any_double();
    else if (kind >= 245) fan.z.back() = in.any_double();
    else if (kind >= 240) fan.range_error.back() = in.any_double(), fan.height_error.back() = in.any_double();
    else if (kind >= 235) fan.x.back() = fan.origin.x(), fan.y.back() = fan.origin.y();
  }
  return fan;
}

bool same_layers(const ElevationMap& a, const ElevationMap& b) {
  const std::size_t cells = static_cast<std::size_t>(a.cells_per_side()) * static_cast<std::size_t>(a.cells_per_side());
  return a.min_cell() == b.min_cell() &&
         std::memcmp(a.elevation_data(), b.elevation_data(), cells * sizeof(float)) == 0 &&
         std::memcmp(a.certainty_data(), b.certainty_data(), cells * sizeof(float)) == 0 &&
         std::memcmp(a.state_data(), b.state_data(), cells) == 0 &&
         std::memcmp(a.contradiction_data(), b.contradiction_data(), cells) == 0 &&
         std::memcmp(a.pending_elevation_data(), b.pending_elevation_data(), cells * sizeof(float)) == 0 &&
         std::memcmp(a.mean_elevation_data(), b.mean_elevation_data(), cells * sizeof(float)) == 0 &&
         std::memcmp(a.mean_count_data(), b.mean_count_data(), cells * sizeof(std::uint16_t)) == 0;
}

void check_same_account(const VisibilityClearing& by_fan, const VisibilityClearing& by_beam) {
  const VisibilityStats &f = by_fan.stats(), &b = by_beam.stats();
  check(f.beams_traced == b.beams_traced && f.cells_crossed == b.cells_crossed &&
            f.cells_contradicted == b.cells_contradicted && f.cells_cleared == b.cells_cleared,
        "trace_fan() counts other beams or cells than trace() one by one");
  check(by_fan.cleared().size() == by_beam.cleared().size(), "trace_fan() lists other cleared cells");
  for (std::size_t c = 0; c < by_beam.cleared().size(); ++c) {
    check(by_fan.cleared()[c].cell == by_beam.cleared()[c].cell &&
              std::memcmp(&by_fan.cleared()[c].elevation_m, &by_beam.cleared()[c].elevation_m, sizeof(float)) == 0,
          "trace_fan() lists other cleared cells");
  }
  check(by_fan.changed().min == by_beam.changed().min && by_fan.changed().max == by_beam.changed().max,
        "trace_fan() marks another changed box");
}

}  // namespace

STRIDEMAP_FUZZ_TARGET(visibility_fan) {
  fuzz::ByteReader in(data);
  ElevationMap fan_map = window_from(in);
  ElevationMap beam_map = fan_map;
  const VisibilityOptions options = options_from(in);
  VisibilityClearing by_fan(fan_map, options), by_beam(beam_map, options);
  const std::uint64_t scans = in.in_range(1, 3);
  for (std::uint64_t scan = 0; scan < scans; ++scan) {
    const Fan fan = fan_from(in, fan_map);
    by_fan.begin_scan(fan_map);
    by_beam.begin_scan(beam_map);
    by_fan.trace_fan(fan_map, fan.view());
    for (std::size_t k = 0; k < fan.x.size(); ++k) by_beam.trace(beam_map, fan.beam(k));
    check(same_layers(fan_map, beam_map), "trace_fan() leaves another map than trace() one by one");
    check_same_account(by_fan, by_beam);
    if (!fan.x.empty()) {
      check(by_fan.thinned(fan.x[0], fan.y[0]) == by_beam.thinned(fan.x[0], fan.y[0]),
            "trace_fan() ends with another last traced hit");
    }
  }
}

}  // namespace visibility_fan_fuzz
