#include "stridemap/core/sensor_transform.hpp"

#include <cmath>
#include <cstring>
#include <numbers>
#include <random>
#include <vector>

#include <Eigen/Geometry>
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

// The full mount, composed here independently of the library.
Eigen::Matrix3d rotation_about(double angle, const Eigen::Vector3d& axis) {
  return Eigen::AngleAxisd(angle, axis).toRotationMatrix();
}

Eigen::Matrix3d full_tilt(double pitch, double roll, const SensorMount& m) {
  return rotation_about(pitch, Eigen::Vector3d::UnitY()) * rotation_about(roll, Eigen::Vector3d::UnitX()) *
         rotation_about(m.yaw_rad, Eigen::Vector3d::UnitZ()) * rotation_about(m.pitch_rad, Eigen::Vector3d::UnitY()) *
         rotation_about(m.roll_rad, Eigen::Vector3d::UnitX());
}

double full_elevation_of(double r, double t, double pitch, double roll, const SensorMount& m) {
  return (full_tilt(pitch, roll, m) * Eigen::Vector3d(r * std::cos(t), r * std::sin(t), 0)).z();
}

struct RandomPoses {
  std::mt19937_64 rng;
  std::uniform_real_distribution<double> angle{-0.4, 0.4};
  std::uniform_real_distribution<double> heading{-3.2, 3.2};
  std::uniform_real_distribution<double> length{-2.0, 2.0};
  explicit RandomPoses(std::uint64_t seed) : rng(seed) {}
  TrunkPose pose() {
    TrunkPose p;
    p.x_m = length(rng);
    p.y_m = length(rng);
    p.yaw_rad = heading(rng);
    p.pitch_rad = angle(rng);
    p.roll_rad = angle(rng);
    p.reference_elevation_m = 0.1 * length(rng);
    p.height_change_m = 0.01 * length(rng);
    return p;
  }
  SensorMount paper_mount() {
    SensorMount m;
    m.height_m = 0.3 + 0.1 * length(rng);
    m.pitch_rad = 0.6 + angle(rng);
    m.forward_offset_m = 0.1 * length(rng);
    m.lateral_offset_m = 0.1 * length(rng);
    return m;
  }
  SensorMount full_mount() {
    SensorMount m = paper_mount();
    m.roll_rad = angle(rng);
    m.yaw_rad = 2.0 * angle(rng);
    return m;
  }
};

TEST(SensorTransformFullMount, ZeroMountRollAndYawGiveTheOldDoublesBitForBit) {
  // What sensor_to_map_rotation and sensor_origin_in_map computed before the
  // mount had roll and yaw.
  const auto old_rotation = [](const TrunkPose& pose, const SensorMount& m) -> Eigen::Matrix3d {
    const Eigen::Matrix3d yaw = rotation_about(pose.yaw_rad, Eigen::Vector3d::UnitZ());
    return yaw * tilt_rotation(pose.pitch_rad, pose.roll_rad, m.pitch_rad);
  };
  const auto old_origin = [](const TrunkPose& pose, const SensorMount& m) -> Eigen::Vector3d {
    const double c = std::cos(pose.yaw_rad), s = std::sin(pose.yaw_rad);
    return {pose.x_m + c * m.forward_offset_m - s * m.lateral_offset_m,
            pose.y_m + s * m.forward_offset_m + c * m.lateral_offset_m,
            pose.reference_elevation_m + m.height_m + pose.height_change_m};
  };
  RandomPoses random(3);
  for (int k = 0; k < 2000; ++k) {
    const TrunkPose pose = random.pose();
    const SensorMount mount = random.paper_mount();
    const Eigen::Matrix3d now = sensor_to_map_rotation(pose, mount), before = old_rotation(pose, mount);
    for (int i = 0; i < 9; ++i) EXPECT_EQ(now(i), before(i)) << "entry " << i << " of pose " << k;
    const Eigen::Matrix3d tilt = tilt_rotation(pose.pitch_rad, pose.roll_rad, mount),
                          old_tilt = tilt_rotation(pose.pitch_rad, pose.roll_rad, mount.pitch_rad);
    for (int i = 0; i < 9; ++i) EXPECT_EQ(tilt(i), old_tilt(i));
    const Eigen::Vector3d origin = sensor_origin_in_map(pose, mount), old = old_origin(pose, mount);
    for (int i = 0; i < 3; ++i) EXPECT_EQ(origin(i), old(i));
    EXPECT_EQ(scan_plane_inclination_rad(pose.pitch_rad, pose.roll_rad, mount),
              scan_plane_inclination_rad(pose.pitch_rad, pose.roll_rad, mount.pitch_rad));
    const double t = 0.5 * pose.yaw_rad, r = 1.0 + pose.x_m;
    const ElevationPartials a = beam_elevation_partials(r, t, pose.pitch_rad, pose.roll_rad, mount);
    const ElevationPartials b = beam_elevation_partials(r, t, pose.pitch_rad, pose.roll_rad, mount.pitch_rad);
    EXPECT_EQ(a.z_m, b.z_m);
    EXPECT_EQ(a.d_range, b.d_range);
    EXPECT_EQ(a.d_pitch_m_per_rad, b.d_pitch_m_per_rad);
    EXPECT_EQ(a.d_roll_m_per_rad, b.d_roll_m_per_rad);
    EXPECT_EQ(a.d_alpha_m_per_rad, b.d_alpha_m_per_rad);
    const ElevationPartials lever = sensor_origin_elevation_partials(pose, mount);
    EXPECT_EQ(lever.d_pitch_m_per_rad, 0.0);
    EXPECT_EQ(lever.d_roll_m_per_rad, 0.0);
  }
}

TEST(SensorTransformFullMount, MountYawTurnsTheScannerAndMountRollTiltsItsPlane) {
  TrunkPose pose;
  SensorMount mount;
  mount.pitch_rad = 0.0;
  mount.yaw_rad = std::numbers::pi / 2;  // looking to the trunk's left
  Eigen::Vector3d ahead = sensor_to_map_rotation(pose, mount) * Eigen::Vector3d::UnitX();
  EXPECT_NEAR(ahead.x(), 0.0, 1e-15);
  EXPECT_NEAR(ahead.y(), 1.0, 1e-15);
  // Yaw first, then alpha about the turned sensor's own Y: still looks down.
  mount.pitch_rad = 30 * kDeg;
  ahead = sensor_to_map_rotation(pose, mount) * Eigen::Vector3d::UnitX();
  EXPECT_NEAR(ahead.z(), -std::sin(30 * kDeg), 1e-15);
  EXPECT_NEAR(ahead.y(), std::cos(30 * kDeg), 1e-15);
  // Positive roll lifts the scanner's left beam.
  mount = SensorMount{};
  mount.pitch_rad = 0.0;
  mount.roll_rad = 5 * kDeg;
  const Eigen::Vector3d left = sensor_to_map_rotation(pose, mount) * Eigen::Vector3d::UnitY();
  EXPECT_NEAR(left.z(), std::sin(5 * kDeg), 1e-15);
}

TEST(SensorTransformFullMount, FullMountPartialsMatchFiniteDifferences) {
  RandomPoses random(19);
  std::uniform_real_distribution<double> beam(-2.0, 2.0);
  std::uniform_real_distribution<double> range(0.05, 4.0);
  const double h = 1e-6;
  const auto fd = [&](auto f) { return (f(h) - f(-h)) / (2 * h); };
  for (int k = 0; k < 500; ++k) {
    const TrunkPose pose = random.pose();
    const SensorMount m = random.full_mount();
    const double r = range(random.rng), t = beam(random.rng), pitch = pose.pitch_rad, roll = pose.roll_rad;
    const ElevationPartials p = beam_elevation_partials(r, t, pitch, roll, m);
    EXPECT_NEAR(p.z_m, full_elevation_of(r, t, pitch, roll, m), 1e-12);
    const Eigen::Vector3d in_map = sensor_to_map_rotation(pose, m) * Eigen::Vector3d(r * std::cos(t), r * std::sin(t), 0);
    EXPECT_NEAR(p.z_m, in_map.z(), 1e-12);
    EXPECT_NEAR(p.d_range, fd([&](double e) { return full_elevation_of(r + e, t, pitch, roll, m); }), 1e-7);
    EXPECT_NEAR(p.d_pitch_m_per_rad, fd([&](double e) { return full_elevation_of(r, t, pitch + e, roll, m); }), 1e-7);
    EXPECT_NEAR(p.d_roll_m_per_rad, fd([&](double e) { return full_elevation_of(r, t, pitch, roll + e, m); }), 1e-7);
    EXPECT_NEAR(p.d_alpha_m_per_rad, fd([&](double e) {
                  SensorMount tilted = m;
                  tilted.pitch_rad += e;
                  return full_elevation_of(r, t, pitch, roll, tilted);
                }),
                1e-7);
  }
}

TEST(SensorTransformFullMount, FullMountPartialsStayLinearInTheBeamDirection) {
  // What TerrainMapper relies on, now with the mount's roll applied to the beam.
  SensorMount m;
  m.roll_rad = 5 * kDeg;
  m.yaw_rad = 10 * kDeg;
  const double pitch = 0.07, roll = -0.05;
  const ElevationPartials f = beam_elevation_partials(1.0, 0.0, pitch, roll, m);
  const ElevationPartials l = beam_elevation_partials(1.0, std::numbers::pi / 2, pitch, roll, m);
  for (double t : {-2.0, -0.5, 0.3, 1.9}) {
    const double r = 0.7, ct = std::cos(t), st = std::sin(t);
    const ElevationPartials p = beam_elevation_partials(r, t, pitch, roll, m);
    EXPECT_NEAR(p.d_range, ct * f.d_range + st * l.d_range, 1e-12);
    EXPECT_NEAR(p.d_pitch_m_per_rad, r * (ct * f.d_pitch_m_per_rad + st * l.d_pitch_m_per_rad), 1e-12);
    EXPECT_NEAR(p.d_roll_m_per_rad, r * (ct * f.d_roll_m_per_rad + st * l.d_roll_m_per_rad), 1e-12);
    EXPECT_NEAR(p.d_alpha_m_per_rad, r * (ct * f.d_alpha_m_per_rad + st * l.d_alpha_m_per_rad), 1e-12);
  }
}

TEST(SensorTransformFullMount, InclinationGivesTheRiseOnAVerticalFaceWithMountRollAndYaw) {
  RandomPoses random(23);
  for (int k = 0; k < 100; ++k) {
    const TrunkPose pose = random.pose();
    const SensorMount m = random.full_mount();
    const double y = 0.5 * random.angle(random.rng);
    const Eigen::Vector3d n = full_tilt(pose.pitch_rad, pose.roll_rad, m) * Eigen::Vector3d::UnitZ();
    const auto trace_z = [&](double sensor_x) { return -(n.x() * (1.0 - sensor_x) + n.y() * y) / n.z(); };
    const double d = 0.01;
    EXPECT_NEAR(trace_z(d) - trace_z(0.0), d * std::tan(scan_plane_inclination_rad(pose.pitch_rad, pose.roll_rad, m)),
                1e-12);
  }
}

TEST(SensorTransformFullMount, ElevationRowsAreTheThirdRowOfTheTiltAndItsDerivatives) {
  // Both forms: the hand-multiplied one for the paper's mount and the
  // composed one for a mount with roll or yaw, against finite differences
  // of the independently composed tilt.
  RandomPoses random(37);
  const double h = 1e-6;
  for (int k = 0; k < 200; ++k) {
    const TrunkPose pose = random.pose();
    const SensorMount m = k % 2 ? random.full_mount() : random.paper_mount();
    const ElevationRows rows = elevation_rows(pose.pitch_rad, pose.roll_rad, m);
    const auto third_row = [&](double dp, double dr, double da) -> Eigen::RowVector3d {
      SensorMount tilted = m;
      tilted.pitch_rad += da;
      return full_tilt(pose.pitch_rad + dp, pose.roll_rad + dr, tilted).row(2);
    };
    EXPECT_TRUE(rows.row.isApprox(third_row(0, 0, 0), 1e-14));
    EXPECT_LT((rows.d_pitch - (third_row(h, 0, 0) - third_row(-h, 0, 0)) / (2 * h)).norm(), 1e-8);
    EXPECT_LT((rows.d_roll - (third_row(0, h, 0) - third_row(0, -h, 0)) / (2 * h)).norm(), 1e-8);
    EXPECT_LT((rows.d_alpha - (third_row(0, 0, h) - third_row(0, 0, -h)) / (2 * h)).norm(), 1e-8);
  }
}

TEST(SensorTransformFullMount, PoseWithZPlacesTheSensorByTheRigidTransform) {
  RandomPoses random(29);
  for (int k = 0; k < 200; ++k) {
    TrunkPose pose = random.pose();
    pose.z_m = 0.4 + 0.1 * random.angle(random.rng);
    const SensorMount m = random.full_mount();
    const Eigen::Matrix3d trunk = rotation_about(pose.yaw_rad, Eigen::Vector3d::UnitZ()) *
                                  rotation_about(pose.pitch_rad, Eigen::Vector3d::UnitY()) *
                                  rotation_about(pose.roll_rad, Eigen::Vector3d::UnitX());
    const Eigen::Vector3d expected = Eigen::Vector3d(pose.x_m, pose.y_m, *pose.z_m) +
                                     trunk * Eigen::Vector3d(m.forward_offset_m, m.lateral_offset_m, m.height_m);
    EXPECT_TRUE(sensor_origin_in_map(pose, m).isApprox(expected, 1e-14));
    // h_ref and the leg height change belong to the paper's model only.
    TrunkPose other = pose;
    other.reference_elevation_m += 1.0;
    other.height_change_m -= 0.5;
    EXPECT_EQ(sensor_origin_in_map(other, m), sensor_origin_in_map(pose, m));
    // The whole sensor-to-map transform is then trunk * mount.
    const Eigen::Vector3d point(0.3, -0.2, 0.05);
    const Eigen::Vector3d via_frames =
        Eigen::Vector3d(pose.x_m, pose.y_m, *pose.z_m) +
        trunk * (Eigen::Vector3d(m.forward_offset_m, m.lateral_offset_m, m.height_m) + mount_rotation(m) * point);
    EXPECT_TRUE(sensor_point_to_map(point, pose, m).isApprox(via_frames, 1e-14));
  }
}

TEST(SensorTransformFullMount, LeverArmPartialsMatchFiniteDifferences) {
  RandomPoses random(31);
  const double h = 1e-6;
  for (int k = 0; k < 300; ++k) {
    TrunkPose pose = random.pose();
    pose.z_m = 0.5;
    const SensorMount m = random.full_mount();
    const auto origin_z = [&](double dpitch, double droll) {
      TrunkPose moved = pose;
      moved.pitch_rad += dpitch;
      moved.roll_rad += droll;
      return sensor_origin_in_map(moved, m).z();
    };
    const ElevationPartials p = sensor_origin_elevation_partials(pose, m);
    EXPECT_NEAR(p.z_m, origin_z(0, 0) - *pose.z_m, 1e-12);
    EXPECT_NEAR(p.d_pitch_m_per_rad, (origin_z(h, 0) - origin_z(-h, 0)) / (2 * h), 1e-8);
    EXPECT_NEAR(p.d_roll_m_per_rad, (origin_z(0, h) - origin_z(0, -h)) / (2 * h), 1e-8);
    EXPECT_EQ(p.d_alpha_m_per_rad, 0.0);
  }
}

// The rotations made from a cosine and sine are Eigen's AngleAxis matrices
// bit for bit (memcmp: a zero's sign counts), over angles of every size and
// sign, so that a scan's geometry made from shared sines moves no map bit.
TEST(SensorTransform, RotationsFromSinesAreAngleAxisBitForBit) {
  std::vector<double> angles = {0.0, -0.0, 1e-300, -1e-300, 0.02, -0.02, 1.0, -1.0, std::numbers::pi / 2,
                                -std::numbers::pi / 2, 2.0, -2.5, std::numbers::pi, -std::numbers::pi, 7.0, 1e6};
  std::mt19937_64 rng(7);
  std::uniform_real_distribution<double> u(-4.0, 4.0);
  for (int k = 0; k < 2000; ++k) angles.push_back(u(rng));
  for (const double a : angles) {
    const double c = std::cos(a), s = std::sin(a);
    const Eigen::Matrix3d x = Eigen::AngleAxisd(a, Eigen::Vector3d::UnitX()).toRotationMatrix();
    const Eigen::Matrix3d y = Eigen::AngleAxisd(a, Eigen::Vector3d::UnitY()).toRotationMatrix();
    const Eigen::Matrix3d z = Eigen::AngleAxisd(a, Eigen::Vector3d::UnitZ()).toRotationMatrix();
    const Eigen::Matrix3d mx = rotation_about_x(c, s), my = rotation_about_y(c, s), mz = rotation_about_z(c, s);
    EXPECT_EQ(std::memcmp(x.data(), mx.data(), sizeof(double) * 9), 0) << "x, angle " << a;
    EXPECT_EQ(std::memcmp(y.data(), my.data(), sizeof(double) * 9), 0) << "y, angle " << a;
    EXPECT_EQ(std::memcmp(z.data(), mz.data(), sizeof(double) * 9), 0) << "z, angle " << a;
    if (HasFailure()) return;
  }
}

}  // namespace
}  // namespace stridemap
