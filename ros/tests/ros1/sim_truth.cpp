#include "sim_truth.hpp"

#include <algorithm>
#include <cstring>
#include <numbers>

#include "stridemap/config/scene_yaml.hpp"
#include "stridemap/core/exported_map.hpp"
#include "stridemap/core/sensor_transform.hpp"
#include "stridemap/mapfile/map_file.hpp"
#include "stridemap/sensors/structured_light.hpp"
#include "stridemap/sim/motion_source.hpp"
#include "stridemap/sim/structured_light_simulator.hpp"
#include "stridemap/sim/urg_scan_source.hpp"
#include "stridemap/sim/urg_simulator.hpp"

namespace stridemap::ros_test {

namespace {

// The rigid transform that puts the sensor where the library's transform
// (core/sensor_transform.hpp) puts it for `pose`, as the trunk's pose: the
// rail's poses have no z, the paper's model.
Eigen::Isometry3d trunk_in_map(const TrunkPose& pose, const SensorMount& mount, const Eigen::Isometry3d& on_trunk) {
  Eigen::Isometry3d sensor = Eigen::Isometry3d::Identity();
  sensor.linear() = sensor_to_map_rotation(pose, mount);
  sensor.translation() = sensor_origin_in_map(pose, mount);
  return sensor * on_trunk.inverse();
}

}  // namespace

SimulatedRun simulate_cart_rail(const std::string& scene_path, int count, std::uint64_t seed) {
  const Scene scene = load_scene_yaml(scene_path);
  const UrgParameters urg{};
  const SensorMount mount{};
  const CartRailPath rail = scene.cart_rail ? *scene.cart_rail : CartRailPath{0.0, 1.2, 0.0, 0.01, 0.0};
  const CartRailMotion motion(rail, urg.scan_period_s);
  SimulatedScanSource source(std::make_unique<UrgSimulator>(scene, urg, UrgSimOptions{}, seed), motion, mount, seed);

  SimulatedRun run;
  run.angle_min_rad = urg.step_angle_rad(urg.first_step);
  run.angle_increment_rad = urg.step_angle_rad(urg.first_step + 1) - run.angle_min_rad;
  run.range_min_m = urg.min_range_m;
  run.range_max_m = urg.max_range_m;
  run.sensor_on_trunk.linear() = mount_rotation(mount);
  run.sensor_on_trunk.translation() = Eigen::Vector3d(mount.forward_offset_m, mount.lateral_offset_m, mount.height_m);
  std::vector<std::uint32_t> values;
  for (int k = 0; k < count; ++k) {
    SimulatedScan scan;
    // A little past the rail step, so the pose is the rail's k-th, not a boundary.
    scan.time_s = (k + 0.5) * urg.scan_period_s;
    source.scan(static_cast<std::uint64_t>(k), scan.time_s, values);
    for (const std::uint32_t v : values) scan.ranges_m.push_back(static_cast<float>(v) / 1000.0f);
    scan.trunk_in_map = trunk_in_map(motion.pose_at(scan.time_s), mount, run.sensor_on_trunk);
    run.scans.push_back(std::move(scan));
  }
  return run;
}

SimulatedCloudRun simulate_structured_light_rail(const std::string& scene_path, int count, std::uint64_t seed) {
  const Scene scene = load_scene_yaml(scene_path);
  const StructuredLightParameters parameters{};  // Ragno's sensor and mount
  StructuredLightSimOptions geometry;
  constexpr double kRowNoisePx = 0.3;  // a sub-pixel detector's spread (the walk sensor's default)
  geometry.row_noise_sigma_px = kRowNoisePx;
  StructuredLightSimulator simulator(scene, parameters, geometry, seed);
  const StructuredLightModel& model = simulator.model();
  const SensorMount& mount = parameters.mount;
  constexpr double kFramePeriodS = 0.04;
  const CartRailPath rail = scene.cart_rail ? *scene.cart_rail : CartRailPath{0.0, 1.2, 0.0, 0.01, 0.0};
  const CartRailMotion motion(rail, kFramePeriodS);

  SimulatedCloudRun run;
  run.mount_height_m = mount.height_m;
  run.mount_pitch_deg = mount.pitch_rad * 180.0 / std::numbers::pi;
  run.sensor_on_trunk.linear() = mount_rotation(mount);
  run.sensor_on_trunk.translation() = Eigen::Vector3d(mount.forward_offset_m, mount.lateral_offset_m, mount.height_m);
  StructuredLightFrameTruth truth;
  for (int k = 0; k < count; ++k) {
    SimulatedCloud frame;
    frame.time_s = (k + 0.5) * kFramePeriodS;
    const TrunkPose pose = motion.pose_at(frame.time_s);
    simulator.simulate(pose, truth);
    for (const StripePixel& pixel : truth.stripe) {
      CameraPointPartials point;
      if (model.back_project(pixel.u_px, pixel.v_px, point) != StripePointStatus::valid) continue;
      frame.points_m.push_back(camera_to_sensor_frame(point.point));
      // How far the row noise moves the point, a bound on its height's spread.
      frame.height_sigma_m.push_back(std::max(2e-4, kRowNoisePx * point.d_row.norm()));
    }
    frame.trunk_in_map = trunk_in_map(pose, mount, run.sensor_on_trunk);
    run.frames.push_back(std::move(frame));
  }
  return run;
}

struct SceneTruth::Scene {
  stridemap::Scene scene;
};

SceneTruth::SceneTruth(const std::string& scene_path)
    : scene_(std::make_unique<Scene>(Scene{load_scene_yaml(scene_path)})) {}
SceneTruth::~SceneTruth() = default;

double SceneTruth::surface_height_m(double x_m, double y_m) const { return scene_->scene.surface_height_at(x_m, y_m); }

std::string compare_map_files(const std::string& a, const std::string& b) {
  const io::MapFile fa = io::load_map_file(a);
  const io::MapFile fb = io::load_map_file(b);
  const ElevationMap& ma = fa.map;
  const ElevationMap& mb = fb.map;
  if (ma.layer_count() != mb.layer_count()) return "layer counts differ";
  std::vector<std::string> names;
  for (std::size_t k = 0; k < ma.layer_count(); ++k) names.push_back(ma.layer_spec(k).name);
  const ExportedMap ea = export_map(ma, names);
  const ExportedMap eb = export_map(mb, names);
  if (!(ea.min_cell == eb.min_cell) || ea.cells_per_side != eb.cells_per_side || ea.cell_size_m != eb.cell_size_m) {
    return "geometry differs";
  }
  for (std::size_t k = 0; k < ea.layers.size(); ++k) {
    const ExportedLayer& la = ea.layers[k];
    const ExportedLayer& lb = eb.layers[k];
    for (Eigen::Index i = 0; i < ea.cells_per_side; ++i) {
      for (Eigen::Index j = 0; j < ea.cells_per_side; ++j) {
        const float va = la.value(i, j), vb = lb.value(i, j);
        if (std::memcmp(&va, &vb, sizeof va) != 0) {
          return "layer " + la.spec.name + " differs at (" + std::to_string(i) + ", " + std::to_string(j) + "): " +
                 std::to_string(va) + " vs " + std::to_string(vb);
        }
      }
    }
  }
  if (fa.metadata.last_scan_time_s != fb.metadata.last_scan_time_s) return "last scan times differ";
  return "";
}

}  // namespace stridemap::ros_test
