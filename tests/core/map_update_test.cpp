#include "stridemap/core/map_update.hpp"
#include "stridemap/core/max_elevation_change.hpp"

#include <cmath>
#include <numbers>

#include <gtest/gtest.h>

namespace stridemap {
namespace {

constexpr auto kUnknown = static_cast<std::uint8_t>(CellState::unknown);
constexpr auto kMeasured = static_cast<std::uint8_t>(CellState::measured);
constexpr auto kFilled = static_cast<std::uint8_t>(CellState::filled);

struct Cell {
  float h = std::nanf("");
  float c = 0.0f;
  std::uint8_t state = kUnknown;
  float pending = std::nanf("");
  std::uint8_t contradictions = 0;
  float mean = std::nanf("");
  std::uint16_t mean_count = 0;
  CellUpdate update(float h_m, float dz, const UpdateOptions& o = {}) {
    return stridemap::update_cell({h, c, state, pending, contradictions, mean, mean_count}, h_m, dz, o);
  }
};

UpdateOptions gated() {
  UpdateOptions o;
  o.elevation_rule = ElevationRule::gated_highest;
  return o;
}

TEST(UpdateRule, UnknownCellTakesTheFirstMeasurement) {
  Cell cell;
  EXPECT_EQ(cell.update(0.12f, 0.01f), CellUpdate::first);
  EXPECT_FLOAT_EQ(cell.h, 0.12f);
  EXPECT_FLOAT_EQ(cell.c, 3.0f);
  EXPECT_EQ(cell.state, kMeasured);
}

TEST(UpdateRule, FirstMeasurementMayBeLowerThanAFilledValue) {
  // A filled cell has c = 0, so eq. (9)'s "or c = 0" applies and the
  // measurement replaces the interpolated value even when it is lower.
  Cell cell{0.2f, 0.0f, kFilled};
  EXPECT_EQ(cell.update(0.05f, 0.01f), CellUpdate::first);
  EXPECT_FLOAT_EQ(cell.h, 0.05f);
  EXPECT_EQ(cell.state, kMeasured);
}

TEST(UpdateRule, PlausibleMeasurementsRaiseCertaintyAndKeepTheHighest) {
  Cell cell{0.10f, 3.0f, kMeasured};
  EXPECT_EQ(cell.update(0.105f, 0.01f), CellUpdate::plausible);
  EXPECT_FLOAT_EQ(cell.c, 6.0f);
  EXPECT_FLOAT_EQ(cell.h, 0.105f);
  EXPECT_EQ(cell.update(0.095f, 0.01f), CellUpdate::plausible);  // lower but within the bound
  EXPECT_FLOAT_EQ(cell.c, 9.0f);
  EXPECT_FLOAT_EQ(cell.h, 0.105f);  // eq. (10): never lowered
}

TEST(UpdateRule, BoundIsInclusiveAndUsesItsMagnitude) {
  Cell cell{0.0f, 3.0f, kMeasured};
  EXPECT_EQ(cell.update(0.5f, -0.5f), CellUpdate::plausible);
}

TEST(UpdateRule, ImplausibleHighReadingRaisesElevationButNotCertainty) {
  Cell cell{0.10f, 9.0f, kMeasured};
  EXPECT_EQ(cell.update(0.30f, 0.01f), CellUpdate::implausible);
  EXPECT_FLOAT_EQ(cell.h, 0.30f);
  EXPECT_FLOAT_EQ(cell.c, 9.0f);
}

TEST(UpdateRule, ImplausibleLowReadingChangesNothing) {
  Cell cell{0.10f, 9.0f, kMeasured};
  EXPECT_EQ(cell.update(-0.20f, 0.01f), CellUpdate::implausible);
  EXPECT_FLOAT_EQ(cell.h, 0.10f);
  EXPECT_FLOAT_EQ(cell.c, 9.0f);
}

TEST(UpdateRule, TheMeanHoldsTheAcceptedReadingsOnly) {
  Cell cell;
  cell.update(0.100f, 0.01f);
  cell.update(0.106f, 0.01f);  // plausible: counted, and the highest
  cell.update(0.097f, 0.01f);  // plausible: counted
  EXPECT_FLOAT_EQ(cell.h, 0.106f);
  EXPECT_NEAR(cell.mean, (0.100f + 0.106f + 0.097f) / 3.0f, 1e-6f);
  EXPECT_EQ(cell.mean_count, 3);
  cell.update(0.300f, 0.01f);  // implausible: raises h (eq. 10) but not the mean
  cell.update(0.010f, 0.01f);  // implausible low: nothing
  EXPECT_FLOAT_EQ(cell.h, 0.300f);
  EXPECT_NEAR(cell.mean, (0.100f + 0.106f + 0.097f) / 3.0f, 1e-6f);
  EXPECT_EQ(cell.mean_count, 3);
}

TEST(UpdateRule, TheMeanCountSaturatesWithoutLosingTheMean) {
  Cell cell;
  cell.update(0.05f, 0.01f);
  cell.mean_count = 0xFFFE;
  for (int i = 0; i < 10; ++i) cell.update(0.05f, 0.01f);
  EXPECT_EQ(cell.mean_count, 0xFFFF);
  EXPECT_FLOAT_EQ(cell.mean, 0.05f);
}

TEST(UpdateRule, CertaintyStopsAtTheCeiling) {
  UpdateOptions options;
  options.certainty_increment = 4.0;
  options.certainty_max = 10.0;
  Cell cell;
  for (int k = 0; k < 10; ++k) cell.update(0.0f, 0.01f, options);
  EXPECT_FLOAT_EQ(cell.c, 10.0f);
}

TEST(GatedRule, ASingleStrayHighReadingDoesNotRaiseAnAgreedCell) {
  Cell cell{0.0f, 9.0f, kMeasured};
  EXPECT_EQ(cell.update(0.10f, 0.01f, gated()), CellUpdate::implausible);
  EXPECT_FLOAT_EQ(cell.h, 0.0f);
  EXPECT_EQ(cell.update(0.002f, 0.01f, gated()), CellUpdate::plausible);  // agreement clears the count
  EXPECT_EQ(cell.contradictions, 0);
  EXPECT_EQ(cell.update(0.10f, 0.01f, gated()), CellUpdate::implausible);
  EXPECT_EQ(cell.update(0.10f, 0.01f, gated()), CellUpdate::implausible);
  EXPECT_FLOAT_EQ(cell.h, 0.002f);
}

TEST(GatedRule, RepeatedContradictionsReplaceTheCellWithTheirHighest) {
  Cell cell{0.0f, 30.0f, kMeasured};
  EXPECT_EQ(cell.update(0.09f, 0.01f, gated()), CellUpdate::implausible);
  EXPECT_EQ(cell.update(0.11f, 0.01f, gated()), CellUpdate::implausible);
  EXPECT_EQ(cell.update(0.10f, 0.01f, gated()), CellUpdate::replaced);
  EXPECT_FLOAT_EQ(cell.h, 0.11f);
  EXPECT_FLOAT_EQ(cell.c, 3.0f);
  EXPECT_EQ(cell.contradictions, 0);
}

TEST(GatedRule, ALoneHighFirstReadingIsCorrectedByLowerOnes) {
  // A stray point that arrived first is outvoted by the surface under it.
  Cell cell;
  cell.update(0.10f, 0.01f, gated());
  cell.update(0.0f, 0.01f, gated());
  cell.update(0.0f, 0.01f, gated());
  EXPECT_EQ(cell.update(0.001f, 0.01f, gated()), CellUpdate::replaced);
  EXPECT_FLOAT_EQ(cell.h, 0.001f);
}

TEST(GatedRule, PlausibleReadingsBehaveAsInThePaper) {
  Cell paper{0.10f, 3.0f, kMeasured}, gate{0.10f, 3.0f, kMeasured};
  for (float h : {0.105f, 0.095f, 0.112f, 0.108f}) {
    EXPECT_EQ(paper.update(h, 0.01f), gate.update(h, 0.01f, gated()));
  }
  EXPECT_FLOAT_EQ(paper.h, gate.h);
  EXPECT_FLOAT_EQ(paper.c, gate.c);
}

TEST(MaxElevationChange, SumsTheTermsOfEquationSix) {
  UpdateOptions options;
  options.max_pitch_error_rad = 0.01;
  options.max_roll_error_rad = 0.02;
  options.max_mount_pitch_error_rad = 0.03;
  ElevationPartials p;
  p.d_range = -0.5;
  p.d_pitch_m_per_rad = 0.4;
  p.d_roll_m_per_rad = -0.2;
  p.d_alpha_m_per_rad = -0.3;
  const double gamma = 0.6;
  const double expected = 0.01 * std::tan(gamma) + 0.5 * 0.01 + 0.4 * 0.01 + 0.2 * 0.02 + 0.3 * 0.03;
  EXPECT_NEAR(laser_max_elevation_change(p, 0.01, 0.01, gamma, options), expected, 1e-15);
  EXPECT_NEAR(laser_max_elevation_change(p, 0.01, 0.0, gamma, options), expected - 0.01 * std::tan(gamma), 1e-15);
}

TEST(MaxElevationChange, TurningTravelFollowsFigureTen) {
  const double theta = 0.1;
  EXPECT_NEAR(turning_travel_m(0.4, 0.1, theta), 0.5 * std::tan(theta / 2) * std::tan(theta), 1e-15);
  EXPECT_NEAR(turning_travel_m(0.4, 0.1, -theta), turning_travel_m(0.4, 0.1, theta), 1e-15);
  EXPECT_EQ(turning_travel_m(0.4, 0.1, 0.0), 0.0);
  EXPECT_TRUE(std::isinf(turning_travel_m(0.4, 0.1, 2.0)));
}

TEST(MaxElevationChange, ATurnMovesAPointBesideTheRobotAlongTheHeading) {
  // Fig. 10 bounds the travel of a point straight ahead; a point 0.3 m to
  // the side moves 0.3 sin(theta) along the heading, and the inclined scan
  // plane meets the ground that much further on.
  UpdateOptions options;
  SensorMount mount;
  mount.forward_offset_m = 0.0;
  mount.lateral_offset_m = 0.0;
  const double theta = 5.0 * kDegToRad, gamma = 0.7;
  const ScanMotion turn{0.0, theta};
  const double radial_per_m = std::tan(gamma) * turning_travel_m(1.0, 0.0, theta);
  const double lateral = 0.3 * std::sin(theta) * std::tan(gamma);
  for (const double heading : {0.0, 1.2, -2.5}) {
    const MaxElevationChange bound(turn, gamma, mount, options, heading);
    const Eigen::Vector2d ahead(std::cos(heading), std::sin(heading)), left(-std::sin(heading), std::cos(heading));
    const Eigen::Vector3d beside(0.3 * left.x(), 0.3 * left.y(), -0.2);
    const Eigen::Vector3d right(-0.3 * left.x(), -0.3 * left.y(), -0.2);
    const Eigen::Vector3d front(0.4 * ahead.x(), 0.4 * ahead.y(), -0.2);
    EXPECT_NEAR(bound.at(0.001, beside), 0.001 + radial_per_m * 0.3 + lateral, 1e-12) << heading;
    EXPECT_NEAR(bound.at(0.001, right), bound.at(0.001, beside), 1e-12) << heading;
    EXPECT_NEAR(bound.at(0.001, front), 0.001 + radial_per_m * 0.4, 1e-12) << heading;
  }
  // 26 mm along the heading in a 5 deg turn: the bound now covers most of
  // it (times tan gamma), where Fig. 10's term alone gave about 1 mm.
  EXPECT_GT(lateral, 0.018);
  EXPECT_LT(radial_per_m * 0.3, 0.0015);
  // Without the turning term, and on a straight walk, nothing is added.
  options.use_turning_term = false;
  EXPECT_NEAR(MaxElevationChange(turn, gamma, mount, options, 0.0).at(0.001, Eigen::Vector3d(0, 0.3, 0)), 0.001, 1e-15);
  options.use_turning_term = true;
  EXPECT_NEAR(MaxElevationChange({0.0, 0.0}, gamma, mount, options, 0.0).at(0.001, Eigen::Vector3d(0, 0.3, 0)), 0.001,
              1e-15);
  // The sensor's own lateral offset counts: the turning centre is the trunk.
  mount.lateral_offset_m = 0.1;
  const MaxElevationChange offset_bound(turn, gamma, mount, options, 0.0);
  EXPECT_NEAR(offset_bound.at(0.0, Eigen::Vector3d(0.0, 0.3, 0.0)) - offset_bound.at(0.0, Eigen::Vector3d(0.0, 0.0, 0.0)),
              radial_per_m * 0.3 + 0.3 * std::sin(theta) * std::tan(gamma), 1e-12);
}

}  // namespace
}  // namespace stridemap
