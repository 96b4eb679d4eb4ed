#include "stridemap/sensors/urg04lx.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <numbers>
#include <string>

#include "stridemap/core/error.hpp"

namespace stridemap {
namespace {

constexpr double deg = std::numbers::pi / 180.0;

// Runs f, expects an InputError and returns its message.
template <typename F>
std::string input_error_message(F&& f) {
  try {
    f();
  } catch (const InputError& e) {
    return e.what();
  }
  ADD_FAILURE() << "expected an InputError";
  return {};
}

UrgRawScan full_scan(std::uint32_t value_mm) {
  UrgRawScan raw;
  raw.time_s = 12.5;
  raw.values_mm.assign(682, value_mm);
  return raw;
}

TEST(UrgParameters, DefaultGeometryMatchesTheUrg04lx) {
  const UrgParameters parameters;
  EXPECT_NO_THROW(parameters.validate());
  EXPECT_EQ(parameters.beam_count(), 682);
  EXPECT_DOUBLE_EQ(parameters.step_angle_rad(384), 0.0);
  EXPECT_NEAR(parameters.step_angle_rad(44) / deg, -119.53125, 1e-9);
  EXPECT_NEAR(parameters.step_angle_rad(725) / deg, 119.8828125, 1e-9);
  EXPECT_NEAR(parameters.step_angle_rad(385) - parameters.step_angle_rad(384),
              2.0 * std::numbers::pi / 1024.0, 1e-15);
}

TEST(UrgParameters, InconsistentFieldsAreNamed) {
  struct Case {
    const char* field;
    void (*spoil)(UrgParameters&);
  };
  const Case cases[] = {
      {"steps_per_turn", [](UrgParameters& p) { p.steps_per_turn = 0; }},
      {"first_step", [](UrgParameters& p) { p.first_step = -1; }},
      {"front_step", [](UrgParameters& p) { p.front_step = 40; }},
      {"last_step", [](UrgParameters& p) { p.last_step = 300; }},
      {"last_step", [](UrgParameters& p) { p.last_step = 1024; }},
      {"last_step", [](UrgParameters& p) {
         p.steps_per_turn = 1'000'000'000;
         p.last_step = 777'777'800;  // beam tables of gigabytes
       }},
      {"min_range_m", [](UrgParameters& p) { p.min_range_m = 0.0; }},
      {"min_range_m", [](UrgParameters& p) { p.min_range_m = std::nan(""); }},
      {"max_range_m", [](UrgParameters& p) { p.max_range_m = 0.01; }},
      {"max_range_m", [](UrgParameters& p) { p.max_range_m = std::numeric_limits<double>::infinity(); }},
      {"scan_period_s", [](UrgParameters& p) { p.scan_period_s = -0.1; }},
      {"scan_period_s", [](UrgParameters& p) { p.scan_period_s = std::nan(""); }},
  };
  for (const Case& c : cases) {
    UrgParameters parameters;
    c.spoil(parameters);
    const std::string message = input_error_message([&] { parameters.validate(); });
    EXPECT_NE(message.find(c.field), std::string::npos) << message;
    EXPECT_NE(message.find("URG parameters"), std::string::npos) << message;
    // The model refuses the same set.
    EXPECT_THROW(UrgModel{parameters}, InputError);
  }
}

TEST(UrgModel, RejectsNonFiniteCalibration) {
  RangeCalibration calibration;
  calibration.coefficients[2] = std::nan("");
  const std::string message = input_error_message([&] { UrgModel model({}, calibration); });
  EXPECT_NE(message.find("coefficients[2]"), std::string::npos) << message;
}

TEST(UrgModel, ClassifiesErrorCodesAndOutOfRangeValues) {
  const UrgModel model;
  for (std::uint32_t code = 0; code < 20; ++code) {
    EXPECT_EQ(model.classify(code), UrgValueClass::error_code) << code;
  }
  EXPECT_EQ(model.classify(20), UrgValueClass::valid);
  EXPECT_EQ(model.classify(1234), UrgValueClass::valid);
  EXPECT_EQ(model.classify(5600), UrgValueClass::valid);
  EXPECT_EQ(model.classify(5601), UrgValueClass::beyond_max_range);
  EXPECT_EQ(model.classify(65535), UrgValueClass::beyond_max_range);
}

TEST(UrgModel, ThresholdsFollowTheParameters) {
  UrgParameters parameters;
  parameters.min_range_m = 0.060;
  parameters.max_range_m = 4.095;
  const UrgModel model(parameters);
  EXPECT_EQ(model.classify(59), UrgValueClass::error_code);
  EXPECT_EQ(model.classify(60), UrgValueClass::valid);
  EXPECT_EQ(model.classify(4095), UrgValueClass::valid);
  EXPECT_EQ(model.classify(4096), UrgValueClass::beyond_max_range);
}

TEST(UrgModel, SpecRangeError) {
  EXPECT_DOUBLE_EQ(UrgModel::spec_range_error_m(0.02), 0.010);
  EXPECT_DOUBLE_EQ(UrgModel::spec_range_error_m(0.5), 0.010);
  EXPECT_DOUBLE_EQ(UrgModel::spec_range_error_m(1.0), 0.010);
  EXPECT_DOUBLE_EQ(UrgModel::spec_range_error_m(2.0), 0.020);
  EXPECT_DOUBLE_EQ(UrgModel::spec_range_error_m(4.0), 0.040);
  EXPECT_TRUE(std::isnan(UrgModel::spec_range_error_m(std::nan(""))));
}

TEST(UrgModel, FullScanGeometry) {
  const UrgModel model;
  UrgRawScan raw = full_scan(1000);
  PlanarScan scan;
  const UrgConversionStats stats = model.to_planar_scan(raw, scan);
  ASSERT_EQ(scan.size(), 682u);
  ASSERT_EQ(scan.angle_rad.size(), 682u);
  ASSERT_EQ(scan.range_error_m.size(), 682u);
  EXPECT_EQ(stats.valid, 682u);
  EXPECT_EQ(stats.error_codes, 0u);
  EXPECT_EQ(stats.beyond_max_range, 0u);
  EXPECT_DOUBLE_EQ(scan.time_s, 12.5);
  EXPECT_NEAR(scan.angle_rad.front() / deg, -119.53125, 1e-9);
  EXPECT_NEAR(scan.angle_rad.back() / deg, 119.8828125, 1e-9);
  EXPECT_NEAR(scan.angle_rad[384 - 44], 0.0, 1e-15);
  for (std::size_t i = 0; i < scan.size(); ++i) {
    EXPECT_DOUBLE_EQ(scan.range_m[i], 1.0);
    EXPECT_DOUBLE_EQ(scan.range_error_m[i], 0.010);
  }
}

TEST(UrgModel, InvalidValuesBecomeNanWithFiniteErrorBound) {
  const UrgModel model;
  UrgRawScan raw = full_scan(500);
  raw.values_mm[0] = 0;      // "object possibly at 22 m"
  raw.values_mm[1] = 6;      // "others" / "possibly at 5.7 m"
  raw.values_mm[2] = 19;     // non-measurable step
  raw.values_mm[3] = 5601;   // beyond DMAX
  raw.values_mm[4] = 20;     // smallest valid value
  raw.values_mm[5] = 2000;
  PlanarScan scan;
  const UrgConversionStats stats = model.to_planar_scan(raw, scan);
  EXPECT_EQ(stats.error_codes, 3u);
  EXPECT_EQ(stats.beyond_max_range, 1u);
  EXPECT_EQ(stats.valid, 678u);
  for (std::size_t i = 0; i < 4; ++i) {
    EXPECT_TRUE(std::isnan(scan.range_m[i])) << i;
  }
  EXPECT_DOUBLE_EQ(scan.range_m[4], 0.020);
  EXPECT_DOUBLE_EQ(scan.range_m[5], 2.0);
  EXPECT_DOUBLE_EQ(scan.range_error_m[5], 0.020);
  // No NaN anywhere in the angles or the error bounds, whatever the beam.
  for (std::size_t i = 0; i < scan.size(); ++i) {
    EXPECT_TRUE(std::isfinite(scan.angle_rad[i])) << i;
    EXPECT_TRUE(std::isfinite(scan.range_error_m[i])) << i;
    EXPECT_GT(scan.range_error_m[i], 0.0) << i;
  }
  EXPECT_DOUBLE_EQ(scan.range_error_m[0], 0.010);
  EXPECT_NEAR(scan.range_error_m[3], 0.05601, 1e-12);
}

TEST(UrgModel, ClusteredScanUsesTheFirstStepOfEachCluster) {
  const UrgModel model;
  UrgRawScan raw;
  raw.first_step = 44;
  raw.cluster = 3;
  raw.values_mm.assign(228, 800);  // ceil(682 / 3): the last cluster starts at 725
  PlanarScan scan;
  model.to_planar_scan(raw, scan);
  ASSERT_EQ(scan.size(), 228u);
  const UrgParameters& p = model.parameters();
  for (std::size_t i = 0; i < scan.size(); ++i) {
    EXPECT_DOUBLE_EQ(scan.angle_rad[i], p.step_angle_rad(44.0 + 3.0 * static_cast<double>(i)));
  }
  EXPECT_NEAR(scan.angle_rad.back() / deg, 119.8828125, 1e-9);

  // A partial scan starting mid-range.
  raw.first_step = 384;
  raw.cluster = 2;
  raw.values_mm.assign(10, 800);
  model.to_planar_scan(raw, scan);
  ASSERT_EQ(scan.size(), 10u);
  EXPECT_DOUBLE_EQ(scan.angle_rad[0], 0.0);
  EXPECT_NEAR(scan.angle_rad[9], 18.0 * 2.0 * std::numbers::pi / 1024.0, 1e-15);
}

TEST(UrgModel, CalibrationIsAppliedToValidRanges) {
  RangeCalibration calibration;
  calibration.coefficients = {0.005, 0.01, -0.02, 0.004};
  const UrgModel model({}, calibration);
  UrgRawScan raw = full_scan(500);
  raw.values_mm[1] = 1500;
  raw.values_mm[2] = 7;
  PlanarScan scan;
  model.to_planar_scan(raw, scan);
  const double expected_05 = 0.5 + 0.005 + 0.01 * 0.5 - 0.02 * 0.25 + 0.004 * 0.125;
  const double expected_15 = 1.5 + 0.005 + 0.01 * 1.5 - 0.02 * 2.25 + 0.004 * 3.375;
  EXPECT_NEAR(scan.range_m[0], expected_05, 1e-15);
  EXPECT_NEAR(scan.range_m[1], expected_15, 1e-15);
  EXPECT_NEAR(scan.range_error_m[1], 0.01 * expected_15, 1e-15);
  EXPECT_TRUE(std::isnan(scan.range_m[2]));
}

TEST(UrgModel, ReusesOutputStorage) {
  const UrgModel model;
  PlanarScan scan;
  model.to_planar_scan(full_scan(700), scan);
  const double* angles = scan.angle_rad.data();
  const double* ranges = scan.range_m.data();
  UrgRawScan shorter = full_scan(900);
  shorter.values_mm.resize(100);
  model.to_planar_scan(shorter, scan);
  EXPECT_EQ(scan.size(), 100u);
  model.to_planar_scan(full_scan(900), scan);
  EXPECT_EQ(scan.size(), 682u);
  EXPECT_EQ(scan.angle_rad.data(), angles);
  EXPECT_EQ(scan.range_m.data(), ranges);
  EXPECT_DOUBLE_EQ(scan.range_m[681], 0.9);
}

TEST(UrgModel, RawScansThatDoNotFitAreRejected) {
  const UrgModel model;
  PlanarScan scan;

  UrgRawScan raw = full_scan(1000);
  raw.cluster = 0;
  std::string message = input_error_message([&] { model.to_planar_scan(raw, scan); });
  EXPECT_NE(message.find("URG scan"), std::string::npos) << message;
  EXPECT_NE(message.find("cluster"), std::string::npos) << message;
  EXPECT_NE(message.find("got 0"), std::string::npos) << message;

  raw = full_scan(1000);
  raw.first_step = 43;
  message = input_error_message([&] { model.to_planar_scan(raw, scan); });
  EXPECT_NE(message.find("first_step 43"), std::string::npos) << message;
  EXPECT_NE(message.find("44..725"), std::string::npos) << message;

  raw = full_scan(1000);
  raw.values_mm.push_back(1000);  // 683 values: the datasheet's count
  message = input_error_message([&] { model.to_planar_scan(raw, scan); });
  EXPECT_NE(message.find("683 values"), std::string::npos) << message;
  EXPECT_NE(message.find("last_step 725"), std::string::npos) << message;
  EXPECT_NE(message.find("at most 682"), std::string::npos) << message;

  raw = full_scan(1000);
  raw.cluster = 3;
  raw.values_mm.resize(229);
  message = input_error_message([&] { model.to_planar_scan(raw, scan); });
  EXPECT_NE(message.find("cluster 3"), std::string::npos) << message;
  EXPECT_NE(message.find("at most 228"), std::string::npos) << message;

  raw = full_scan(1000);
  raw.first_step = 726;
  raw.values_mm.resize(1);
  EXPECT_THROW(model.to_planar_scan(raw, scan), InputError);
}

TEST(UrgModel, EmptyScanIsAccepted) {
  const UrgModel model;
  UrgRawScan raw;
  PlanarScan scan;
  scan.resize(5);
  const UrgConversionStats stats = model.to_planar_scan(raw, scan);
  EXPECT_EQ(scan.size(), 0u);
  EXPECT_EQ(stats.valid + stats.error_codes + stats.beyond_max_range, 0u);
}

}  // namespace
}  // namespace stridemap
