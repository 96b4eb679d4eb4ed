// UrgModel::to_beams (raw values straight into the mapper's packed beams)
// against to_planar_scan + TerrainMapper::integrate(PlanarScan): the same
// map bit for bit, the same counts, for calibrated and uncalibrated
// sensors, clustered scans and every kind of raw value.
#include <cmath>
#include <cstring>
#include <limits>
#include <random>
#include <vector>

#include <gtest/gtest.h>

#include "stridemap/core/error.hpp"
#include "stridemap/core/terrain_mapper.hpp"
#include "stridemap/sensors/urg04lx.hpp"

namespace stridemap {
namespace {

UrgRawScan random_scan(std::mt19937_64& rng, const UrgParameters& p, int first_step, int cluster) {
  std::uniform_real_distribution<double> u(0.0, 1.0);
  UrgRawScan raw;
  raw.first_step = first_step;
  raw.cluster = cluster;
  const int values = (p.last_step - first_step) / cluster + 1;
  for (int i = 0; i < values; ++i) {
    const double angle = p.step_angle_rad(first_step + i * cluster);
    const double down = std::cos(angle) * std::sin(0.61);
    auto mm = static_cast<std::uint32_t>(down > 0.05 ? 260.0 / down * (0.8 + 0.3 * u(rng)) : 0.0);
    const double bad = u(rng);
    if (bad < 0.03) mm = static_cast<std::uint32_t>(u(rng) * 20.0);  // error codes 0..19
    else if (bad < 0.05) mm = 5601 + static_cast<std::uint32_t>(u(rng) * 100000.0);
    else if (bad < 0.06) mm = 4294967295u;
    else if (bad < 0.07) mm = 20;
    else if (bad < 0.08) mm = 5600;
    raw.values_mm.push_back(mm);
  }
  return raw;
}

void expect_same_maps(const ElevationMap& a, const ElevationMap& b) {
  const std::size_t cells = static_cast<std::size_t>(a.cells_per_side()) * static_cast<std::size_t>(a.cells_per_side());
  for (std::size_t k = 0; k < a.layer_count(); ++k) {
    EXPECT_EQ(std::memcmp(a.layer_bytes(k), b.layer_bytes(k), cells * layer_type_bytes(a.layer_spec(k).type)), 0)
        << a.layer_spec(k).name;
  }
}

void run(const RangeCalibration& calibration, int first_step, int cluster, unsigned seed) {
  const UrgParameters p;
  const UrgModel model(p, calibration);
  MapperOptions options;
  options.window_ahead_m = 0.3;
  TerrainMapper packed(options, SensorMount{}), planar(options, SensorMount{});
  std::mt19937_64 rng(seed);
  std::normal_distribution<double> tilt(0.0, 0.02);
  PlanarBeams beams;
  PlanarScan scan;
  TrunkPose pose;
  for (int k = 0; k < 60; ++k) {
    UrgRawScan raw = random_scan(rng, p, first_step, cluster);
    raw.time_s = 0.1 * (k + 1);
    pose.x_m += 0.005;
    pose.yaw_rad += 0.004;
    pose.pitch_rad = tilt(rng);
    pose.roll_rad = tilt(rng);
    const UrgConversionStats ca = model.to_beams(raw, beams);
    const UrgConversionStats cb = model.to_planar_scan(raw, scan);
    EXPECT_EQ(ca.valid, cb.valid);
    EXPECT_EQ(ca.error_codes, cb.error_codes);
    EXPECT_EQ(ca.beyond_max_range, cb.beyond_max_range);
    const ScanStats a = packed.integrate(beams, pose), b = planar.integrate(scan, pose);
    EXPECT_EQ(a.beams, b.beams);
    EXPECT_EQ(a.integrated, b.integrated);
    EXPECT_EQ(a.plausible, b.plausible);
    EXPECT_EQ(a.implausible, b.implausible);
    EXPECT_EQ(a.invalid_range, b.invalid_range);
    EXPECT_EQ(a.invalid_beam, b.invalid_beam);
    EXPECT_EQ(a.outside_map, b.outside_map);
    if (::testing::Test::HasFailure()) return;
  }
  expect_same_maps(packed.map(), planar.map());
  EXPECT_GT(packed.totals().integrated, 5000u);
}

TEST(UrgPackedBeams, SameMapAsThePlanarScanPath) {
  run(RangeCalibration{}, 44, 1, 1);
  run(RangeCalibration{}, 100, 3, 2);
  run(RangeCalibration{{0.004, -0.01, 0.002, -0.0005}}, 44, 1, 3);
  // A calibration that drives short ranges negative: those beams are
  // invalid ranges on both ways.
  run(RangeCalibration{{-0.3, 0.0, 0.0, 0.0}}, 60, 2, 4);
  run(RangeCalibration{{-0.3, 0.0, 0.0, 0.0}}, 44, 1, 5);  // unclustered: four beams at a time where AVX2 is
}

// None, a small polynomial, and an offset that pushes short ranges to 0 or below.
std::vector<RangeCalibration> some_calibrations() {
  return {RangeCalibration{}, RangeCalibration{{0.004, -0.01, 0.002, -0.0005}}, RangeCalibration{{-0.3, 0.0, 0.0, 0.0}}};
}

// Every packed beam is the planar scan's valid beam, bit for bit and in
// order: the four-beams-at-a-time conversion (x86-64 with AVX2) and the
// beam-by-beam one alike, over every kind of raw value, with and without
// calibration, clustered or not, scans of every length modulo 4.
TEST(UrgPackedBeams, PackedBeamsAreThePlanarScansValidBeamsBitForBit) {
  const UrgParameters p;
  const std::vector<RangeCalibration> calibrations = some_calibrations();
  std::mt19937_64 rng(7);
  PlanarBeams beams;
  PlanarScan scan;
  for (const RangeCalibration& calibration : calibrations) {
    const UrgModel model(p, calibration);
    for (const int cluster : {1, 2}) {
      for (const int first_step : {44, 45, 46, 47, 300}) {
        const UrgRawScan raw = random_scan(rng, p, first_step, cluster);
        model.to_beams(raw, beams);
        model.to_planar_scan(raw, scan);
        std::size_t k = 0;
        for (std::size_t i = 0; i < scan.range_m.size(); ++i) {
          if (!(scan.range_m[i] > 0.0 && std::isfinite(scan.range_m[i]))) continue;
          ASSERT_LT(k, beams.count) << "beam " << i << ", cluster " << cluster << ", first step " << first_step;
          EXPECT_EQ(beams.range_m[k], scan.range_m[i]) << "beam " << i;
          EXPECT_EQ(beams.range_error_m[k], scan.range_error_m[i]) << "beam " << i;
          EXPECT_EQ(beams.cos_angle[k], std::cos(scan.angle_rad[i])) << "beam " << i;
          EXPECT_EQ(beams.sin_angle[k], std::sin(scan.angle_rad[i])) << "beam " << i;
          ++k;
        }
        EXPECT_EQ(k, beams.count) << "cluster " << cluster << ", first step " << first_step;
        EXPECT_EQ(beams.invalid_range, raw.values_mm.size() - k);
        if (::testing::Test::HasFailure()) return;
      }
    }
  }
}

// to_planar_scan itself, every beam against classify(), corrected_m() and
// spec_range_error_m() (the bound at the raw value for an invalid beam):
// the four-beams-at-a-time loop (unclustered, where AVX2 is) and the
// beam-by-beam one, for scans of every length modulo 4.
TEST(UrgPackedBeams, ThePlanarScanIsTheClassifiedCorrectedValueBitForBit) {
  const UrgParameters p;
  const std::vector<RangeCalibration> calibrations = some_calibrations();
  const auto same = [](double a, double b) { return std::memcmp(&a, &b, sizeof a) == 0; };
  std::mt19937_64 rng(11);
  PlanarScan scan;
  for (const RangeCalibration& calibration : calibrations) {
    const UrgModel model(p, calibration);
    for (const int cluster : {1, 2}) {
      for (const int first_step : {44, 45, 46, 47, 300}) {
        const UrgRawScan raw = random_scan(rng, p, first_step, cluster);
        const UrgConversionStats stats = model.to_planar_scan(raw, scan);
        ASSERT_EQ(scan.size(), raw.values_mm.size());
        UrgConversionStats expected;
        for (std::size_t i = 0; i < scan.size(); ++i) {
          const std::uint32_t value = raw.values_mm[i];
          const double raw_m = static_cast<double>(value) * 0.001;
          const UrgValueClass kind = model.classify(value);
          const bool valid = kind == UrgValueClass::valid;
          expected.valid += valid ? 1 : 0;
          expected.error_codes += kind == UrgValueClass::error_code ? 1 : 0;
          const double range = valid ? calibration.corrected_m(raw_m) : std::numeric_limits<double>::quiet_NaN();
          const double angle = p.step_angle_rad(first_step + static_cast<int>(i) * cluster);
          ASSERT_TRUE(same(scan.range_m[i], range)) << "beam " << i << ", value " << value;
          ASSERT_TRUE(same(scan.range_error_m[i], UrgModel::spec_range_error_m(valid ? range : raw_m)))
              << "beam " << i << ", value " << value;
          ASSERT_TRUE(same(scan.angle_rad[i], angle)) << "beam " << i;
        }
        EXPECT_EQ(stats.valid, expected.valid);
        EXPECT_EQ(stats.error_codes, expected.error_codes);
        EXPECT_EQ(stats.beyond_max_range, scan.size() - expected.valid - expected.error_codes);
      }
    }
  }
}

TEST(UrgPackedBeams, BadScansAreRefusedAsByTheConversion) {
  const UrgModel model;
  PlanarBeams beams;
  UrgRawScan raw;
  raw.first_step = 10;
  raw.values_mm = {100};
  EXPECT_THROW(model.to_beams(raw, beams), InputError);
  raw.first_step = 44;
  raw.cluster = 0;
  EXPECT_THROW(model.to_beams(raw, beams), InputError);
  raw.cluster = 1;
  raw.values_mm.assign(700, 100);
  EXPECT_THROW(model.to_beams(raw, beams), InputError);
}

// classify() in whole millimetres against the comparison it stands for,
// around thresholds that are not whole millimetres.
TEST(UrgPackedBeams, ClassifyMatchesTheMetreBounds) {
  for (const auto& [lo_m, hi_m] : {std::pair{0.020, 5.600}, std::pair{0.0205, 4.0999}, std::pair{1e-12, 1e9}}) {
    UrgParameters p;
    p.min_range_m = lo_m;
    p.max_range_m = hi_m;
    const UrgModel model(p);
    for (std::uint32_t v : {0u, 1u, 19u, 20u, 21u, 4099u, 4100u, 5599u, 5600u, 5601u, 4294967295u}) {
      const double mm = v;
      const UrgValueClass expected = mm < lo_m * 1000.0 - 1e-6   ? UrgValueClass::error_code
                                     : mm > hi_m * 1000.0 + 1e-6 ? UrgValueClass::beyond_max_range
                                                                 : UrgValueClass::valid;
      EXPECT_EQ(model.classify(v), expected) << v << " mm with bounds " << lo_m << ", " << hi_m;
    }
  }
}

}  // namespace
}  // namespace stridemap
