#pragma once
// The simulator's side of the ROS tests, behind a C++17 header (the tests
// include ROS 1's headers, which need C++17; the library is C++20): a
// URG-04LX on the cart rail over a scene, its scans as LaserScan fields and
// its true poses, the scene's surface height, and map files compared.
#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include <Eigen/Geometry>

namespace stridemap::ros_test {

struct SimulatedScan {
  double time_s = 0.0;  ///< since the run started
  std::vector<float> ranges_m;  ///< raw values / 1000: error codes fall below range_min
  Eigen::Isometry3d trunk_in_map = Eigen::Isometry3d::Identity();  ///< true pose
};

struct SimulatedRun {
  double angle_min_rad = 0.0;
  double angle_increment_rad = 0.0;
  double range_min_m = 0.0;
  double range_max_m = 0.0;
  Eigen::Isometry3d sensor_on_trunk = Eigen::Isometry3d::Identity();  ///< the default mount
  std::vector<SimulatedScan> scans;
};

/// `count` scans of the URG on the scene's rail (docs/experiments.md, cart
/// rail), default mount and configuration, seeded.
SimulatedRun simulate_cart_rail(const std::string& scene_path, int count, std::uint64_t seed);

/// One frame of the stripe camera: the detected stripe (the simulator's,
/// with its row noise) back-projected onto the laser sheet, in the sensor
/// frame S (REP-103: x ahead, y left, z up before the mount's pitch).
struct SimulatedCloud {
  double time_s = 0.0;
  std::vector<Eigen::Vector3d> points_m;
  std::vector<double> height_sigma_m;  ///< the row noise's effect on the point
  Eigen::Isometry3d trunk_in_map = Eigen::Isometry3d::Identity();  ///< true pose
};

struct SimulatedCloudRun {
  double mount_height_m = 0.0;
  double mount_pitch_deg = 0.0;
  Eigen::Isometry3d sensor_on_trunk = Eigen::Isometry3d::Identity();  ///< Ragno's mount
  std::vector<SimulatedCloud> frames;
};

/// `count` frames of Ragno's structured-light sensor (camera + laser
/// stripe, docs/structured_light.md) on the scene's rail, one every
/// 40 ms (25 Hz), the stripe's rows with 0.3 px of noise, seeded.
SimulatedCloudRun simulate_structured_light_rail(const std::string& scene_path, int count, std::uint64_t seed);

class SceneTruth {
 public:
  explicit SceneTruth(const std::string& scene_path);
  ~SceneTruth();
  double surface_height_m(double x_m, double y_m) const;

 private:
  struct Scene;
  std::unique_ptr<Scene> scene_;
};

/// "" when the two map files hold the same layers and geometry bit for
/// bit; else what differs.
std::string compare_map_files(const std::string& a, const std::string& b);

}  // namespace stridemap::ros_test
