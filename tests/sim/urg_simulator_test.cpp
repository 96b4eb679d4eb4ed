#include "stridemap/sim/urg_simulator.hpp"

#include <atomic>
#include <cmath>
#include <cstdlib>
#include <new>
#include <limits>
#include <memory>
#include <numbers>
#include <vector>

#include <Eigen/Geometry>
#include <gtest/gtest.h>

#include "allocation_counting.hpp"

#include "stridemap/core/error.hpp"
#include "stridemap/core/sensor_transform.hpp"
#include "stridemap/sensors/range_calibration.hpp"

// Counts heap allocations, to show that a scan allocates nothing once its
// buffers have grown. Replacing the global operator new only counts; every
// allocation of this test program still goes to malloc.
namespace {
std::atomic<std::size_t> heap_allocations{0};
}  // namespace

#if STRIDEMAP_ALLOCATION_COUNTING
void* operator new(std::size_t size) {
  ++heap_allocations;
  if (void* memory = std::malloc(size == 0 ? 1 : size)) return memory;
  throw std::bad_alloc();
}
void operator delete(void* memory) noexcept { std::free(memory); }
void operator delete(void* memory, std::size_t) noexcept { std::free(memory); }
#endif

namespace stridemap {
namespace urg_simulator_test {
namespace {

const double alpha = 35.0 * std::numbers::pi / 180.0;  // the default mount's pitch

Scene floor_scene(double reflectance = 0.5) {
  Scene scene;
  scene.terrain.reflectance = reflectance;
  return scene;
}

UrgSimOptions ideal_options() {
  UrgSimOptions options;
  options.enable_noise = false;
  options.enable_systematic_error = false;
  options.enable_dropouts = false;
  options.receiver.enabled = false;  // the lagging gain control shifts readings at grazing incidence
  return options;
}

// From the default mount (0.26 m, 35 deg) at the origin, beam angle t meets
// the floor at 0.26 / (cos t sin alpha), at incidence cos = cos t sin alpha.
double floor_range_m(double t) { return 0.26 / (std::cos(t) * std::sin(alpha)); }
double floor_amplitude(double t, double reflectance) {
  const double r = floor_range_m(t);
  return reflectance * std::cos(t) * std::sin(alpha) / (r * r);
}

TEST(UrgSimulator, BeamGeometryFollowsTheParameters) {
  const UrgParameters params;
  UrgSimulator sim(floor_scene(), params, ideal_options(), 1);
  UrgRawScan scan;
  std::vector<BeamLabel> labels;
  sim.scan(TrunkPose{}, SensorMount{}, 2.5, scan, &labels);
  ASSERT_EQ(scan.values_mm.size(), 682u);
  ASSERT_EQ(labels.size(), 682u);
  EXPECT_EQ(scan.first_step, 44);
  EXPECT_EQ(scan.cluster, 1);
  EXPECT_EQ(scan.time_s, 2.5);
  EXPECT_EQ(scan.values_mm[384 - 44], 453u);        // straight ahead: 0.26 / sin 35 deg
  EXPECT_EQ(scan.values_mm[384 + 128 - 44], 641u);  // 45 deg left
  EXPECT_EQ(scan.values_mm[384 - 128 - 44], 641u);  // 45 deg right
  int returns = 0;
  for (int i = 0; i < params.beam_count(); ++i) {
    const double t = params.step_angle_rad(params.first_step + i);
    std::uint32_t expected = urg_code_no_return;  // upwards, or beyond DMAX
    if (std::cos(t) > 0.0 && floor_range_m(t) <= params.max_range_m - 0.001) {
      expected = static_cast<std::uint32_t>(std::lround(floor_range_m(t) * 1000.0));
    }
    if (std::cos(t) > 0.0 && std::abs(floor_range_m(t) - params.max_range_m) < 0.001) continue;  // rounding edge
    EXPECT_EQ(scan.values_mm[i], expected) << "beam " << i << " at " << t << " rad";
    EXPECT_EQ(labels[i], expected == urg_code_no_return ? BeamLabel::dropped : BeamLabel::clean);
    returns += expected != urg_code_no_return;
  }
  EXPECT_GT(returns, 400);
}

TEST(UrgSimulator, TheSensorModelPutsIdealReadingsBackOnTheSurfaces) {
  // Simulator and sensor model must agree on beam angles and frames: with
  // the errors off, every reading converted by UrgModel and eq. (5) lands on
  // the surface the simulator saw, up to the 1 mm rounding.
  Scene scene = floor_scene();
  BoxObject box;
  box.name = "box";
  box.center_x_m = 0.9;
  box.center_y_m = 0.15;
  box.length_m = 0.2;
  box.width_m = 0.3;
  box.height_m = 0.1;
  box.yaw_rad = 0.4;
  scene.boxes.push_back(box);
  UrgSimulator sim(scene, UrgParameters{}, ideal_options(), 1);
  const UrgModel model;
  TrunkPose pose;
  pose.x_m = 0.55;
  pose.y_m = -0.05;
  pose.yaw_rad = 0.2;
  pose.pitch_rad = 0.05;
  pose.roll_rad = -0.04;
  const SensorMount mount;
  UrgRawScan raw;
  PlanarScan scan;
  sim.scan(pose, mount, 0.0, raw);
  model.to_planar_scan(raw, scan);
  const Eigen::Vector3d origin = sensor_origin_in_map(pose, mount);
  int on_box = 0, checked = 0;
  for (std::size_t i = 0; i < scan.size(); ++i) {
    if (!std::isfinite(scan.range_m[i])) continue;
    const Eigen::Vector3d in_sensor(scan.range_m[i] * std::cos(scan.angle_rad[i]),
                                    scan.range_m[i] * std::sin(scan.angle_rad[i]), 0.0);
    const Eigen::Vector3d point = sensor_point_to_map(in_sensor, pose, mount);
    const auto hit = scene.cast_ray(origin, (point - origin).normalized(), 10.0);
    ASSERT_TRUE(hit) << "beam " << i;
    EXPECT_NEAR(hit->range_m, scan.range_m[i], 0.0005 + 1e-9) << "beam " << i;
    on_box += hit->object_index == 0;
    ++checked;
  }
  EXPECT_GT(checked, 400);
  EXPECT_GT(on_box, 20);
}

TEST(UrgSimulator, ABoxInFrontShortensTheBeam) {
  Scene scene = floor_scene();
  BoxObject box;
  box.name = "box";
  box.center_x_m = 0.4;
  box.length_m = 0.2;
  box.width_m = 0.3;
  box.height_m = 0.1;
  scene.boxes.push_back(box);
  UrgSimulator sim(scene, UrgParameters{}, ideal_options(), 1);
  UrgRawScan scan;
  sim.scan(TrunkPose{}, SensorMount{}, 0.0, scan);
  // The centre beam is 0.05 m high at x = 0.3: it meets the front face.
  EXPECT_EQ(scan.values_mm[384 - 44], static_cast<std::uint32_t>(std::lround(300.0 / std::cos(alpha))));
  // Moving the cart 1 m ahead leaves the box behind: the floor again.
  TrunkPose ahead;
  ahead.x_m = 1.0;
  sim.scan(ahead, SensorMount{}, 0.1, scan);
  EXPECT_EQ(scan.values_mm[384 - 44], 453u);
}

TEST(UrgSimulator, WeakReturnsBecomeErrorCodeOne) {
  const UrgParameters params;
  UrgSimOptions options = ideal_options();
  options.enable_dropouts = true;
  UrgSimulator sim(floor_scene(), params, options, 1);
  UrgRawScan scan;
  std::vector<BeamLabel> labels;
  sim.scan(TrunkPose{}, SensorMount{}, 0.0, scan, &labels);
  int weak = 0;
  for (int i = 0; i < params.beam_count(); ++i) {
    const double t = params.step_angle_rad(params.first_step + i);
    if (std::cos(t) <= 0.0 || floor_range_m(t) > 5.7) continue;
    const double amplitude = floor_amplitude(t, 0.5);
    if (std::abs(amplitude - options.dropout_amplitude_threshold) < 1e-4) continue;
    if (amplitude < options.dropout_amplitude_threshold) {
      EXPECT_EQ(scan.values_mm[i], urg_code_weak_return) << "beam " << i;
      EXPECT_EQ(labels[i], BeamLabel::dropped);
      ++weak;
    } else {
      EXPECT_GE(scan.values_mm[i], 20u) << "beam " << i;
    }
  }
  EXPECT_GT(weak, 20);  // the floor far out to both sides, beyond about 76 deg
}

TEST(UrgSimulator, SystematicErrorFollowsTheCubic) {
  UrgSimOptions options = ideal_options();
  options.enable_systematic_error = true;
  UrgSimulator sim(floor_scene(), UrgParameters{}, options, 1);
  UrgRawScan scan;
  sim.scan(TrunkPose{}, SensorMount{}, 0.0, scan);
  const auto& c = options.systematic_error_coefficients;
  for (int step : {384, 384 + 100, 384 - 170}) {
    const double t = (step - 384) * 2.0 * std::numbers::pi / 1024.0;
    const double r = floor_range_m(t);
    const double expected = r + c[0] + c[1] * r + c[2] * r * r + c[3] * r * r * r;
    EXPECT_EQ(scan.values_mm[step - 44], static_cast<std::uint32_t>(std::lround(expected * 1000.0))) << step;
  }
}

TEST(UrgSimulator, DefaultSystematicErrorIsInsideTheSpecAndCalibrationRecoversIt) {
  const UrgSimOptions options;
  UrgSimulator sim(floor_scene(), UrgParameters{}, options, 1);
  std::vector<double> measured, truth;
  for (double r = 0.02; r <= 5.6; r += 0.01) {
    const double envelope = r <= 1.0 ? 0.010 : 0.01 * r;
    EXPECT_LE(std::abs(sim.systematic_error_m(r)), 0.6 * envelope) << r;
  }
  for (double r = 0.05; r <= 4.0; r += 0.05) {
    truth.push_back(r);
    measured.push_back(r + sim.systematic_error_m(r));
  }
  const RangeCalibrationFit fit = fit_range_calibration(measured, truth);
  EXPECT_LT(fit.rms_residual_m, 5e-5);
  for (double r = 0.1; r <= 4.0; r += 0.1) {
    EXPECT_NEAR(fit.calibration.corrected_m(r + sim.systematic_error_m(r)), r, 1e-4) << r;
  }
}

TEST(UrgSimulator, SameSeedSameScansWhateverCameBefore) {
  UrgSimulator a(floor_scene(), UrgParameters{}, UrgSimOptions{}, 77);
  UrgSimulator b(floor_scene(), UrgParameters{}, UrgSimOptions{}, 77);
  UrgSimulator other_seed(floor_scene(), UrgParameters{}, UrgSimOptions{}, 78);
  std::vector<TrunkPose> poses(3);
  poses[1].x_m = 0.01;
  poses[2].x_m = 0.02;
  poses[2].yaw_rad = 0.1;
  UrgRawScan scan_a, scan_b, scan_other;
  for (const TrunkPose& pose : poses) {
    a.scan(pose, SensorMount{}, 0.0, scan_a);
    b.scan(pose, SensorMount{}, 0.0, scan_b);
    other_seed.scan(pose, SensorMount{}, 0.0, scan_other);
    EXPECT_EQ(scan_a.values_mm, scan_b.values_mm);
    EXPECT_NE(scan_a.values_mm, scan_other.values_mm);
  }
  // Scan 2 depends on the seed and its index, not on what scans 0 and 1 saw.
  UrgSimulator c(floor_scene(), UrgParameters{}, UrgSimOptions{}, 77);
  TrunkPose elsewhere;
  elsewhere.x_m = 3.0;
  c.scan(elsewhere, SensorMount{}, 0.0, scan_b);
  c.scan(elsewhere, SensorMount{}, 0.0, scan_b);
  c.scan(poses[2], SensorMount{}, 0.0, scan_b);
  EXPECT_EQ(scan_a.values_mm, scan_b.values_mm);
  EXPECT_EQ(c.scans_simulated(), 3u);
  // reset() starts the sequence again.
  c.reset(77);
  a.reset(77);
  a.scan(poses[1], SensorMount{}, 0.0, scan_a);
  c.scan(poses[1], SensorMount{}, 0.0, scan_b);
  EXPECT_EQ(scan_a.values_mm, scan_b.values_mm);
}

// Range errors of the beams within +/-20 steps of straight ahead over many
// scans, with the systematic error off.
void noise_statistics(double reflectance, double& mean_m, double& sigma_m) {
  UrgSimOptions options;
  options.enable_systematic_error = false;
  UrgSimulator sim(floor_scene(reflectance), UrgParameters{}, options, 2024);
  UrgRawScan scan;
  double sum = 0.0, sum_sq = 0.0;
  int count = 0;
  for (int k = 0; k < 100; ++k) {
    sim.scan(TrunkPose{}, SensorMount{}, 0.1 * k, scan);
    for (int step = 384 - 20; step <= 384 + 20; ++step) {
      const double t = (step - 384) * 2.0 * std::numbers::pi / 1024.0;
      const double error = scan.values_mm[step - 44] / 1000.0 - floor_range_m(t);
      sum += error;
      sum_sq += error * error;
      ++count;
    }
  }
  mean_m = sum / count;
  sigma_m = std::sqrt(sum_sq / count - mean_m * mean_m);
}

TEST(UrgSimulator, NoiseGrowsAsTheReturnWeakens) {
  double mean = 0.0, sigma = 0.0;
  // Grey floor straight ahead: amplitude about 1.4, above the reference, so
  // the base sigma of 3 mm (plus 0.3 mm of rounding).
  noise_statistics(0.5, mean, sigma);
  EXPECT_NEAR(mean, 0.0, 0.0003);
  EXPECT_GT(sigma, 0.00285);
  EXPECT_LT(sigma, 0.00320);
  // Dark floor (0.05): amplitude 0.14, sigma 3 mm * sqrt(1 / 0.14) = 8 mm.
  const double expected = 0.003 * std::sqrt(1.0 / floor_amplitude(0.0, 0.05));
  noise_statistics(0.05, mean, sigma);
  EXPECT_NEAR(mean, 0.0, 0.0008);
  EXPECT_NEAR(sigma, expected, 0.1 * expected);
}

// A beam model that records what it is asked and answers with a fixed echo,
// labelling every third beam mixed.
class ScriptedBeamModel final : public BeamModel {
 public:
  explicit ScriptedBeamModel(BeamEcho echo, std::vector<BeamRequest>* requests)
      : echo_(echo), requests_(requests) {}
  BeamEcho trace(const SceneRayCaster&, const BeamRequest& beam, std::mt19937_64&) override {
    requests_->push_back(beam);
    BeamEcho echo = echo_;
    if (requests_->size() % 3 == 0) echo.label = BeamLabel::mixed;
    return echo;
  }
  BeamLabel label_for_range(double) const override { return BeamLabel::clean; }

 private:
  BeamEcho echo_;
  std::vector<BeamRequest>* requests_;
};

TEST(UrgSimulator, AnotherBeamModelPlugsIn) {
  std::vector<BeamRequest> requests;
  BeamEcho echo;
  echo.has_return = true;
  echo.range_m = 1.2344;
  echo.amplitude = 0.5;
  UrgSimulator sim(floor_scene(), UrgParameters{}, ideal_options(), 1,
                   std::make_unique<ScriptedBeamModel>(echo, &requests));
  UrgRawScan scan;
  std::vector<BeamLabel> labels;
  TrunkPose pose;
  pose.yaw_rad = 0.3;
  sim.scan(pose, SensorMount{}, 0.0, scan, &labels);
  ASSERT_EQ(requests.size(), 682u);
  for (std::size_t i = 0; i < requests.size(); ++i) {
    const BeamRequest& beam = requests[i];
    EXPECT_NEAR(beam.direction.norm(), 1.0, 1e-12);
    EXPECT_NEAR(beam.direction.dot(beam.sweep_axis), 0.0, 1e-12);
    EXPECT_TRUE(beam.direction.cross(beam.sweep_axis).isApprox(beam.plane_normal, 1e-12));
    EXPECT_NEAR(beam.origin_m.z(), 0.26, 1e-12);
    EXPECT_NEAR(beam.step_angle_rad, 2.0 * std::numbers::pi / 1024.0, 1e-15);
    EXPECT_GE(beam.max_range_m, 5.6);
    if (i + 1 < requests.size()) {  // the sweep axis points towards the next beam
      EXPECT_GT((requests[i + 1].direction - beam.direction).dot(beam.sweep_axis), 0.0);
    }
    EXPECT_EQ(scan.values_mm[i], 1234u);
    EXPECT_EQ(labels[i], (i + 1) % 3 == 0 ? BeamLabel::mixed : BeamLabel::clean);
  }
  // A code decided by the model passes through, labelled dropped.
  requests.clear();
  echo.sensor_error_code = 8;
  UrgSimulator coded(floor_scene(), UrgParameters{}, ideal_options(), 1,
                     std::make_unique<ScriptedBeamModel>(echo, &requests));
  coded.scan(pose, SensorMount{}, 0.0, scan, &labels);
  EXPECT_EQ(scan.values_mm[0], 8u);
  EXPECT_EQ(labels[0], BeamLabel::dropped);
  echo.sensor_error_code = 25;
  UrgSimulator wrong(floor_scene(), UrgParameters{}, ideal_options(), 1,
                     std::make_unique<ScriptedBeamModel>(echo, &requests));
  EXPECT_THROW(wrong.scan(pose, SensorMount{}, 0.0, scan, &labels), InputError);
}

TEST(UrgSimulator, AScanAllocatesNothingOnceBuffersHaveGrown) {
  STRIDEMAP_SKIP_UNLESS_COUNTING_ALLOCATIONS();
  Scene scene = floor_scene();
  ProceduralTerrainOptions rocky;
  rocky.amplitude_m = 0.05;
  scene.terrain = make_procedural_height_field(rocky, 3);
  BoxObject box;
  box.name = "box";
  box.center_x_m = 0.5;
  box.length_m = box.width_m = box.height_m = 0.1;
  scene.boxes.push_back(box);
  UrgSimulator sim(scene, UrgParameters{}, UrgSimOptions{}, 1);
  UrgRawScan scan;
  std::vector<BeamLabel> labels;
  TrunkPose pose;
  sim.scan(pose, SensorMount{}, 0.0, scan, &labels);
  const std::size_t before = heap_allocations.load();
  for (int k = 0; k < 10; ++k) {
    pose.x_m += 0.01;
    sim.scan(pose, SensorMount{}, 0.1 * k, scan, &labels);
  }
  EXPECT_EQ(heap_allocations.load() - before, 0u);
  EXPECT_GT(before, 0u);  // the counter does count
}

TEST(UrgSimulator, RejectsBadInput) {
  UrgSimulator sim(floor_scene(), UrgParameters{}, UrgSimOptions{}, 1);
  UrgRawScan scan;
  TrunkPose pose;
  pose.pitch_rad = std::numeric_limits<double>::quiet_NaN();
  EXPECT_THROW(sim.scan(pose, SensorMount{}, 0.0, scan), InputError);

  UrgSimOptions options;
  options.range_noise_sigma_m = -1.0;
  try {
    UrgSimulator bad(floor_scene(), UrgParameters{}, options, 1);
    FAIL() << "expected InputError";
  } catch (const InputError& error) {
    EXPECT_STREQ(error.what(), "URG simulator options: range_noise_sigma_m: expected a number >= 0, got -1");
  }
  Scene scene = floor_scene();
  scene.terrain.reflectance = 0.0;
  EXPECT_THROW(UrgSimulator(scene, UrgParameters{}, UrgSimOptions{}, 1), InputError);
}

}  // namespace
}  // namespace urg_simulator_test
}  // namespace stridemap
