// The adapter's decisions without ROS running: conversions of poses, and
// bad scans counted by reason, never thrown.
#include <cmath>
#include <limits>
#include <vector>

#include <gtest/gtest.h>

#include "stridemap/core/sensor_transform.hpp"
#include "stridemap/core/error.hpp"
#include "stridemap/core/exported_map.hpp"
#include "stridemap_ros/message_mapper_library.hpp"

namespace stridemap::ros_adapter {
namespace {

TEST(TrunkPoseFromSensor, PutsTheSensorWhereTheTransformSays) {
  SensorMount mount;
  mount.forward_offset_m = 0.1;
  mount.lateral_offset_m = -0.03;
  mount.yaw_rad = 0.2;
  mount.roll_rad = -0.05;
  Eigen::Isometry3d sensor = Eigen::Isometry3d::Identity();
  sensor.linear() = (Eigen::AngleAxisd(0.7, Eigen::Vector3d::UnitZ()) * Eigen::AngleAxisd(0.5, Eigen::Vector3d::UnitY()) *
                     Eigen::AngleAxisd(0.1, Eigen::Vector3d::UnitX()))
                        .toRotationMatrix();
  sensor.translation() = Eigen::Vector3d(1.0, -2.0, 0.4);
  const TrunkPose trunk = trunk_pose_from_sensor(sensor, mount);
  ASSERT_TRUE(trunk.z_m.has_value());
  EXPECT_LT((sensor_origin_in_map(trunk, mount) - sensor.translation()).norm(), 1e-12);
  EXPECT_LT((sensor_to_map_rotation(trunk, mount) - sensor.linear()).norm(), 1e-12);
}

// A pose source that knows every time, at a fixed sensor pose.
class FixedPose final : public PoseSource {
 public:
  PoseAnswer answer = PoseAnswer::ok;
  PoseAnswer sensor_in_map(const std::string&, double, Eigen::Isometry3d& out, std::string& why) override {
    out = Eigen::Isometry3d::Identity();
    out.linear() = Eigen::AngleAxisd(0.6, Eigen::Vector3d::UnitY()).toRotationMatrix();
    out.translation() = Eigen::Vector3d(0, 0, 0.3);
    why = "test";
    return answer;
  }
};

struct Scan {
  std::vector<float> ranges = std::vector<float>(21, 0.5f);
  LaserScanData data(double stamp, const std::string& frame = "laser") const {
    LaserScanData d;
    d.stamp_s = stamp;
    d.frame_id = frame;
    d.angle_min_rad = -0.5;
    d.angle_increment_rad = 0.05;
    d.range_min_m = 0.02;
    d.range_max_m = 5.6;
    d.ranges_m = ranges.data();
    d.range_count = ranges.size();
    return d;
  }
};

TEST(MessageMapper, CountsEveryBadScanByReasonAndMapsTheRest) {
  FixedPose poses;
  MessageMapper mapper({}, poses);
  Scan good;
  mapper.add(good.data(1.0), 0.0);
  mapper.add(good.data(1.1, "other_frame"), 0.0);
  mapper.add(good.data(0.95), 0.0);  // stamp going back
  Scan nan = good;
  nan.ranges[3] = std::numeric_limits<float>::quiet_NaN();
  mapper.add(nan.data(1.2), 0.0);
  Scan all_nan;
  all_nan.ranges.assign(21, std::numeric_limits<float>::quiet_NaN());
  mapper.add(all_nan.data(1.3), 0.0);
  Scan bad_angles = good;
  LaserScanData d = bad_angles.data(1.4);
  d.angle_increment_rad = std::numeric_limits<double>::quiet_NaN();
  mapper.add(d, 0.0);
  mapper.process(0.0, false);
  const MessageMapperStats& s = mapper.stats();
  EXPECT_EQ(s.scans, 6u);
  EXPECT_EQ(s.mapped, 2u);
  EXPECT_EQ(s.wrong_frame, 1u);
  EXPECT_EQ(s.stamp_not_increasing, 1u);
  EXPECT_EQ(s.no_valid_beams, 1u);
  EXPECT_EQ(s.bad_geometry, 1u);
  EXPECT_EQ(s.beams_not_finite, 22u);
  EXPECT_EQ(s.scans_with_bad_beams, 2u);
  EXPECT_EQ(s.dropped(), 4u);
  EXPECT_GT(mapper.impl().pipeline->mapper().totals().beams, 0u);
}

TEST(MessageMapper, AScanWaitsForItsPoseWithinTheBoundOnly) {
  FixedPose poses;
  poses.answer = PoseAnswer::not_yet;
  MessageMapperOptions options;
  options.pose_wait_s = 0.5;
  MessageMapper mapper(options, poses);
  Scan good;
  mapper.add(good.data(1.0), 10.0);
  EXPECT_EQ(mapper.process(10.4, false), 0u);
  EXPECT_EQ(mapper.waiting(), 1u);
  EXPECT_EQ(mapper.process(10.6, false), 0u);
  EXPECT_EQ(mapper.stats().pose_timeout, 1u);
  poses.answer = PoseAnswer::never;
  mapper.add(good.data(2.0), 11.0);
  mapper.process(11.0, false);
  EXPECT_EQ(mapper.stats().pose_unavailable, 1u);
  poses.answer = PoseAnswer::ok;
  mapper.add(good.data(3.0), 12.0);
  EXPECT_EQ(mapper.process(12.1, false), 1u);
  EXPECT_NEAR(mapper.stats().latency_max_s, 0.1, 1e-9);
}

TEST(MessageMapper, ClearEmptiesTheMapAndAcceptsAnyStampAfter) {
  FixedPose poses;
  MessageMapper mapper({}, poses);
  Scan good;
  mapper.add(good.data(5.0), 0.0);
  mapper.process(0.0, false);
  EXPECT_GT(map_coverage(export_map(mapper.impl().pipeline->mapper().map())), 0.0);
  mapper.clear();
  EXPECT_EQ(map_coverage(export_map(mapper.impl().pipeline->mapper().map())), 0.0);
  mapper.add(good.data(1.0), 0.0);
  mapper.process(0.0, false);
  EXPECT_EQ(mapper.stats().mapped, 2u);
}

TEST(MessageMapperOptions, BadValuesNameTheField) {
  MessageMapperOptions options;
  options.range_sigma_m = -1;
  try {
    options.validate();
    FAIL();
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("range_sigma_m"), std::string::npos);
  }
}

}  // namespace
}  // namespace stridemap::ros_adapter
