#include "sim_truth.hpp"

#include <cstring>

#include "stridemap/core/exported_map.hpp"
#include "stridemap/core/sensor_transform.hpp"
#include "stridemap/io/map_file.hpp"
#include "stridemap/io/scene_yaml.hpp"
#include "stridemap/sim/motion_source.hpp"
#include "stridemap/sim/urg_scan_source.hpp"
#include "stridemap/sim/urg_simulator.hpp"

namespace stridemap::ros_test {

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
    // The true trunk pose as a rigid transform that puts the sensor where
    // the simulator put it (the rail's pose has no z: the paper's model).
    const TrunkPose pose = motion.pose_at(scan.time_s);
    Eigen::Isometry3d sensor = Eigen::Isometry3d::Identity();
    sensor.linear() = sensor_to_map_rotation(pose, mount);
    sensor.translation() = sensor_origin_in_map(pose, mount);
    scan.trunk_in_map = sensor * run.sensor_on_trunk.inverse();
    run.scans.push_back(std::move(scan));
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
