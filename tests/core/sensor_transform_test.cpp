#include "stridemap/core/sensor_transform.hpp"

#include <cmath>
#include <numbers>
#include <random>

#include <gtest/gtest.h>

namespace stridemap {
namespace {

constexpr double kDeg = std::numbers::pi / 180.0;

double elevation_of(double r, double t, double pitch, double roll, double alpha) {
  const Eigen::Vector3d p = tilt_rotation(pitch, roll, alpha) * Eigen::Vector3d(r * std::cos(t), r * std::sin(t), 0);
  return p.z();
}

TEST(SensorTransform, PitchedSensorLooksDown) {
  // 35 deg down, straight ahead, 0.26 m high: the beam meets flat ground at
  // 0.26 / tan(35 deg) ahead.
  TrunkPose pose;
  SensorMount mount;
  const double r = mount.height_m / std::sin(mount.pitch_rad);
  const Eigen::Vector3d hit = sensor_point_to_map({r, 0, 0}, pose, mount);
  EXPECT_NEAR(hit.z(), 0.0, 1e-12);
  EXPECT_NEAR(hit.x(), mount.height_m / std::tan(mount.pitch_rad), 1e-12);
  EXPECT_NEAR(hit.y(), 0.0, 1e-12);
}

TEST(SensorTransform, PositiveBeamAngleIsLeftAndYawTurnsCounterClockwise) {
  TrunkPose pose;
  pose.yaw_rad = std::numbers::pi / 2;  // facing +Y
  SensorMount mount;
  mount.pitch_rad = 0.0;
  mount.forward_offset_m = 0.1;
  const Eigen::Vector3d left = sensor_point_to_map({0, 1, 0}, pose, mount);
  EXPECT_NEAR(left.x(), -1.0, 1e-12);  // left of +Y is -X
  EXPECT_NEAR(left.y(), 0.1, 1e-12);   // offset turned onto +Y
}

TEST(SensorTransform, OriginCarriesReferenceElevationAndHeightChange) {
  TrunkPose pose;
  pose.reference_elevation_m = 0.05;
  pose.height_change_m = -0.01;
  SensorMount mount;
  EXPECT_NEAR(sensor_origin_in_map(pose, mount).z(), 0.05 + 0.26 - 0.01, 1e-12);
}

TEST(SensorTransform, InclinationIsThePrintedEquationSeven) {
  EXPECT_NEAR(scan_plane_inclination_rad(0.1, 0.0, 35 * kDeg), 0.1 + 35 * kDeg, 1e-12);
  std::mt19937_64 rng(7);
  std::uniform_real_distribution<double> angle(-0.4, 0.4);
  for (int k = 0; k < 200; ++k) {
    const double phi = angle(rng), psi = angle(rng), alpha = 35 * kDeg + angle(rng);
    const double printed = std::atan2(
        std::cos(phi) * std::sin(alpha) + std::sin(phi) * std::cos(alpha) * std::cos(psi),
        -std::sin(phi) * std::sin(alpha) + std::cos(phi) * std::cos(alpha) * std::cos(psi));
    EXPECT_NEAR(scan_plane_inclination_rad(phi, psi, alpha), printed, 1e-12);
  }
}

TEST(SensorTransform, InclinationGivesTheRiseOnAVerticalFaceWhenMovingForward) {
  // Where the composed scan plane meets the face x = 1 m at lateral y, and
  // how much that point rises when the sensor advances by d: d tan(gamma).
  std::mt19937_64 rng(11);
  std::uniform_real_distribution<double> angle(-0.3, 0.3);
  for (int k = 0; k < 100; ++k) {
    const double phi = angle(rng), psi = angle(rng), alpha = 35 * kDeg + angle(rng), y = angle(rng);
    const Eigen::Vector3d n = tilt_rotation(phi, psi, alpha) * Eigen::Vector3d::UnitZ();
    const auto trace_z = [&](double sensor_x) { return -(n.x() * (1.0 - sensor_x) + n.y() * y) / n.z(); };
    const double d = 0.01;
    EXPECT_NEAR(trace_z(d) - trace_z(0.0), d * std::tan(scan_plane_inclination_rad(phi, psi, alpha)), 1e-12);
  }
}

TEST(SensorTransform, AnalyticPartialsMatchFiniteDifferences) {
  std::mt19937_64 rng(42);
  std::uniform_real_distribution<double> angle(-0.4, 0.4);
  std::uniform_real_distribution<double> beam(-2.0, 2.0);
  std::uniform_real_distribution<double> range(0.05, 4.0);
  const double h = 1e-6;
  for (int k = 0; k < 500; ++k) {
    const double r = range(rng), t = beam(rng), pitch = angle(rng), roll = angle(rng);
    const double alpha = 0.6 + angle(rng);
    const ElevationPartials p = beam_elevation_partials(r, t, pitch, roll, alpha);
    EXPECT_NEAR(p.z_m, elevation_of(r, t, pitch, roll, alpha), 1e-12);
    const auto fd = [&](auto f) { return (f(h) - f(-h)) / (2 * h); };
    EXPECT_NEAR(p.d_range, fd([&](double e) { return elevation_of(r + e, t, pitch, roll, alpha); }), 1e-7);
    EXPECT_NEAR(p.d_pitch_m_per_rad, fd([&](double e) { return elevation_of(r, t, pitch + e, roll, alpha); }), 1e-7);
    EXPECT_NEAR(p.d_roll_m_per_rad, fd([&](double e) { return elevation_of(r, t, pitch, roll + e, alpha); }), 1e-7);
    EXPECT_NEAR(p.d_alpha_m_per_rad, fd([&](double e) { return elevation_of(r, t, pitch, roll, alpha + e); }), 1e-7);
  }
}

TEST(SensorTransform, PartialsAreLinearInTheBeamDirection) {
  // The mapper evaluates the partials once per scan at t = 0 and 90 deg and
  // combines them per beam; that is exact because z is linear in
  // (r cos t, r sin t).
  const double pitch = 0.07, roll = -0.05, alpha = 0.6;
  const ElevationPartials f = beam_elevation_partials(1.0, 0.0, pitch, roll, alpha);
  const ElevationPartials l = beam_elevation_partials(1.0, std::numbers::pi / 2, pitch, roll, alpha);
  for (double t : {-2.0, -0.5, 0.3, 1.9}) {
    const double r = 0.7, ct = std::cos(t), st = std::sin(t);
    const ElevationPartials p = beam_elevation_partials(r, t, pitch, roll, alpha);
    EXPECT_NEAR(p.d_range, ct * f.d_range + st * l.d_range, 1e-12);
    EXPECT_NEAR(p.d_pitch_m_per_rad, r * (ct * f.d_pitch_m_per_rad + st * l.d_pitch_m_per_rad), 1e-12);
    EXPECT_NEAR(p.d_roll_m_per_rad, r * (ct * f.d_roll_m_per_rad + st * l.d_roll_m_per_rad), 1e-12);
    EXPECT_NEAR(p.d_alpha_m_per_rad, r * (ct * f.d_alpha_m_per_rad + st * l.d_alpha_m_per_rad), 1e-12);
  }
}

}  // namespace
}  // namespace stridemap
