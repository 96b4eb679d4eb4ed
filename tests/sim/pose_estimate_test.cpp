#include "stridemap/sim/pose_estimate.hpp"

#include <cmath>
#include <string>
#include <numbers>
#include <vector>

#include <gtest/gtest.h>

#include "stridemap/core/error.hpp"
#include "stridemap/core/height_fusion.hpp"

namespace stridemap {
namespace pose_estimate_test {
namespace {

constexpr double kDeg = std::numbers::pi / 180.0;

TrunkState truth_at(double x, double ground = 0.0) {
  TrunkState t;
  t.pose.x_m = x;
  t.pose.y_m = -0.2;
  t.pose.yaw_rad = 0.3;
  t.pose.pitch_rad = 0.02;
  t.pose.roll_rad = -0.01;
  t.pose.reference_elevation_m = ground;
  t.pose.height_change_m = 0.003;
  return t;
}

struct Moments {
  double mean = 0, sigma = 0;
};
Moments moments(const std::vector<double>& v) {
  Moments m;
  for (double x : v) m.mean += x;
  m.mean /= static_cast<double>(v.size());
  for (double x : v) m.sigma += (x - m.mean) * (x - m.mean);
  m.sigma = std::sqrt(m.sigma / static_cast<double>(v.size() - 1));
  return m;
}

// Every channel's error has the bias and the sigma its options say: the
// sample mean within 4 standard errors, the sample sigma within 4 %.
TEST(PoseEstimate, ErrorStatisticsMatchTheOptions) {
  PoseErrorOptions o;
  o.imu_pitch_noise_sigma_rad = 0.4 * kDeg;
  o.imu_pitch_bias_rad = -0.25 * kDeg;
  o.imu_roll_noise_sigma_rad = 0.15 * kDeg;
  o.imu_roll_bias_rad = 0.5 * kDeg;
  o.camera_position_noise_sigma_m = 0.004;
  o.camera_yaw_noise_sigma_rad = 0.6 * kDeg;
  o.leg_height_noise_sigma_m = 0.0025;
  o.reference = ReferenceElevationSource::truth;
  PoseEstimator estimator(o, GaitOptions{}, 7);
  const ElevationMap map;
  constexpr int n = 20000;
  std::vector<double> pitch, roll, x, y, yaw, height, reference;
  for (int k = 0; k < n; ++k) {
    const TrunkState t = truth_at(0.001 * k, 0.01 * std::sin(k));
    const TrunkPose e = estimator.estimate(t, map);
    pitch.push_back(e.pitch_rad - t.pose.pitch_rad);
    roll.push_back(e.roll_rad - t.pose.roll_rad);
    x.push_back(e.x_m - t.pose.x_m);
    y.push_back(e.y_m - t.pose.y_m);
    yaw.push_back(e.yaw_rad - t.pose.yaw_rad);
    height.push_back(e.height_change_m - t.pose.height_change_m);
    reference.push_back(e.reference_elevation_m - t.pose.reference_elevation_m);
  }
  const auto check = [&](const std::vector<double>& errors, double bias, double sigma, const char* name) {
    const Moments m = moments(errors);
    EXPECT_NEAR(m.mean, bias, 4.0 * sigma / std::sqrt(double(n))) << name;
    EXPECT_NEAR(m.sigma, sigma, 0.04 * sigma) << name;
  };
  check(pitch, o.imu_pitch_bias_rad, o.imu_pitch_noise_sigma_rad, "pitch");
  check(roll, o.imu_roll_bias_rad, o.imu_roll_noise_sigma_rad, "roll");
  check(x, 0.0, o.camera_position_noise_sigma_m, "x");
  check(y, 0.0, o.camera_position_noise_sigma_m, "y");
  check(yaw, 0.0, o.camera_yaw_noise_sigma_rad, "yaw");
  check(height, 0.0, o.leg_height_noise_sigma_m, "leg height");
  for (double r : reference) ASSERT_EQ(r, 0.0);  // h_ref from the truth
  // x and y draw independently.
  double cross = 0;
  for (int k = 0; k < n; ++k) cross += x[k] * y[k];
  EXPECT_NEAR(cross / n / (o.camera_position_noise_sigma_m * o.camera_position_noise_sigma_m), 0.0, 0.05);
}

TEST(PoseEstimate, NoErrorGivesTheTruthAndTheSameSeedTheSameEstimates) {
  PoseEstimator perfect(PoseErrorOptions::none(), GaitOptions{}, 3);
  const ElevationMap map;
  const TrunkState t = truth_at(0.4, 0.02);
  const TrunkPose e = perfect.estimate(t, map);
  EXPECT_EQ(e.x_m, t.pose.x_m);
  EXPECT_EQ(e.pitch_rad, t.pose.pitch_rad);
  EXPECT_EQ(e.reference_elevation_m, t.pose.reference_elevation_m);
  EXPECT_EQ(e.height_change_m, t.pose.height_change_m);

  PoseEstimator a(PoseErrorOptions{}, GaitOptions{}, 11), b(PoseErrorOptions{}, GaitOptions{}, 11);
  for (int k = 0; k < 5; ++k) {
    const TrunkPose ea = a.estimate(truth_at(0.01 * k), map), eb = b.estimate(truth_at(0.01 * k), map);
    EXPECT_EQ(ea.x_m, eb.x_m);
    EXPECT_EQ(ea.roll_rad, eb.roll_rad);
  }
}

TEST(PoseEstimate, ReferenceElevationIsReadFromTheMapAtTheFeet) {
  PoseErrorOptions o = PoseErrorOptions{}.scaled(0.0);
  o.reference = ReferenceElevationSource::map;
  const GaitOptions gait;
  PoseEstimator estimator(o, gait, 1);
  ElevationMap map(GridOptions{100, 0.01});
  map.move_to(0.0, 0.0);
  TrunkState t = truth_at(0.0, 0.004);
  t.pose.yaw_rad = 0.0;
  t.pose.y_m = 0.0;
  // Nothing known yet: h_ref stays the true ground of the first scan.
  EXPECT_NEAR(estimator.estimate(t, map).reference_elevation_m, 0.004, 1e-12);
  EXPECT_EQ(estimator.feet_read_from_map(), 0);
  const auto set_foot = [&](const Eigen::Vector2d& f, float h) {
    for (int dx = -1; dx <= 1; ++dx) {
      for (int dy = -1; dy <= 1; ++dy) {
        const std::size_t s = map.slot(map.cell_of(f.x() + 0.01 * dx, f.y() + 0.01 * dy));
        map.elevation_data()[s] = h;
        map.certainty_data()[s] = 3.0f;
        map.state_data()[s] = static_cast<std::uint8_t>(CellState::measured);
      }
    }
  };
  const auto feet = foot_positions(gait, 0.0, 0.0, 0.0);  // left front, middle, rear, then right
  // Two known feet do not determine the ground: h_ref stays.
  set_foot(feet[0], 0.05f);
  set_foot(feet[1], 0.05f);
  EXPECT_NEAR(estimator.estimate(t, map).reference_elevation_m, 0.004, 1e-12);
  EXPECT_EQ(estimator.feet_read_from_map(), 2);
  // Three and more: their mean, the unknown feet having no say.
  set_foot(feet[2], 0.05f);
  EXPECT_NEAR(estimator.estimate(t, map).reference_elevation_m, 0.05, 1e-6);
  set_foot(feet[3], 0.02f);
  set_foot(feet[4], 0.02f);
  set_foot(feet[5], 0.02f);
  EXPECT_NEAR(estimator.estimate(t, map).reference_elevation_m, 0.035, 1e-6);
  EXPECT_EQ(estimator.feet_read_from_map(), 6);
  // One stray high cell under a foot does not move it (the median).
  map.elevation_data()[map.slot(map.cell_of(feet[5].x(), feet[5].y()))] = 0.5f;
  EXPECT_NEAR(estimator.estimate(t, map).reference_elevation_m, 0.035, 1e-6);
}

TEST(PoseEstimate, BadOptionsNameTheField) {
  PoseErrorOptions o;
  o.camera_yaw_noise_sigma_rad = -0.01;
  try {
    PoseEstimator(o, GaitOptions{}, 1);
    FAIL() << "a negative sigma was accepted";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("camera_yaw_noise_sigma_rad"), std::string::npos) << e.what();
  }
  o = PoseErrorOptions{};
  o.imu_roll_bias_rad = INFINITY;
  EXPECT_THROW(o.validate(), InputError);
  EXPECT_THROW(PoseErrorOptions{}.scaled(-1.0), InputError);
  const PoseErrorOptions doubled = PoseErrorOptions{}.scaled(2.0);
  EXPECT_DOUBLE_EQ(doubled.leg_height_noise_sigma_m, 2 * PoseErrorOptions{}.leg_height_noise_sigma_m);
  EXPECT_DOUBLE_EQ(doubled.imu_pitch_bias_rad, 2 * PoseErrorOptions{}.imu_pitch_bias_rad);
  EXPECT_EQ(doubled.reference, ReferenceElevationSource::map);
}

TEST(PoseEstimate, MapFusedReadsTheFusedLayerAndTakesOffACalibratedBias) {
  PoseErrorOptions o = PoseErrorOptions{}.scaled(0.0);
  o.imu_pitch_bias_rad = 0.01;
  o.reference = ReferenceElevationSource::map_fused;
  const GaitOptions gait;
  PoseEstimator estimator(o, gait, 1);
  ElevationMap map(GridOptions{100, 0.01});
  map.move_to(0.0, 0.0);
  TrunkState t = truth_at(0.0, 0.0);
  t.pose.yaw_rad = 0.0;
  t.pose.y_m = 0.0;
  // Without the layer the source cannot work: said so, naming the layers there are.
  try {
    estimator.estimate(t, map);
    FAIL() << "map-fused read a map without its layer";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("fused_elevation"), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find("mean_elevation"), std::string::npos) << e.what();
  }
  const HeightFusion fusion(map);
  // Eq. (10)'s layer says 0.05 under every foot, the fused layer 0.01: the
  // fused one is read, whatever eq. (9) made of the cells.
  for (const Eigen::Vector2d& f : foot_positions(gait, 0.0, 0.0, 0.0)) {
    const std::size_t s = map.slot(map.cell_of(f.x(), f.y()));
    map.elevation_data()[s] = 0.05f;
    map.state_data()[s] = static_cast<std::uint8_t>(CellState::measured);
    map.data(fusion.elevation_layer())[s] = 0.01f;
  }
  EXPECT_NEAR(estimator.estimate(t, map).pitch_rad, t.pose.pitch_rad + 0.01, 1e-12);
  estimator.set_attitude_correction(0.008, -0.002);
  const TrunkPose e = estimator.estimate(t, map);
  EXPECT_NEAR(e.reference_elevation_m, 0.01, 1e-6);
  EXPECT_EQ(estimator.feet_read_from_map(), 6);
  EXPECT_NEAR(e.pitch_rad, t.pose.pitch_rad + 0.002, 1e-12);
  EXPECT_NEAR(e.roll_rad, t.pose.roll_rad + 0.002, 1e-12);
}

// A 4 x 2 m terrain sampled every `resolution_m`, its height a function of x.
template <typename HeightOfX>
Scene terrain_along_x(double resolution_m, HeightOfX height_m) {
  Scene scene;
  scene.terrain.resolution_m = resolution_m;
  scene.terrain.nx = static_cast<int>(std::lround(4.0 / resolution_m)) + 1;
  scene.terrain.ny = static_cast<int>(std::lround(2.0 / resolution_m)) + 1;
  scene.terrain.max_x_m = scene.terrain.min_x_m + (scene.terrain.nx - 1) * resolution_m;
  scene.terrain.max_y_m = scene.terrain.min_y_m + (scene.terrain.ny - 1) * resolution_m;
  for (int j = 0; j < scene.terrain.ny; ++j)
    for (int i = 0; i < scene.terrain.nx; ++i)
      scene.terrain.samples.push_back(static_cast<float>(height_m(scene.terrain.min_x_m + i * resolution_m)));
  return scene;
}

// A ramp rising 0.1 m per metre along +X.
Scene ramp_scene() {
  return terrain_along_x(0.05, [](double x) { return 0.1 * x; });
}

// One metre straight ahead from x = 0.5 m.
WalkPath straight_path(double start_x_m = 0.5, double length_m = 1.0) {
  WalkPath path;
  path.start_x_m = start_x_m;
  path.segments.push_back({WalkSegment::Kind::straight, length_m, 0.0, 0.0});
  return path;
}

// A 4 x 4 m map centred at (centre_x_m, 0) whose fused layer knows the
// scene everywhere, offset_m too high, with this variance (NaN: the
// variance layer left unknown).
ElevationMap fused_map_of(const Scene& scene, double centre_x_m, double offset_m, float variance_m2) {
  ElevationMap map(GridOptions{400, 0.01});
  map.move_to(centre_x_m, 0.0);
  const HeightFusion fusion(map);
  for (int i = 0; i < 400; ++i) {
    for (int j = 0; j < 400; ++j) {
      const CellIndex c = map.cell_at_local(i, j);
      const Eigen::Vector2d centre = map.cell_center(c);
      map.data(fusion.elevation_layer())[map.slot(c)] =
          static_cast<float>(scene.surface_height_at(centre.x(), centre.y()) + offset_m);
      if (!std::isnan(variance_m2)) map.data(fusion.variance_layer())[map.slot(c)] = variance_m2;
    }
  }
  return map;
}

// The estimate's trunk height (h_ref + d_z) less the truth's.
double height_error_m(const TrunkPose& estimate, const TrunkState& truth) {
  return estimate.reference_elevation_m + estimate.height_change_m -
         (truth.pose.reference_elevation_m + truth.pose.height_change_m);
}

// The `legs` reference: the trunk stands on its stance feet by the leg
// kinematics, and a landing foot's height comes from the feet still standing
// (every switch has a scan in double support at 10 Hz), so without errors the
// odometry climbs the ramp exactly; trusting the map, it stands on the map.
TEST(PoseEstimate, LegsCarryTheTrunkOnItsStanceFeet) {
  const Scene ramp = ramp_scene();
  const GaitOptions gait;
  const TrunkMotion motion(ramp, straight_path(), gait);
  const auto walk = [&](double map_sigma_m, float map_offset_m) {
    PoseErrorOptions o = PoseErrorOptions{}.scaled(0.0);
    o.reference = ReferenceElevationSource::legs;
    o.foothold_map_sigma_m = map_sigma_m;
    PoseEstimator estimator(o, gait, 1);
    const ElevationMap map = fused_map_of(ramp, 1.5, map_offset_m, NAN);
    double worst = 0.0;
    for (double t = 0.0; t <= motion.duration_s(); t += 0.1) {
      const TrunkState truth = motion.at(t);
      worst = std::max(worst, std::abs(height_error_m(estimator.estimate(truth, map), truth)));
    }
    return worst;
  };
  // The odometry alone, a map 2 cm too high all but ignored.
  EXPECT_LT(walk(1e6, 0.02f), 1e-6);
  // Trusting the map: the trunk stands on the map's footholds, 2 cm high.
  const double trusting = walk(0.0, 0.02f);
  EXPECT_GT(trusting, 0.018);
  EXPECT_LT(trusting, 0.022);
  // Without the fused layer the source cannot work.
  PoseErrorOptions o = PoseErrorOptions{}.scaled(0.0);
  o.reference = ReferenceElevationSource::legs;
  PoseEstimator estimator(o, gait, 1);
  try {
    estimator.estimate(motion.at(0.0), ElevationMap(GridOptions{100, 0.01}));
    FAIL() << "legs read a map without the fused layer";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("legs needs"), std::string::npos) << e.what();
  }
  o.foothold_map_sigma_m = -1.0;
  EXPECT_THROW(o.validate(), InputError);
}


// A map that knows nothing under the feet (structured light's stripe leaves
// them on unknown cells for seconds): with foothold odometry the trunk climbs
// the ramp on its legs; without it the height of the start stays while the
// ground rises 10 cm.
TEST(PoseEstimate, MapFootholdsClimbsOnItsLegsWhereTheMapKnowsNothing) {
  const Scene ramp = ramp_scene();
  const GaitOptions gait;
  const TrunkMotion motion(ramp, straight_path(), gait);
  ElevationMap map(GridOptions{100, 0.01});
  const HeightFusion fusion(map);  // both layers unknown everywhere
  const auto worst_error = [&](bool odometry) {
    PoseErrorOptions o = PoseErrorOptions{}.scaled(0.0);
    o.reference = ReferenceElevationSource::map_footholds;
    o.foothold_odometry = odometry;
    PoseEstimator estimator(o, gait, 1);
    double worst = 0.0;
    for (double t = 0.0; t <= motion.duration_s(); t += 0.1) {
      const TrunkState truth = motion.at(t);
      const TrunkPose e = estimator.estimate(truth, map);
      EXPECT_EQ(estimator.feet_read_from_map(), 0);
      worst = std::max(worst, std::abs(height_error_m(e, truth)));
    }
    return worst;
  };
  EXPECT_LT(worst_error(true), 1e-6);
  EXPECT_GT(worst_error(false), 0.08);
}

// The error by cause adds up to the error, scan by scan; a map 5 mm too high
// shows as the map's part once the feet stand on it.
TEST(PoseEstimate, MapFootholdsSplitsItsErrorByCause) {
  const Scene ramp = ramp_scene();
  const GaitOptions gait;
  const TrunkMotion motion(ramp, straight_path(), gait);
  const ElevationMap map = fused_map_of(ramp, 1.5, 0.005, 0.001f * 0.001f);
  PoseErrorOptions o;  // the default errors
  o.reference = ReferenceElevationSource::map_footholds;
  o.foothold_odometry = true;
  PoseEstimator estimator(o, gait, 7);
  double map_part = 0.0;
  int scans = 0;
  for (double t = 0.0; t <= motion.duration_s(); t += 0.1, ++scans) {
    const TrunkState truth = motion.at(t);
    const double error = height_error_m(estimator.estimate(truth, map), truth);
    const HeightReferenceError& split = estimator.last_height_error();
    EXPECT_NEAR(split.error_m, error, 1e-9);
    EXPECT_NEAR(split.odometry_m + split.map_m + split.placement_m + split.kinematics_m, error, 1e-9);
    EXPECT_EQ(split.feet_read, estimator.feet_read_from_map());
    map_part += split.map_m;
  }
  // The ramp's 10 % slope under a 2 cm sole moves the median little: most
  // of the 5 mm is the map's.
  EXPECT_GT(map_part / scans, 0.003);
}

// A floor with a 4 cm step up at x = 1 m, sampled every 1 cm.
Scene step_scene() {
  return terrain_along_x(0.01, [](double x) { return x >= 1.0 ? 0.04 : 0.0; });
}

// The `map_footholds` reference reads the map where the stance feet stand
// (the kinematics place them), not at their nominal places around the trunk:
// walking over a step with a perfect map and no pose error, it gives the
// trunk's true height, where `map_fused` (the nominal places) is off by a
// sixth of the step whenever a foot has landed beyond the step while its
// nominal place is still before it, or the reverse.
TEST(PoseEstimate, MapFootholdsReadsTheMapWhereTheFeetLanded) {
  const Scene step = step_scene();
  const GaitOptions gait;
  const TrunkMotion motion(step, straight_path(0.3, 1.2), gait);
  const ElevationMap map = fused_map_of(step, 1.0, 0.0, 0.0015f * 0.0015f);
  const auto worst_error = [&](ReferenceElevationSource source) {
    PoseErrorOptions o = PoseErrorOptions{}.scaled(0.0);
    o.reference = source;
    PoseEstimator estimator(o, gait, 1);
    double worst = 0.0;
    for (double t = 0.0; t <= motion.duration_s(); t += 0.1) {
      const TrunkState truth = motion.at(t);
      worst = std::max(worst, std::abs(height_error_m(estimator.estimate(truth, map), truth)));
    }
    return worst;
  };
  const double footholds = worst_error(ReferenceElevationSource::map_footholds);
  const double nominal = worst_error(ReferenceElevationSource::map_fused);
  EXPECT_LT(footholds, 0.001);
  EXPECT_GT(nominal, 0.005);

  // Without the variance layer the source cannot work: said so.
  ElevationMap bare(GridOptions{100, 0.01});
  bare.add_layer(fused_elevation_layer());
  PoseErrorOptions o = PoseErrorOptions{}.scaled(0.0);
  o.reference = ReferenceElevationSource::map_footholds;
  PoseEstimator estimator(o, gait, 1);
  try {
    estimator.estimate(motion.at(0.0), bare);
    FAIL() << "map-footholds read a map without the fused_variance layer";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("fused_variance"), std::string::npos) << e.what();
  }
  o.foothold_gate_sigmas = 0.0;
  EXPECT_THROW(o.validate(), InputError);
}


// A sole mostly on unknown cells (a shadow behind a rock, say) has no say in
// map_footholds, even when the few cells known there are high and no gate
// would stop them; nor does a foot in swing.
TEST(PoseEstimate, MapFootholdsIgnoresASoleInAShadowAndASwingingFoot) {
  const GaitOptions gait;
  ElevationMap map(GridOptions{100, 0.01});
  map.move_to(0.0, 0.0);
  const HeightFusion fusion(map);
  for (int i = 0; i < 100; ++i) {
    for (int j = 0; j < 100; ++j) {
      const std::size_t s = map.slot(map.cell_at_local(i, j));
      map.data(fusion.elevation_layer())[s] = 0.0f;
      map.data(fusion.variance_layer())[s] = 0.0015f * 0.0015f;
    }
  }
  TrunkState t = truth_at(0.0, 0.0);
  t.pose = TrunkPose{};
  t.pose.height_change_m = 0.1;  // the trunk 10 cm above flat ground
  const auto feet = foot_positions(gait, 0.0, 0.0, 0.0);
  for (std::size_t f = 0; f < 6; ++f) t.feet[f] = {Eigen::Vector3d(feet[f].x(), feet[f].y(), 0.0), true};
  // Under the left front foot only the cell at its centre is known, 5 cm high.
  for (int dx = -2; dx <= 2; ++dx) {
    for (int dy = -2; dy <= 2; ++dy) {
      const std::size_t s = map.slot(map.cell_of(feet[0].x() + 0.01 * dx, feet[0].y() + 0.01 * dy));
      map.data(fusion.elevation_layer())[s] = (dx == 0 && dy == 0) ? 0.05f : NAN;
    }
  }
  // Under the right rear foot, swinging, the ground is 5 cm high everywhere.
  t.feet[5].in_stance = false;
  for (int dx = -2; dx <= 2; ++dx) {
    for (int dy = -2; dy <= 2; ++dy) {
      map.data(fusion.elevation_layer())[map.slot(map.cell_of(feet[5].x() + 0.01 * dx, feet[5].y() + 0.01 * dy))] = 0.05f;
    }
  }
  PoseErrorOptions o = PoseErrorOptions{}.scaled(0.0);
  o.reference = ReferenceElevationSource::map_footholds;
  o.foothold_gate_sigmas = 1e9;  // no gate: the share of known cells alone decides
  PoseEstimator estimator(o, gait, 1);
  const TrunkPose e = estimator.estimate(t, map);
  EXPECT_EQ(estimator.feet_read_from_map(), 4);
  EXPECT_NEAR(e.reference_elevation_m, 0.0, 1e-6);
}

}  // namespace
}  // namespace pose_estimate_test
}  // namespace stridemap
