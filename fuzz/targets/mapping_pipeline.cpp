// The mapping pipeline (pipeline/mapping_pipeline.hpp) on URG scans and
// poses drawn from the bytes: a floor the scans see, made rough, cut by
// dropouts and error codes, or raw values as they come; poses that walk,
// turn, jump, repeat a time or hold any double. Options vary the window,
// the cells, the scan filters, the foot and the visibility clean-up.
//
// Two pipelines take the same scans: one keeps its foothold layers current
// after every scan, the other refreshes them only when map() is read.
// Whatever the input, nothing may throw but InputError (and then both
// alike) and every cell must stay valid. Every read must find the two maps
// the same bit for bit in every layer, and the same as the layers
// recomputed from scratch: the refresh's marks (which cells a scan, a
// window move or the clean-up changed) must miss nothing.
#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <optional>
#include <random>
#include <string>
#include <string_view>

#include "fuzz_input.hpp"
#include "stridemap/core/error.hpp"
#include "stridemap/core/map_integrity.hpp"
#include "stridemap/pipeline/mapping_pipeline.hpp"
#include "stridemap/preprocess/scan_filter_chain.hpp"

namespace mapping_pipeline_fuzz {
namespace {

using namespace stridemap;
using fuzz::check;

template <typename T, std::size_t N>
T pick(fuzz::ByteReader& in, const std::array<T, N>& choices) {
  return choices[in.byte() % N];
}

PipelineOptions options_from(fuzz::ByteReader& in) {
  PipelineOptions o;
  o.mapper.grid.cells_per_side = pick(in, std::array{12, 24, 64, 70, 130});
  o.mapper.grid.cell_size_m = pick(in, std::array{0.005, 0.01, 0.02});
  o.filters = parse_scan_filter_list(pick(in, std::array<std::string_view, 3>{"none", "paper", "urg"}));
  o.visibility.enabled = in.byte() % 2 == 1;
  o.foothold.foot_radius_m = pick(in, std::array{0.02, 0.05, 0.1});
  o.foothold.edge_search_radius_m = pick(in, std::array{0.05, 0.1, 0.3});
  return o;
}

// A scan of a floor from the pose's mount, as the URG would report it, then
// spoiled as the bytes say.
void scan_from(fuzz::ByteReader& in, const PipelineOptions& o, std::mt19937_64& rng, double time_s, UrgRawScan& raw) {
  const UrgParameters& urg = o.urg;
  raw.time_s = time_s;
  raw.first_step = urg.first_step;
  raw.values_mm.assign(static_cast<std::size_t>(urg.beam_count()), 0u);
  std::normal_distribution<double> noise_mm(0.0, 1.0 + in.byte() % 20);
  const int step_every = 1 + in.byte() % 60;  // a step (a nearer surface) every so many beams
  for (int k = 0; k < urg.beam_count(); ++k) {
    const double down = std::cos(urg.step_angle_rad(urg.first_step + k)) * std::sin(o.mount.pitch_rad);
    if (down <= 0.1) continue;  // no floor that way: an error code
    const double range_mm = 1000.0 * o.mount.height_m / down * (k % step_every < step_every / 3 ? 0.8 : 1.0);
    const double value = std::round(range_mm + noise_mm(rng));
    raw.values_mm[static_cast<std::size_t>(k)] = value > 0.0 ? static_cast<std::uint32_t>(value) : 0u;
  }
  // Spoiled stretches: dropouts, error codes, the largest value, anything.
  for (std::uint64_t spoils = in.in_range(0, 4); spoils > 0; --spoils) {
    const std::size_t first = in.in_range(0, raw.values_mm.size() - 1);
    const std::size_t length = in.in_range(1, 64);
    const std::uint8_t kind = in.byte();
    for (std::size_t k = first; k < std::min(first + length, raw.values_mm.size()); ++k) {
      std::uint32_t& v = raw.values_mm[k];
      switch (kind % 5) {
        case 0: v = 0; break;
        case 1: v = 1 + kind % 19; break;  // the URG's error codes
        case 2: v = 0xFFFFFFu; break;      // three characters' largest
        case 3: v = static_cast<std::uint32_t>(std::min(static_cast<double>(v) * (0.2 + (kind % 16) * 0.1), 4294967295.0)); break;
        default: v = in.integer<std::uint32_t>(); break;
      }
    }
  }
}

void step_pose(fuzz::ByteReader& in, TrunkPose& pose) {
  const std::uint8_t kind = in.byte();
  pose.x_m += 0.001 * (kind % 16);
  pose.yaw_rad += 0.002 * ((kind >> 4) % 8) - 0.006;
  pose.pitch_rad = 0.001 * (static_cast<int>(in.byte()) - 128) * 0.2;
  pose.roll_rad = 0.001 * (static_cast<int>(in.byte()) - 128) * 0.2;
  pose.height_change_m = 0.0001 * (static_cast<int>(in.byte()) - 128);
  if (kind >= 250) {
    // A glitch: any double in one field.
    double* fields[] = {&pose.x_m, &pose.y_m, &pose.yaw_rad, &pose.pitch_rad, &pose.roll_rad, &pose.reference_elevation_m};
    *fields[in.byte() % 6] = in.any_double();
  } else if (kind >= 244) {
    pose.x_m += 0.5 * (kind - 243);  // a jump past the window
  }
}

bool same_maps(const ElevationMap& a, const ElevationMap& b) {
  if (!(a.min_cell() == b.min_cell()) || a.layer_count() != b.layer_count()) return false;
  const std::size_t cells = static_cast<std::size_t>(a.cells_per_side()) * static_cast<std::size_t>(a.cells_per_side());
  for (std::size_t layer = 0; layer < a.layer_count(); ++layer) {
    const std::size_t bytes = cells * layer_type_bytes(a.layer_spec(layer).type);
    if (std::memcmp(a.layer_bytes(layer), b.layer_bytes(layer), bytes) != 0) return false;
  }
  return true;
}

void check_same(const MappingPipeline& lazy, const MappingPipeline& eager, const char* when) {
  const ElevationMap& map = eager.map();
  const MapIntegrity integrity = check_map_integrity(map, eager.options().mapper.update.certainty_max);
  check(integrity.ok(), std::string("a cell is invalid ") + when + ": " + integrity.first_problem);
  check(same_maps(lazy.map(), map), std::string("the lazy foothold layers differ from the eager ones ") + when);
  if (!eager.options().foothold.enabled) return;
  ElevationMap recomputed = map;
  FootholdLayers(recomputed, eager.options().foothold).recompute_all(recomputed);
  check(same_maps(recomputed, map), std::string("the foothold layers differ from a recomputation ") + when);
}

}  // namespace

STRIDEMAP_FUZZ_TARGET(mapping_pipeline) {
  fuzz::ByteReader in(data);
  const PipelineOptions options = options_from(in);
  PipelineOptions eager_options = options;
  eager_options.foothold.update_every_scan = true;
  MappingPipeline lazy(options), eager(eager_options);
  std::mt19937_64 rng(in.integer<std::uint32_t>());
  const std::uint64_t scans = in.in_range(1, 40), read_every = in.in_range(1, 12);
  TrunkPose pose;
  double time_s = 0.0;
  UrgRawScan raw;
  for (std::uint64_t k = 0; k < scans; ++k) {
    const std::uint8_t clock = in.byte();
    time_s += clock >= 250 ? 0.0 : clock >= 245 ? -0.1 : 0.1;  // a repeated or earlier time now and then
    scan_from(in, options, rng, time_s, raw);
    step_pose(in, pose);
    bool lazy_refused = false, eager_refused = false;
    try {
      lazy.add(raw, pose);
    } catch (const InputError&) {
      lazy_refused = true;
    }
    try {
      eager.add(raw, pose);
    } catch (const InputError&) {
      eager_refused = true;
    }
    check(lazy_refused == eager_refused, "one pipeline refused a scan the other took");
    if ((k + 1) % read_every == 0) check_same(lazy, eager, "after a read");
  }
  lazy.finish();
  eager.finish();
  check_same(lazy, eager, "at the end");
}

}  // namespace mapping_pipeline_fuzz
