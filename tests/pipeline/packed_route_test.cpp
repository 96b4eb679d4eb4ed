// The pipeline's URG route (packed beams without scan filters, the planar
// scan with them) against the planar route as it was: to_planar_scan, the
// tagged filter chain, then TerrainMapper::integrate(PlanarScan) with the
// visibility clean-up and the foothold layers (MappingPipeline::add_planar).
// Every layer of the two maps must agree bit for bit, and so must what the
// observers, the stats and last_scan() hand out.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <limits>
#include <random>
#include <span>
#include <string>
#include <vector>

#include "pipeline_test_support.hpp"
#include "stridemap/core/error.hpp"
#include "stridemap/core/map_layer.hpp"
#include "stridemap/pipeline/mapping_pipeline.hpp"
#include "stridemap/pipeline/tagged_scan_filter.hpp"

namespace stridemap {
namespace {

using test::pose_at;

// A floor with boxes at random places seen from the default mount, with what
// a real URG adds: mixed pixels (a value between the two sides of an edge),
// range noise, error codes, values beyond DMAX and returns just above DMIN.
UrgRawScan random_scan(double time_s, const UrgParameters& urg, const SensorMount& mount, std::mt19937_64& rng) {
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  std::normal_distribution<double> noise_mm(0.0, 4.0);
  UrgRawScan raw;
  raw.time_s = time_s;
  raw.first_step = urg.first_step;
  const int box_start = static_cast<int>(unit(rng) * 600.0), box_end = box_start + 20 + static_cast<int>(unit(rng) * 80);
  const double box_scale = 0.6 + 0.3 * unit(rng);
  double previous_mm = 0.0;
  for (int step = urg.first_step; step <= urg.last_step; ++step) {
    const double down = std::cos(urg.step_angle_rad(step)) * std::sin(mount.pitch_rad);
    const int k = step - urg.first_step;
    double range_mm = down > 0.1 ? 1000.0 * mount.height_m / down : 7000.0 * unit(rng);
    if (k >= box_start && k < box_end) range_mm *= box_scale;
    range_mm += noise_mm(rng);
    const double u = unit(rng);
    if ((k == box_start || k == box_end) && u < 0.8) {
      range_mm = previous_mm + unit(rng) * (range_mm - previous_mm);  // a mixed pixel at the edge
    } else if (u < 0.03) {
      range_mm = std::floor(unit(rng) * 20.0);  // error code
    } else if (u < 0.05) {
      range_mm = 5601.0 + 2000.0 * unit(rng);  // beyond DMAX
    } else if (u < 0.06) {
      range_mm = 20.0 + 20.0 * unit(rng);  // just above DMIN: calibrated to <= 0 or barely above
    }
    previous_mm = range_mm;
    raw.values_mm.push_back(static_cast<std::uint32_t>(std::lround(std::max(0.0, range_mm))));
  }
  return raw;
}

bool same_bits(const std::vector<double>& a, const std::vector<double>& b) {
  return a.size() == b.size() && (a.empty() || std::memcmp(a.data(), b.data(), a.size() * sizeof(double)) == 0);
}

using test::same_maps;

// Read through const: the mapper counts a mutable map() as a change.
const ElevationMap& map_of(const MappingPipeline& pipeline) { return pipeline.mapper().map(); }

void expect_same_stats(const ScanStats& a, const ScanStats& b, int scan) {
  EXPECT_EQ(a.beams, b.beams) << scan;
  EXPECT_EQ(a.integrated, b.integrated) << scan;
  EXPECT_EQ(a.first, b.first) << scan;
  EXPECT_EQ(a.plausible, b.plausible) << scan;
  EXPECT_EQ(a.implausible, b.implausible) << scan;
  EXPECT_EQ(a.invalid_range, b.invalid_range) << scan;
  EXPECT_EQ(a.invalid_beam, b.invalid_beam) << scan;
  EXPECT_EQ(a.outside_map, b.outside_map) << scan;
  EXPECT_EQ(a.pose_rejected, b.pose_rejected) << scan;
  EXPECT_EQ(a.time_rejected, b.time_rejected) << scan;
  EXPECT_EQ(a.cells_reset_by_move, b.cells_reset_by_move) << scan;
}

// Within a few units of the last place of a double (a and b's), so that
// a multiply and add the compiler fuses (FMA, as GCC does on ARM) in one
// path and not the other still compares; on x86-64 they are equal.
bool same_to_last_bits(double a, double b) {
  return std::abs(a - b) <= 4.0 * std::numeric_limits<double>::epsilon() * std::max(1.0, std::abs(b));
}

// The same points in the same order: the ranges bit for bit, the positions
// and error bounds as the one formula gives them (above).
void expect_same_points(const std::vector<IntegratedPoint>& a, const std::vector<IntegratedPoint>& b, int scan) {
  ASSERT_EQ(a.size(), b.size()) << scan;
  for (std::size_t i = 0; i < a.size(); ++i) {
    for (int axis = 0; axis < 3; ++axis) {
      ASSERT_TRUE(same_to_last_bits(a[i].map_m[axis], b[i].map_m[axis]))
          << scan << " point " << i << " axis " << axis << ": " << a[i].map_m[axis] << " vs " << b[i].map_m[axis];
    }
    ASSERT_EQ(std::memcmp(&a[i].range_m, &b[i].range_m, sizeof(double)), 0) << scan << " point " << i;
    ASSERT_TRUE(same_to_last_bits(a[i].height_uncertainty_m, b[i].height_uncertainty_m)) << scan << " point " << i;
  }
}

struct Seen {
  std::size_t sequence = 0;
  TrunkPose pose{};
  std::size_t tags = 0;
  std::size_t removed = 0, removed_size = 0;
};

class Recorder : public PipelineObserver {
 public:
  void on_scan(const ScanReport& report) override {
    Seen s;
    s.sequence = report.payload.sequence;
    s.pose = report.payload.pose;
    s.tags = report.payload.beam_tags.size();
    s.removed_size = report.removed.size();
    for (const std::uint8_t r : report.removed) s.removed += r;
    seen.push_back(s);
  }
  std::vector<Seen> seen;
};

struct Case {
  std::string filters;  // as the CLI takes them
  bool calibrated = false;
  bool visibility = false;
  int cluster = 1;
  bool collect = false;  // the integrated points handed back (the fused heights' and top points' observers)
};

// The planar route, step by step, as ScanIntegrator::push took it.
class PlanarReference {
 public:
  explicit PlanarReference(const PipelineOptions& options)
      : options_(options), model_(options.urg, options.calibration), filters_(options.filters, options.filter_options),
        pipeline_(without_filters(options)) {}

  // Returns whether a scan reached the mapper, with its stats.
  bool push(const UrgRawScan& raw, const TrunkPose& pose, std::span<const std::uint8_t> tags, ScanStats& stats) {
    try {
      beams_ += model_.to_planar_scan(raw, scan_);
    } catch (const InputError&) {
      ++rejected_;
      return false;
    }
    if (options_.drop_beams_tagged) {
      for (std::size_t i = 0; i < tags.size() && i < scan_.range_m.size(); ++i) {
        if (tags[i] == *options_.drop_beams_tagged) scan_.range_m[i] = std::numeric_limits<double>::quiet_NaN();
      }
    }
    try {
      if (!filters_.push(scan_, pose, tags, filtered_)) return false;
    } catch (const InputError&) {
      ++rejected_;
      return false;
    }
    integrate(stats);
    return true;
  }
  bool flush(ScanStats& stats) {
    if (!filters_.flush(filtered_)) return false;
    integrate(stats);
    return true;
  }
  // The points the mapper's per-point way hands its sink for the scan
  // integrated last: what a pipeline collecting points must give back.
  const std::vector<IntegratedPoint>& sink_points() const { return sink_points_; }

  const MappingPipeline& pipeline() const { return pipeline_; }
  MappingPipeline& pipeline() { return pipeline_; }
  const PlanarScan& filtered() const { return filtered_; }
  const ScanFilterChain& chain() const { return filters_.chain(); }
  const ScanPayload& payload() const { return filters_.output(); }
  std::size_t rejected() const { return rejected_; }
  const UrgConversionStats& beams() const { return beams_; }

 private:
  void integrate(ScanStats& stats) {
    stats = pipeline_.add_planar(filtered_, filters_.output().pose);
    sink_points_.clear();
    per_point_.integrate(filtered_, filters_.output().pose,
                         [&](std::size_t, const Eigen::Vector3d& map_m, const SensorPoint& p) {
                           sink_points_.push_back({map_m, p.range_m, p.height_error_m});
                         });
  }
  static PipelineOptions without_filters(PipelineOptions options) {
    options.filters.clear();
    return options;
  }
  PipelineOptions options_;
  UrgModel model_;
  TaggedScanFilter filters_;
  MappingPipeline pipeline_;
  TerrainMapper per_point_{options_.mapper, options_.mount};
  std::vector<IntegratedPoint> sink_points_;
  PlanarScan scan_, filtered_;
  UrgConversionStats beams_;
  std::size_t rejected_ = 0;
};

void run_case(const Case& c, std::uint64_t seed) {
  SCOPED_TRACE("filters " + c.filters + (c.calibrated ? ", calibrated" : "") +
               (c.visibility ? ", visibility" : "") + ", cluster " + std::to_string(c.cluster) +
               (c.collect ? ", points collected" : ""));
  PipelineOptions options;
  options.filters = parse_scan_filter_list(std::string_view(c.filters));
  options.mapper.window_ahead_m = 0.3;
  options.visibility.enabled = c.visibility;
  if (c.calibrated) options.calibration.coefficients = {-0.03, 0.02, -0.004, 0.0005};  // some short ranges go <= 0
  MappingPipeline pipeline(options);
  Recorder recorder;
  pipeline.integrator().add_observer(recorder);
  PlanarReference reference(options);
  pipeline.integrator().set_collect_points(c.collect);
  reference.pipeline().integrator().set_collect_points(c.collect);

  std::mt19937_64 rng(seed);
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  std::normal_distribution<double> tilt(0.0, 0.03);
  TrunkPose pose = pose_at(0.0);
  double time_s = 0.0;
  std::size_t compared = 0;
  for (int k = 0; k < 120; ++k) {
    pose.x_m += 0.004 + 0.004 * unit(rng);
    pose.y_m += 0.002 * (unit(rng) - 0.5);
    pose.yaw_rad += 0.02 * (unit(rng) - 0.3);
    pose.pitch_rad = tilt(rng);
    pose.roll_rad = tilt(rng);
    time_s += 0.1;
    UrgRawScan raw = random_scan(time_s, options.urg, options.mount, rng);
    if (c.cluster > 1) {  // the sensor's cluster count: the minimum of each cluster
      std::vector<std::uint32_t> merged;
      for (std::size_t i = 0; i < raw.values_mm.size(); i += static_cast<std::size_t>(c.cluster)) {
        merged.push_back(raw.values_mm[i]);
      }
      raw.values_mm = merged;
      raw.cluster = c.cluster;
    }
    TrunkPose given = pose;
    const double fault = unit(rng);
    if (fault < 0.04) given.roll_rad = std::numeric_limits<double>::quiet_NaN();  // rejected by the mapper
    if (fault > 0.96) raw.time_s -= 0.15;                                        // stale
    if (k % 37 == 36) raw.first_step = options.urg.last_step + 5;                 // not this sensor's shape
    if (k % 53 == 52) raw.values_mm.resize(raw.values_mm.size() / 2);            // a shorter scan

    const ScanOutcome got = pipeline.add(raw, given);
    ScanStats expected;
    const bool reached = reference.push(raw, given, {}, expected);
    ASSERT_EQ(got.integrated, reached) << "scan " << k;
    if (reached) {
      expect_same_stats(got.stats, expected, k);
      ASSERT_TRUE(same_bits(pipeline.integrator().last_scan().range_m, reference.filtered().range_m)) << k;
      ASSERT_TRUE(same_bits(pipeline.integrator().last_scan().angle_rad, reference.filtered().angle_rad)) << k;
      ASSERT_TRUE(same_bits(pipeline.integrator().last_scan().range_error_m, reference.filtered().range_error_m)) << k;
      ASSERT_FALSE(recorder.seen.empty());
      const Seen& seen = recorder.seen.back();
      EXPECT_EQ(seen.sequence, reference.payload().sequence) << k;
      EXPECT_EQ(std::memcmp(&seen.pose, &reference.payload().pose, sizeof(TrunkPose)), 0) << k;
      EXPECT_EQ(seen.removed_size, reference.chain().removed_by_any().size()) << k;
      std::size_t removed = 0;
      for (const std::uint8_t r : reference.chain().removed_by_any()) removed += r;
      EXPECT_EQ(seen.removed, removed) << k;
      expect_same_points(pipeline.integrator().last_points(), reference.pipeline().integrator().last_points(), k);
      if (c.collect) expect_same_points(pipeline.integrator().last_points(), reference.sink_points(), k);
      ++compared;
    }
    ASSERT_TRUE(same_maps(map_of(pipeline), map_of(reference.pipeline()))) << "after scan " << k;
  }
  const ScanOutcome last = pipeline.finish();
  ScanStats expected;
  ASSERT_EQ(last.integrated, reference.flush(expected));
  if (last.integrated) expect_same_stats(last.stats, expected, -1);
  EXPECT_TRUE(same_maps(map_of(pipeline), map_of(reference.pipeline())));

  const PipelineStats stats = pipeline.stats();
  EXPECT_EQ(stats.rejected, reference.rejected());
  EXPECT_GE(stats.rejected, 3u);
  EXPECT_EQ(stats.beams.valid, reference.beams().valid);
  EXPECT_EQ(stats.beams.error_codes, reference.beams().error_codes);
  EXPECT_EQ(stats.beams.beyond_max_range, reference.beams().beyond_max_range);
  EXPECT_EQ(stats.cells_cleared, reference.pipeline().stats().cells_cleared);
  EXPECT_EQ(stats.cells_contradicted, reference.pipeline().stats().cells_contradicted);
  EXPECT_GT(compared, 90u);
  EXPECT_EQ(recorder.seen.size(), compared + (last.integrated ? 1u : 0u));
}

TEST(PackedRoute, MapsEqualThePlanarRouteBitForBit) {
  std::uint64_t seed = 1;
  for (const std::string filters : {"none", "paper", "urg", "range-clustering", "speckle,shadow"}) {
    for (const bool calibrated : {false, true}) {
      for (const bool visibility : {false, true}) {
        run_case({filters, calibrated, visibility, 1}, seed++);
      }
    }
  }
  run_case({"none", false, true, 2}, seed++);
  run_case({"none", true, false, 3}, seed++);
  // Collecting the points keeps the packed route (without filters) and
  // hands back what the planar route's points were.
  for (const std::string filters : {"none", "paper"}) {
    for (const bool visibility : {false, true}) run_case({filters, false, visibility, 1, true}, seed++);
  }
  run_case({"none", true, false, 2, true}, seed++);
}

TEST(PackedRoute, PointsAreCollectedWhereTheMapperTakesItsPerPointWay) {
  // A window beyond 2^30 cells from the origin: the packed pass keeps no
  // hits there, so the points are formed from the beams, the same ones.
  PipelineOptions options;
  MappingPipeline packed(options);
  PlanarReference reference(options);
  packed.integrator().set_collect_points(true);
  reference.pipeline().integrator().set_collect_points(true);
  for (int k = 0; k < 5; ++k) {
    const UrgRawScan raw = test::floor_scan(0.1 * (k + 1));
    const TrunkPose pose = pose_at(1.2e7 + 0.01 * k);
    ASSERT_TRUE(packed.add(raw, pose).integrated);
    ScanStats stats;
    ASSERT_TRUE(reference.push(raw, pose, {}, stats));
    ASSERT_GT(packed.integrator().last_points().size(), 100u);
    expect_same_points(packed.integrator().last_points(), reference.pipeline().integrator().last_points(), k);
    expect_same_points(packed.integrator().last_points(), reference.sink_points(), k);
  }
}

TEST(PackedRoute, AScanOfTheWrongShapeIsRejectedAndCounted) {
  PipelineOptions options;
  MappingPipeline pipeline(options);
  UrgRawScan raw = test::floor_scan(0.1);
  raw.values_mm.push_back(1000);  // one value past the last step
  const ScanOutcome out = pipeline.add(raw, pose_at(0.0));
  EXPECT_FALSE(out.integrated);
  EXPECT_EQ(pipeline.stats().rejected, 1u);
  EXPECT_EQ(pipeline.stats().integrated, 0u);
  EXPECT_EQ(pipeline.stats().beams.valid, 0u);
  // The next good scan goes in as usual.
  EXPECT_TRUE(pipeline.add(test::floor_scan(0.2), pose_at(0.0)).integrated);
  EXPECT_EQ(pipeline.stats().rejected, 1u);
  EXPECT_EQ(pipeline.stats().integrated, 1u);
}

TEST(PackedRoute, TaggedBeamsAreDroppedAsBefore) {
  // drop_beams_tagged keeps the planar route; the map must not depend on
  // which route an untagged scan took either.
  PipelineOptions options;
  options.drop_beams_tagged = 1;
  MappingPipeline tagged(options), untagged(options);
  PlanarReference reference(options);
  for (int k = 0; k < 30; ++k) {
    const UrgRawScan raw = test::floor_scan(0.1 * (k + 1));
    std::vector<std::uint8_t> tags(raw.values_mm.size(), 0);
    for (std::size_t i = 0; i < tags.size(); i += 3) tags[i] = 1;
    const TrunkPose pose = pose_at(0.005 * k, 0.01 * k);
    tagged.add(raw, pose, tags);
    untagged.add(raw, pose);
    ScanStats stats;
    ASSERT_TRUE(reference.push(raw, pose, tags, stats));
  }
  EXPECT_TRUE(same_maps(map_of(tagged), map_of(reference.pipeline())));
  EXPECT_FALSE(same_maps(map_of(tagged), map_of(untagged)));
}

}  // namespace
}  // namespace stridemap
