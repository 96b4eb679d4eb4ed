#pragma once
// What stridemap_urg_bridge reads, without ROS: a URG-04LX (or the
// emulator's pseudo-terminal) through the library's UrgDriver, and a pose
// file written as it grows (the emulator's --poses-out, docs/live.md's
// format) through the recordings layer's PoseStreamReader. C++17 (see
// message_mapper.hpp).
#include <memory>
#include <string>
#include <vector>

#include <Eigen/Geometry>

namespace stridemap::ros_adapter {

/// One scan as LaserScan fields: raw values / 1000 (error codes fall below
/// range_min), beam k at angle_min + k angle_increment.
struct UrgInputScan {
  double stamp_s = 0.0;  ///< host time of step 0 (the driver's estimate)
  double angle_min_rad = 0.0;
  double angle_increment_rad = 0.0;
  double range_min_m = 0.0;
  double range_max_m = 0.0;
  double scan_period_s = 0.1;
  std::vector<float> ranges_m;
};

struct UrgInputPose {
  double stamp_s = 0.0;
  Eigen::Isometry3d trunk_in_map = Eigen::Isometry3d::Identity();
};

class UrgInput {
 public:
  enum class Event { none, scan, connected, fault };
  /// Throws InputError for a config file that does not load. The device is
  /// opened (and reopened after faults) by the driver; the pose file may be
  /// empty ("" = no poses).
  UrgInput(const std::string& device, const std::string& poses_path, const std::string& config_path);
  ~UrgInput();
  /// Runs the driver for at most `timeout_s`: a scan, a (re)connection or a
  /// fault (`message` says what), or none.
  Event next(UrgInputScan& scan, std::string& message, double timeout_s);
  /// The poses written since the last call (the newest of them, as a rigid
  /// trunk pose; the file's paper-model poses are made rigid through the mount).
  std::vector<UrgInputPose> poll_poses();
  /// The config's mount as base_link -> laser.
  Eigen::Isometry3d sensor_on_trunk() const;

 private:
  struct State;
  std::unique_ptr<State> state_;
};

}  // namespace stridemap::ros_adapter
