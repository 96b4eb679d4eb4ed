#include "stridemap/sim/footprint_beam_model.hpp"

#include <cmath>
#include <limits>
#include <memory>
#include <numbers>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "stridemap/core/error.hpp"
#include "stridemap/core/sensor_transform.hpp"
#include "stridemap/sim/urg_simulator.hpp"

namespace stridemap {
namespace {

const double alpha = 35.0 * std::numbers::pi / 180.0;  // the paper's mount: 0.26 m, 35 deg
const double urg_step_rad = 2.0 * std::numbers::pi / 1024.0;
const double fine_hz = FootprintBeamOptions{}.fine_frequency_hz;
const double coarse_hz = FootprintBeamOptions{}.coarse_frequency_hz;

double fine_period_m(double frequency_hz) { return speed_of_light_m_per_s / (2.0 * frequency_hz); }

// What the phase meter reads from a set of (range, amplitude) echoes.
WaveReading read(const std::vector<std::pair<double, double>>& echoes, double frequency_hz) {
  std::complex<double> sum(0.0, 0.0);
  for (const auto& [range_m, amplitude] : echoes) sum += echo_phasor(range_m, amplitude, frequency_hz);
  return read_wave(sum, frequency_hz);
}

// Beam t of a scan from the pose and mount, built as UrgSimulator builds it.
BeamRequest scan_beam(double t, const TrunkPose& pose = {}, const SensorMount& mount = {}) {
  const Eigen::Matrix3d rotation = sensor_to_map_rotation(pose, mount);
  BeamRequest beam;
  beam.origin_m = sensor_origin_in_map(pose, mount);
  beam.direction = std::cos(t) * rotation.col(0) + std::sin(t) * rotation.col(1);
  beam.sweep_axis = -std::sin(t) * rotation.col(0) + std::cos(t) * rotation.col(1);
  beam.plane_normal = rotation.col(2);
  beam.step_angle_rad = urg_step_rad;
  beam.max_range_m = 5.8;
  return beam;
}

// Without the surface texture the model is exact and deterministic, which the
// tests of geometry and phasor sums rely on.
FootprintBeamOptions untextured() {
  FootprintBeamOptions options;
  options.texture.log_sigma = 0.0;
  return options;
}

Scene floor_scene() {
  Scene scene;
  scene.terrain.reflectance = 0.5;
  return scene;
}

// The far top edge of a 0.1 m box lies exactly on the straight-ahead beam
// of the paper's mount: x = 0.16 / tan 35 deg.
const double edge_x_m = 0.16 / std::tan(alpha);
const double top_range_m = 0.16 / std::sin(alpha);
const double floor_range_m = 0.26 / std::sin(alpha);

Scene box_edge_scene(double width_m = 0.3) {
  Scene scene = floor_scene();
  BoxObject box;
  box.name = "box";
  box.center_x_m = edge_x_m - 0.05;
  box.length_m = 0.1;
  box.width_m = width_m;
  box.height_m = 0.1;
  box.reflectance = 0.6;
  scene.boxes.push_back(box);
  return scene;
}

TEST(PhasorModel, TwoEqualReturnsReadTheMidpoint) {
  const WaveReading reading = read({{0.40, 1.0}, {0.44, 1.0}}, fine_hz);
  EXPECT_NEAR(reading.range_m, 0.42, 1e-9);
  // The phasors are 2 pi f 0.08 / c apart; their sum is shorter than 2.
  const double half_phase = 2.0 * std::numbers::pi * fine_hz * 0.04 / speed_of_light_m_per_s;
  EXPECT_NEAR(reading.amplitude, 2.0 * std::cos(half_phase), 1e-12);
}

TEST(PhasorModel, ADominantReturnPullsTheReadingToItself) {
  const WaveReading reading = read({{0.40, 10.0}, {0.50, 1.0}}, fine_hz);
  // For small phase differences the reading is the amplitude-weighted mean.
  EXPECT_NEAR(reading.range_m, (10.0 * 0.40 + 0.50) / 11.0, 0.001);
  EXPECT_LT(reading.range_m - 0.40, 0.01);
}

TEST(PhasorModel, ASingleReturnAnywhereInRangeUnwraps) {
  for (double r : {0.02, 0.45, 1.7, 3.3, 3.5, 4.2, 5.6}) {
    const WaveReading fine = read({{r, 1.0}}, fine_hz);
    const WaveReading coarse = read({{r, 1.0}}, coarse_hz);
    EXPECT_LT(fine.range_m, fine_period_m(fine_hz));
    EXPECT_NEAR(unwrap_fine_with_coarse(fine.range_m, coarse.range_m, fine_hz), r, 1e-9) << r;
  }
}

TEST(PhasorModel, ADepthGapBeyondHalfTheFinePeriodWrapsInFrontOrBehind) {
  // 1.9 m lies between half the fine period (1.70 m at 44 MHz) and the
  // whole period: the fine phasors are more than pi apart, so their sum
  // points the short way round, in front of the near surface; the coarse
  // wave (22 m period) still reads between the two. Whichever period the
  // unwrapping then picks, the result is not between the surfaces.
  const double period_m = fine_period_m(fine_hz);
  ASSERT_GT(1.9, period_m / 2.0);
  for (double far_amplitude : {0.2, 0.5, 0.9, 2.0, 5.0}) {
    const std::vector<std::pair<double, double>> echoes{{0.5, 1.0}, {2.4, far_amplitude}};
    const WaveReading fine = read(echoes, fine_hz);
    const WaveReading coarse = read(echoes, coarse_hz);
    EXPECT_GT(coarse.range_m, 0.5);
    EXPECT_LT(coarse.range_m, 2.4);
    const double fine_near = fine.range_m > 0.5 ? fine.range_m - period_m : fine.range_m;
    EXPECT_LT(fine_near, 0.5) << far_amplitude;  // in front of the near surface, modulo the period
    EXPECT_GT(fine_near, 2.4 - period_m) << far_amplitude;
    const double r = unwrap_fine_with_coarse(fine.range_m, coarse.range_m, fine_hz);
    EXPECT_TRUE(r < 0.5 || r > 2.4) << "far amplitude " << far_amplitude << " reads " << r;
  }
}

TEST(FootprintBeamModel, ABeamOnTheFloorReadsTheFloorAndIsClean) {
  const SceneRayCaster caster(floor_scene());
  FootprintBeamModel model(untextured());
  SingleRayBeamModel single;
  std::mt19937_64 rng(1);
  for (double t : {0.0, 0.5, -0.9, 1.2}) {
    const BeamRequest beam = scan_beam(t);
    const BeamEcho echo = model.trace(caster, beam, rng);
    const BeamEcho axis = single.trace(caster, beam, rng);
    ASSERT_TRUE(echo.has_return) << t;
    EXPECT_EQ(echo.label, BeamLabel::clean) << t;
    EXPECT_FALSE(echo.sensor_error_code.has_value());
    EXPECT_NEAR(echo.range_m, axis.range_m, 0.001) << t;
    EXPECT_NEAR(echo.amplitude, axis.amplitude, 0.03 * axis.amplitude) << t;
    EXPECT_EQ(model.last_diagnostics().sub_ray_hits, 3 * 19);
  }
}

TEST(FootprintBeamModel, OneRingOneInstantIsTheSingleRay) {
  FootprintBeamOptions options = untextured();
  options.footprint_rings = 0;
  options.smear_instants = 1;
  FootprintBeamModel model(options);
  EXPECT_EQ(model.sub_rays_per_instant(), 1);
  SingleRayBeamModel single;
  const SceneRayCaster caster(box_edge_scene());
  std::mt19937_64 rng(1);
  for (double t = -1.0; t <= 1.0; t += 0.05) {
    const BeamRequest beam = scan_beam(t);
    const BeamEcho a = model.trace(caster, beam, rng), b = single.trace(caster, beam, rng);
    ASSERT_EQ(a.has_return, b.has_return);
    EXPECT_NEAR(a.range_m, b.range_m, 1e-9) << t;
    EXPECT_NEAR(a.amplitude, b.amplitude, 1e-9 * b.amplitude) << t;
    EXPECT_EQ(a.label, BeamLabel::clean);
  }
}

TEST(FootprintBeamModel, TextureScattersTheMixedReadingsAlongAnEdge) {
  // The box's far top edge runs along the scan line: without texture every
  // footprint straddles it in the same proportion and the mixed readings
  // line up; with texture each beam sees other grains on either side.
  const SceneRayCaster caster(box_edge_scene());
  // 0.7 mm back, so that no sub-ray runs exactly along the edge (one that
  // did would flip sides from beam to beam on rounding alone).
  TrunkPose pose;
  pose.x_m = -0.0007;
  const auto spread_m = [&](const FootprintBeamOptions& options) {
    FootprintBeamModel model(options);
    std::mt19937_64 rng(1);
    std::vector<double> ranges;
    for (int i = -15; i <= 15; ++i) {
      const BeamEcho echo = model.trace(caster, scan_beam(i * urg_step_rad, pose), rng);
      EXPECT_EQ(echo.label, BeamLabel::mixed) << i;
      ranges.push_back(echo.range_m);
    }
    // Beam-to-beam jitter: the RMS step between neighbours (a smooth trend
    // along the row, from the changing geometry, hardly counts).
    double squares = 0.0;
    for (std::size_t i = 1; i < ranges.size(); ++i) squares += std::pow(ranges[i] - ranges[i - 1], 2);
    return std::sqrt(squares / static_cast<double>(ranges.size() - 1));
  };
  const double smooth = spread_m(untextured());
  const double textured = spread_m(FootprintBeamOptions{});
  EXPECT_LT(smooth, 0.0015);
  EXPECT_GT(textured, 3.0 * smooth);
  EXPECT_GT(textured, 0.002);
}

TEST(FootprintBeamModel, TheFootprintHasTheDatasheetSize) {
  const FootprintBeamModel model;
  EXPECT_LT(model.footprint_diameter_m(2.0), 0.020);
  EXPECT_LE(model.footprint_diameter_m(4.0), 0.040);
  EXPECT_NEAR(model.footprint_diameter_m(0.0), 0.004, 1e-12);
  // On a wall turned 45 deg about the vertical, 2 m ahead of a horizontal
  // beam, range varies one to one with the lateral offset: the spread of
  // hit ranges is the footprint's width across the wall (outer ring at the
  // 1/e^2 radius, so about one diameter). No smear: step angle 0.
  Scene scene = floor_scene();
  BoxObject wall;  // a slab whose near face is the plane x + y = 2
  wall.name = "wall";
  wall.center_x_m = 2.0 + 0.1 / std::sqrt(2.0);
  wall.center_y_m = 0.1 / std::sqrt(2.0);
  wall.length_m = 0.2;
  wall.width_m = 2.0;
  wall.height_m = 1.0;
  wall.yaw_rad = std::numbers::pi / 4.0;
  scene.boxes.push_back(wall);
  const SceneRayCaster caster(scene);
  SensorMount level;
  level.height_m = 0.5;
  level.pitch_rad = 0.0;
  BeamRequest beam = scan_beam(0.0, TrunkPose{}, level);
  beam.step_angle_rad = 0.0;
  FootprintBeamModel traced;
  std::mt19937_64 rng(1);
  const BeamEcho echo = traced.trace(caster, beam, rng);
  ASSERT_TRUE(echo.has_return);
  EXPECT_NEAR(echo.range_m, 2.0, 0.001);
  const FootprintDiagnostics& d = traced.last_diagnostics();
  EXPECT_NEAR(d.farthest_hit_m - d.nearest_hit_m, traced.footprint_diameter_m(2.0), 0.1 * traced.footprint_diameter_m(2.0));
}

TEST(FootprintBeamModel, AFootprintOnABoxEdgeAndTheFloorBehindIsMixed) {
  const SceneRayCaster caster(box_edge_scene());
  FootprintBeamModel model;
  std::mt19937_64 rng(1);
  const BeamEcho echo = model.trace(caster, scan_beam(0.0), rng);
  ASSERT_TRUE(echo.has_return);
  EXPECT_FALSE(echo.sensor_error_code.has_value());
  EXPECT_EQ(echo.label, BeamLabel::mixed);
  const FootprintDiagnostics& d = model.last_diagnostics();
  EXPECT_NEAR(d.nearest_hit_m, top_range_m, 0.01);
  EXPECT_NEAR(d.farthest_hit_m, floor_range_m, 0.01);
  // The 0.17 m gap is far below half the fine period: the reading lies
  // between the surfaces.
  EXPECT_GT(echo.range_m, top_range_m + 0.015);
  EXPECT_LT(echo.range_m, floor_range_m - 0.015);
  // Moving the cart 10 mm either way puts the whole footprint on one
  // surface again.
  for (double dx : {-0.01, 0.01}) {
    TrunkPose moved;
    moved.x_m = dx;
    const BeamEcho clean = model.trace(caster, scan_beam(0.0, moved), rng);
    EXPECT_EQ(clean.label, BeamLabel::clean) << dx;
    EXPECT_NEAR(clean.range_m, dx < 0 ? top_range_m : floor_range_m, 0.01) << dx;
  }
}

// A thin pole 0.5 m ahead of a level sensor, a wall 1.9 m behind it.
Scene pole_scene(bool with_wall) {
  Scene scene = floor_scene();
  CylinderObject pole;
  pole.name = "pole";
  pole.center_x_m = 0.52;
  pole.radius_m = 0.02;
  pole.height_m = 1.0;
  pole.reflectance = 0.5;
  scene.cylinders.push_back(pole);
  if (with_wall) {
    BoxObject wall;
    wall.name = "wall";
    wall.center_x_m = 2.5;
    wall.length_m = 0.2;
    wall.width_m = 3.0;
    wall.height_m = 1.0;
    scene.boxes.push_back(wall);
  }
  return scene;
}

SensorMount level_mount() {
  SensorMount mount;
  mount.height_m = 0.5;
  mount.pitch_rad = 0.0;
  return mount;
}

TEST(FootprintBeamModel, APoleBeforeAFarWallGivesReadingsOutsideBothButNeverBetween) {
  const SceneRayCaster caster(pole_scene(true));
  FootprintBeamOptions options;
  options.wave_timing = WaveTiming::simultaneous;
  FootprintBeamModel model(options);
  std::mt19937_64 rng(1);
  const double tol = options.mixed_tolerance_m;
  int outside = 0, mixed = 0, rejected = 0;
  // Sweep the beam across the pole's left edge (at 0.04 rad) in 0.1 mrad.
  for (double t = 0.02; t <= 0.06; t += 1e-4) {
    const BeamEcho echo = model.trace(caster, scan_beam(t, TrunkPose{}, level_mount()), rng);
    ASSERT_TRUE(echo.has_return);
    // Where the fine phasors nearly cancel, the fine wave is much weaker
    // than the coarse one and the sensor rejects the beam (code 8).
    if (echo.sensor_error_code) {
      ++rejected;
      continue;
    }
    const FootprintDiagnostics& d = model.last_diagnostics();
    const bool near_pole = std::abs(echo.range_m - d.nearest_hit_m) <= tol;
    const bool near_wall = std::abs(echo.range_m - d.farthest_hit_m) <= tol;
    if (d.farthest_hit_m - d.nearest_hit_m < 1.0) continue;  // footprint on one surface
    EXPECT_TRUE(near_pole || near_wall || echo.range_m < d.nearest_hit_m || echo.range_m > d.farthest_hit_m)
        << "t = " << t << " reads " << echo.range_m << " between " << d.nearest_hit_m << " and " << d.farthest_hit_m;
    outside += echo.range_m < d.nearest_hit_m - tol || echo.range_m > d.farthest_hit_m + tol;
    mixed += echo.label == BeamLabel::mixed;
  }
  EXPECT_GT(outside, 0);
  EXPECT_EQ(mixed, outside);
  EXPECT_LT(rejected, outside);
}

TEST(FootprintBeamModel, WavesThatSeeDifferentTargetsGiveCodeEight) {
  // No wall: past the pole the beam meets nothing within range. A wide step
  // (0.06 rad, test geometry) lets the mirror carry the footprint off the
  // pole within one measurement. The pole's left edge is at 0.0385 rad and
  // the footprint's radius 6 mrad at 0.5 m. Measured one after the other,
  // the fine wave (instants at 0.028 and 0.048 rad) sees the pole and the
  // coarse wave (0.048 and 0.068 rad) sees nothing.
  const SceneRayCaster caster(pole_scene(false));
  BeamRequest beam = scan_beam(0.035, TrunkPose{}, level_mount());
  beam.step_angle_rad = 0.06;
  beam.max_range_m = 1.5;
  std::mt19937_64 rng(1);
  FootprintBeamModel sequential;
  const BeamEcho rejected = sequential.trace(caster, beam, rng);
  ASSERT_TRUE(rejected.sensor_error_code.has_value());
  EXPECT_EQ(*rejected.sensor_error_code, urg_code_two_wave_difference);
  EXPECT_EQ(rejected.label, BeamLabel::dropped);
  EXPECT_EQ(sequential.last_diagnostics().coarse.amplitude, 0.0);
  // Measured together (instants at 0.015, 0.035 and 0.055 rad), both
  // waves see the same part of the pole: a weaker but clean reading.
  FootprintBeamOptions options;
  options.wave_timing = WaveTiming::simultaneous;
  FootprintBeamModel simultaneous(options);
  const BeamEcho accepted = simultaneous.trace(caster, beam, rng);
  EXPECT_FALSE(accepted.sensor_error_code.has_value());
  EXPECT_EQ(accepted.label, BeamLabel::clean);
  EXPECT_NEAR(accepted.range_m, 0.5, 0.01);
}

// A box as wide as the scan line's crossing: its far top edge lies across
// the whole sector, as in the paper's Fig. 11 (right).
UrgSimulator box_scan_simulator(std::uint64_t seed) {
  return UrgSimulator(box_edge_scene(0.6), UrgParameters{}, UrgSimOptions{}, seed,
                      std::make_unique<FootprintBeamModel>());
}

TEST(FootprintBeamModel, AScanOfABoxHasCleanMixedAndDroppedBeams) {
  UrgSimulator sim = box_scan_simulator(5);
  UrgRawScan scan;
  std::vector<BeamLabel> labels;
  sim.scan(TrunkPose{}, SensorMount{}, 0.0, scan, &labels);
  int clean = 0, mixed = 0, dropped = 0;
  for (std::size_t i = 0; i < labels.size(); ++i) {
    const long value = static_cast<long>(scan.values_mm[i]);
    // On a horizontal plane the tilted scan plane draws a line parallel to
    // Y: ranges grow as 1 / cos t along it.
    const double t = static_cast<double>(scan.first_step + static_cast<int>(i) - 384) * urg_step_rad;
    switch (labels[i]) {
      case BeamLabel::clean: ++clean; EXPECT_GE(value, 20); break;
      case BeamLabel::dropped: ++dropped; EXPECT_LT(value, 20); break;
      case BeamLabel::mixed:
        ++mixed;
        // Between the box top and the floor behind it, give or take the
        // sensor's noise and systematic error.
        EXPECT_GT(value, std::lround(top_range_m / std::cos(t) * 1000.0) + 5) << "beam " << i;
        EXPECT_LT(value, std::lround(floor_range_m / std::cos(t) * 1000.0) - 5) << "beam " << i;
        break;
    }
  }
  EXPECT_GT(clean, 100);  // the floor to both sides
  // The edge lies along the scan line over the box's 0.6 m width: a
  // trailing group of mixed beams, most of the 2 atan(0.3 / 0.23) / 6.1 mrad
  // = 300 beams that cross it (271 with this seed).
  EXPECT_GT(mixed, 250);
  EXPECT_GT(dropped, 20);  // grazing floor far out to the sides (code 1), and nothing behind the sensor
}

TEST(FootprintBeamModel, SameSeedSameScan) {
  UrgSimulator a = box_scan_simulator(9), b = box_scan_simulator(9);
  UrgRawScan scan_a, scan_b;
  std::vector<BeamLabel> labels_a, labels_b;
  TrunkPose pose;
  pose.x_m = 0.003;
  pose.yaw_rad = 0.1;
  for (int k = 0; k < 3; ++k) {
    a.scan(pose, SensorMount{}, 0.1 * k, scan_a, &labels_a);
    b.scan(pose, SensorMount{}, 0.1 * k, scan_b, &labels_b);
    EXPECT_EQ(scan_a.values_mm, scan_b.values_mm);
    EXPECT_EQ(labels_a, labels_b);
  }
  // The model itself holds no state between beams.
  const SceneRayCaster caster(box_edge_scene());
  FootprintBeamModel model;
  std::mt19937_64 rng(1);
  const BeamEcho first = model.trace(caster, scan_beam(0.0), rng);
  model.trace(caster, scan_beam(0.7), rng);
  const BeamEcho again = model.trace(caster, scan_beam(0.0), rng);
  EXPECT_EQ(first.range_m, again.range_m);
  EXPECT_EQ(first.amplitude, again.amplitude);
}

void expect_rejected(const FootprintBeamOptions& options, const std::string& field) {
  try {
    FootprintBeamModel model(options);
    ADD_FAILURE() << "accepted a bad " << field;
  } catch (const InputError& e) {
    const std::string message = e.what();
    EXPECT_NE(message.find("footprint beam model options: " + field + ":"), std::string::npos) << message;
  }
}

TEST(FootprintBeamModel, RejectsBadOptions) {
  const double nan = std::nan("");
  FootprintBeamOptions o;
  o.beam_divergence_rad = -0.001;
  expect_rejected(o, "beam_divergence_rad");
  o = {};
  o.exit_diameter_m = nan;
  expect_rejected(o, "exit_diameter_m");
  o = {};
  o.footprint_rings = 31;
  expect_rejected(o, "footprint_rings");
  o = {};
  o.footprint_outer_radius = 0.0;
  expect_rejected(o, "footprint_outer_radius");
  o = {};
  o.smear_instants = 0;
  expect_rejected(o, "smear_instants");
  o = {};
  o.coarse_frequency_hz = 50e6;
  expect_rejected(o, "coarse_frequency_hz");
  o = {};
  o.fine_frequency_hz = std::numeric_limits<double>::infinity();
  expect_rejected(o, "fine_frequency_hz");
  o = {};
  o.max_two_wave_amplitude_ratio = 1.0;
  expect_rejected(o, "max_two_wave_amplitude_ratio");
  o = {};
  o.detection_amplitude = -1.0;
  expect_rejected(o, "detection_amplitude");
  o = {};
  o.mixed_tolerance_m = nan;
  expect_rejected(o, "mixed_tolerance_m");
  o = {};
  o.wave_timing = static_cast<WaveTiming>(7);
  expect_rejected(o, "wave_timing");
  o = {};
  o.max_two_wave_amplitude_ratio = std::numeric_limits<double>::infinity();
  EXPECT_NO_THROW(FootprintBeamModel{o});
}

}  // namespace
}  // namespace stridemap
