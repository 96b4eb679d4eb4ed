#include "stridemap/experiments/wall_range_calibration.hpp"

#include <cmath>
#include <string>

#include <gtest/gtest.h>

#include "stridemap/core/error.hpp"

namespace stridemap {
namespace {

TEST(WallRangeCalibration, UndoesTheSimulatorsSystematicErrorOverTheTerrainRanges) {
  const UrgParameters urg;
  const UrgSimOptions sim;
  const UrgSimulator model(Scene{}, urg, sim, 1);
  const RangeCalibrationFit fit = calibrate_range_on_wall(urg, sim, 7);
  EXPECT_EQ(fit.residuals_m.size(), 29u * 20u * 5u);
  // What is left is the 3 mm noise and the millimetre rounding.
  EXPECT_LT(fit.rms_residual_m, 0.004);
  for (double r = 0.2; r <= 1.3; r += 0.1) {
    const double measured = r + model.systematic_error_m(r);
    EXPECT_NEAR(fit.calibration.corrected_m(measured), r, 0.0006) << "at " << r << " m";
  }
  // The uncorrected error is several millimetres there: the test can fail.
  EXPECT_GT(std::abs(model.systematic_error_m(0.8)), 0.004);
}

TEST(WallRangeCalibration, FindsNothingToCorrectWhenTheSensorHasNoSystematicError) {
  UrgSimOptions sim;
  sim.enable_systematic_error = false;
  const RangeCalibrationFit fit = calibrate_range_on_wall(UrgParameters{}, sim, 3);
  for (double r = 0.2; r <= 1.3; r += 0.1) EXPECT_NEAR(fit.calibration.correction_m(r), 0.0, 0.0006) << r;
}

TEST(WallRangeCalibration, SameSeedSameFit) {
  const RangeCalibrationFit a = calibrate_range_on_wall(UrgParameters{}, UrgSimOptions{}, 11);
  const RangeCalibrationFit b = calibrate_range_on_wall(UrgParameters{}, UrgSimOptions{}, 11);
  EXPECT_EQ(a.calibration.coefficients, b.calibration.coefficients);
}

TEST(WallRangeCalibration, BadOptionsNameTheField) {
  const auto message = [](const WallRangeCalibrationOptions& o) {
    try {
      calibrate_range_on_wall(UrgParameters{}, UrgSimOptions{}, 1, o);
    } catch (const InputError& e) {
      return std::string(e.what());
    }
    return std::string("no error");
  };
  WallRangeCalibrationOptions o;
  o.farthest_m = o.nearest_m;
  EXPECT_NE(message(o).find("farthest_m"), std::string::npos) << message(o);
  o = {};
  o.step_m = 1.0;
  EXPECT_NE(message(o).find("step_m"), std::string::npos) << message(o);
  o = {};
  o.scans_per_distance = 0;
  EXPECT_NE(message(o).find("scans_per_distance"), std::string::npos) << message(o);
  o = {};
  o.wall_reflectance = std::nan("");
  EXPECT_NE(message(o).find("wall_reflectance"), std::string::npos) << message(o);
  o = {};
  o.beams_each_side = 400;
  EXPECT_NE(message(o).find("beams_each_side"), std::string::npos) << message(o);
}

TEST(WallRangeCalibration, AWallTooDarkToSeeIsAClearError) {
  WallRangeCalibrationOptions o;
  o.wall_reflectance = 1e-6;
  try {
    calibrate_range_on_wall(UrgParameters{}, UrgSimOptions{}, 1, o);
    FAIL() << "no error";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("valid readings of the wall"), std::string::npos) << e.what();
  }
}

}  // namespace
}  // namespace stridemap
