#include "stridemap_ros/urg_input.hpp"

#include <numbers>

#include "stridemap/config/mapper_config.hpp"
#include "stridemap/core/pose_track.hpp"
#include "stridemap/core/sensor_transform.hpp"
#include "stridemap/devices/serial_port.hpp"
#include "stridemap/recordings/pose_stream.hpp"
#include "stridemap/sensors/urg_driver.hpp"

namespace stridemap::ros_adapter {

struct UrgInput::State {
  MapperConfig config;
  std::unique_ptr<UrgDriver> driver;
  std::unique_ptr<io::PoseStreamReader> poses;
  PoseTrack track{1e9};
  double last_pose_s = -1e300;
};

UrgInput::UrgInput(const std::string& device, const std::string& poses_path, const std::string& config_path)
    : state_(std::make_unique<State>()) {
  if (!config_path.empty()) state_->config = load_mapper_config(config_path);
  state_->driver = std::make_unique<UrgDriver>(io::SerialPort::opener(device));
  if (!poses_path.empty()) state_->poses = std::make_unique<io::PoseStreamReader>(poses_path);
}

UrgInput::~UrgInput() = default;

UrgInput::Event UrgInput::next(UrgInputScan& scan, std::string& message, double timeout_s) {
  UrgDriverEvent event;
  if (!state_->driver->next(event, timeout_s)) return Event::none;
  if (event.kind == UrgDriverEvent::Kind::fault) {
    message = event.message;
    return Event::fault;
  }
  if (event.kind == UrgDriverEvent::Kind::connected) {
    message = event.message;
    return Event::connected;
  }
  const UrgParameters& p = state_->driver->urg_parameters();
  const UrgRawScan& raw = event.scan.raw;
  const int cluster = std::max(1, raw.cluster);
  // A clustered value stands for its steps' middle direction.
  scan.stamp_s = event.scan.host_time_s;
  scan.angle_min_rad = p.step_angle_rad(raw.first_step + 0.5 * (cluster - 1));
  scan.angle_increment_rad = cluster * 2.0 * std::numbers::pi / p.steps_per_turn;
  scan.range_min_m = p.min_range_m;
  scan.range_max_m = p.max_range_m;
  scan.scan_period_s = p.scan_period_s;
  scan.ranges_m.resize(raw.values_mm.size());
  for (std::size_t k = 0; k < raw.values_mm.size(); ++k) scan.ranges_m[k] = static_cast<float>(raw.values_mm[k]) / 1000.0f;
  return Event::scan;
}

std::vector<UrgInputPose> UrgInput::poll_poses() {
  std::vector<UrgInputPose> out;
  if (!state_->poses || state_->poses->poll(state_->track) == 0 || state_->track.empty()) return out;
  const double t = state_->track.last_time_s();
  TrunkPose pose;
  if (t <= state_->last_pose_s || state_->track.interpolate(t, pose) != PoseLookup::ok) return out;
  state_->last_pose_s = t;
  state_->track.drop_before(t);
  const SensorMount& mount = state_->config.mount;
  Eigen::Isometry3d sensor = Eigen::Isometry3d::Identity();
  sensor.linear() = sensor_to_map_rotation(pose, mount);
  sensor.translation() = sensor_origin_in_map(pose, mount);
  out.push_back({t, sensor * sensor_on_trunk().inverse()});
  return out;
}

Eigen::Isometry3d UrgInput::sensor_on_trunk() const {
  const SensorMount& mount = state_->config.mount;
  Eigen::Isometry3d t = Eigen::Isometry3d::Identity();
  t.linear() = mount_rotation(mount);
  t.translation() = Eigen::Vector3d(mount.forward_offset_m, mount.lateral_offset_m, mount.height_m);
  return t;
}

}  // namespace stridemap::ros_adapter
