// The adapter's decisions without ROS running: conversions of poses, and
// bad scans counted by reason, never thrown.
#include <cmath>
#include <limits>
#include <vector>

#include <gtest/gtest.h>

#include "stridemap/core/sensor_transform.hpp"
#include "stridemap/core/error.hpp"
#include "stridemap/core/exported_map.hpp"
#include "stridemap/sensors/urg04lx.hpp"
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
  std::string why_not = "test";
  PoseAnswer sensor_in_map(const std::string&, double, Eigen::Isometry3d& out, std::string* why) override {
    out = Eigen::Isometry3d::Identity();
    out.linear() = Eigen::AngleAxisd(0.6, Eigen::Vector3d::UnitY()).toRotationMatrix();
    out.translation() = Eigen::Vector3d(0, 0, 0.3);
    if (why) *why = why_not;
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

// TF's own words for a stamp older than everything it holds.
constexpr const char* kOlderThanTf = "Lookup would require extrapolation 0.07s into the past.";

TEST(MessageMapper, ScansBeforeTheFirstPoseAreStartUpNotDrops) {
  FixedPose poses;
  poses.answer = PoseAnswer::never;
  poses.why_not = kOlderThanTf;
  MessageMapper mapper({}, poses);
  Scan good;
  mapper.add(good.data(1.0), 1.0);
  mapper.add(good.data(1.1), 1.1);
  mapper.process(1.1, false);
  EXPECT_EQ(mapper.stats().before_first_pose, 2u);
  EXPECT_EQ(mapper.stats().dropped(), 0u);
  poses.answer = PoseAnswer::ok;
  mapper.add(good.data(1.2), 1.2);
  EXPECT_EQ(mapper.process(1.2, false), 1u);
  // Once a scan was mapped, a scan TF has forgotten is a real loss.
  poses.answer = PoseAnswer::never;
  mapper.add(good.data(1.3), 1.3);
  mapper.process(1.3, false);
  EXPECT_EQ(mapper.stats().before_first_pose, 2u);
  EXPECT_EQ(mapper.stats().pose_unavailable, 1u);
  EXPECT_EQ(mapper.stats().dropped(), 1u);
}

TEST(MessageMapper, APoseTopicStartingLateIsStartUpNotDrops) {
  TopicPoseSource poses(1.0);
  MessageMapper mapper({}, poses);
  Scan good;
  mapper.add(good.data(1.0), 1.0);
  Eigen::Isometry3d trunk = Eigen::Isometry3d::Identity();
  trunk.translation().z() = 0.3;
  ASSERT_TRUE(poses.add(1.05, trunk));
  ASSERT_TRUE(poses.add(1.25, trunk));
  mapper.process(1.05, false);
  EXPECT_EQ(mapper.stats().before_first_pose, 1u);
  EXPECT_EQ(mapper.stats().dropped(), 0u);
  mapper.add(good.data(1.2), 1.2);
  EXPECT_EQ(mapper.process(1.25, false), 1u);
}

TEST(MessageMapper, ClearEmptiesTheMapAndAcceptsAnyStampAfter) {
  FixedPose poses;
  MessageMapper mapper({}, poses);
  Scan good;
  mapper.add(good.data(5.0), 0.0);
  mapper.process(0.0, false);
  EXPECT_GT(map_coverage(export_map(mapper.impl().pipeline->map())), 0.0);
  mapper.clear();
  EXPECT_EQ(map_coverage(export_map(mapper.impl().pipeline->map())), 0.0);
  mapper.add(good.data(1.0), 0.0);
  mapper.process(0.0, false);
  EXPECT_EQ(mapper.stats().mapped, 2u);
}

// Asked for, the fused height layers follow the scans (a LaserScan takes
// the planar route) and survive ~clear_map; not asked for, they are not
// there to publish.
TEST(MessageMapper, FusedHeightsFollowTheScansWhenAskedFor) {
  FixedPose poses;
  MessageMapperOptions options;
  options.fused_heights = true;
  MessageMapper mapper(options, poses);
  Scan good;
  mapper.add(good.data(1.0), 0.0);
  mapper.process(0.0, false);
  const MapLayers layers = mapper.layers({"elevation", "fused_elevation"});
  std::size_t fused = 0;
  for (std::size_t k = 0; k < layers.values[0].size(); ++k) {
    const float elevation = layers.values[0][k], height = layers.values[1][k];
    ASSERT_EQ(std::isnan(elevation), std::isnan(height)) << k;
    if (std::isnan(height)) continue;
    ++fused;
    EXPECT_NEAR(height, elevation, 0.03) << k;  // one scan: the cells' readings, fused or highest
  }
  EXPECT_GT(fused, 0u);
  mapper.clear();
  EXPECT_NO_THROW(mapper.layers({"fused_elevation"}));

  MessageMapper plain({}, poses);
  EXPECT_THROW(plain.layers({"fused_elevation"}), InputError);
}

// Any scanner: the beams' angles, limits and intensities come from the
// message, each beam judged on its own.
TEST(MessageMapper, TakesEachBeamAsTheMessageDescribesIt) {
  FixedPose poses;
  MessageMapperOptions options;
  options.min_intensity = 100.0;
  MessageMapper mapper(options, poses);
  Scan scan;
  std::vector<float> intensities(21, 500.0f);
  scan.ranges[0] = 0.0f;                                        // "no echo" of many drivers
  scan.ranges[1] = std::numeric_limits<float>::infinity();      // REP-117: nothing within range
  scan.ranges[2] = -std::numeric_limits<float>::infinity();     // REP-117: too close
  scan.ranges[3] = 6.0f;                                        // beyond range_max
  intensities[4] = 20.0f;                                       // too weak
  intensities[5] = std::numeric_limits<float>::quiet_NaN();     // no intensity
  LaserScanData d = scan.data(1.0);
  d.range_min_m = 0.0;  // a driver that states no minimum: 0 is still no reading
  d.range_max_m = 5.6;
  d.intensities = intensities.data();
  d.intensity_count = intensities.size();
  mapper.add(d, 0.0);
  LaserScanData wrong_count = scan.data(1.1);
  wrong_count.intensities = intensities.data();
  wrong_count.intensity_count = 20;  // not one per range while they filter
  mapper.add(wrong_count, 0.0);
  LaserScanData no_increment = scan.data(1.2);
  no_increment.angle_increment_rad = 0.0;
  mapper.add(no_increment, 0.0);
  LaserScanData far_angle = scan.data(1.25);
  far_angle.angle_min_rad = 1e30;  // finite, but no scanner's
  mapper.add(far_angle, 0.0);
  LaserScanData wide = scan.data(1.27);
  wide.angle_increment_rad = 1.0;  // 20 beams over 19 rad
  mapper.add(wide, 0.0);
  LaserScanData limits = scan.data(1.3);
  limits.range_max_m = 0.01;  // below range_min
  mapper.add(limits, 0.0);
  mapper.process(0.0, false);
  const MessageMapperStats& s = mapper.stats();
  EXPECT_EQ(s.mapped, 1u);
  EXPECT_EQ(s.beams, 21u);
  EXPECT_EQ(s.beams_out_of_range, 4u);
  EXPECT_EQ(s.beams_low_intensity, 2u);
  EXPECT_EQ(s.beams_not_finite, 0u);
  EXPECT_EQ(s.bad_geometry, 5u);
  EXPECT_NE(mapper.last_drop().find("range limits"), std::string::npos) << mapper.last_drop();
  EXPECT_EQ(mapper.last_bad_scan(), mapper.last_drop());
  EXPECT_EQ(mapper.impl().pipeline->mapper().totals().beams, 15u);  // the 15 usable beams reached the map

  // Without an intensity threshold the intensities are not looked at.
  MessageMapper ignoring({}, poses);
  ignoring.add(wrong_count, 0.0);
  ignoring.process(0.0, false);
  EXPECT_EQ(ignoring.stats().mapped, 1u);
}

// A scanner turning clockwise (negative angle_increment) describes the same
// beams from the other end: the same map.
TEST(MessageMapper, ANegativeAngleIncrementGivesTheSameMap) {
  FixedPose poses;
  MessageMapper forward({}, poses), backward({}, poses);
  Scan scan;
  for (std::size_t k = 0; k < scan.ranges.size(); ++k) scan.ranges[k] = 0.4f + 0.01f * static_cast<float>(k);
  Scan reversed;
  reversed.ranges.assign(scan.ranges.rbegin(), scan.ranges.rend());
  forward.add(scan.data(1.0), 0.0);
  LaserScanData d = reversed.data(1.0);
  d.angle_min_rad = 0.5;
  d.angle_increment_rad = -0.05;
  backward.add(d, 0.0);
  forward.process(0.0, false);
  backward.process(0.0, false);
  const ExportedMap a = export_map(forward.impl().pipeline->map());
  const ExportedMap b = export_map(backward.impl().pipeline->map());
  ASSERT_GT(map_coverage(a), 0.0);
  EXPECT_EQ(map_coverage(a), map_coverage(b));
  const ExportedLayer& za = a.layers.front();
  const ExportedLayer& zb = b.layers.front();
  for (Eigen::Index i = 0; i < a.cells_per_side; ++i) {
    for (Eigen::Index j = 0; j < a.cells_per_side; ++j) {
      const float va = za.value(i, j), vb = zb.value(i, j);
      if (std::isnan(va)) {
        EXPECT_TRUE(std::isnan(vb));
      } else {
        EXPECT_NEAR(va, vb, 1e-6);
      }
    }
  }
}

// The URG's raw scan as a LaserScan (its step angles, values / 1000, its
// limits) gives the map the library's own URG path gives: the same eq. (6)
// model, Delta r the URG's specification, not a copy with its own model.
TEST(MessageMapper, AUrgScanAsALaserScanMapsAsTheLibrarysUrgPath) {
  FixedPose poses;
  MessageMapper mapper({}, poses);
  PipelineOptions urg_options = message_pipeline_options(MapperConfig{});
  urg_options.sensor = SensorKind::urg;
  MappingPipeline urg(urg_options);
  const UrgParameters p{};
  UrgRawScan raw;
  raw.time_s = 1.0;
  raw.first_step = p.first_step;
  std::vector<float> ranges;
  for (int step = p.first_step; step <= p.last_step; ++step) {
    const auto mm = static_cast<std::uint32_t>(300 + (step * 37) % 900);  // 0.3 to 1.2 m
    raw.values_mm.push_back(step % 50 == 0 ? 5u : mm);                      // 5: an error code
    ranges.push_back(static_cast<float>(raw.values_mm.back()) / 1000.0f);
  }
  LaserScanData d;
  d.stamp_s = 1.0;
  d.frame_id = "laser";
  d.angle_min_rad = p.step_angle_rad(p.first_step);
  d.angle_increment_rad = p.step_angle_rad(p.first_step + 1) - d.angle_min_rad;
  d.range_min_m = p.min_range_m;
  d.range_max_m = p.max_range_m;
  d.ranges_m = ranges.data();
  d.range_count = ranges.size();
  mapper.add(d, 0.0);
  ASSERT_EQ(mapper.process(0.0, false), 1u);
  Eigen::Isometry3d sensor;
  poses.sensor_in_map("laser", 1.0, sensor, nullptr);
  urg.add(raw, trunk_pose_from_sensor(sensor, MapperConfig{}.mount));
  const ExportedMap a = export_map(mapper.impl().pipeline->map());
  const ExportedMap b = export_map(urg.map());
  ASSERT_GT(map_coverage(b), 0.0);
  EXPECT_EQ(map_coverage(a), map_coverage(b));
  for (std::size_t l = 0; l < a.layers.size(); ++l) {
    for (Eigen::Index i = 0; i < a.cells_per_side; ++i) {
      for (Eigen::Index j = 0; j < a.cells_per_side; ++j) {
        const float va = a.layers[l].value(i, j), vb = b.layers[l].value(i, j);
        if (std::isnan(vb)) {
          EXPECT_TRUE(std::isnan(va)) << a.layers[l].spec.name;
        } else {
          EXPECT_NEAR(va, vb, 1e-5) << a.layers[l].spec.name << " at " << i << ", " << j;
        }
      }
    }
  }
}

TEST(MessageMapper, AnUnreadableCloudIsCountedWithItsReason) {
  FixedPose poses;
  MessageMapper mapper({}, poses);
  mapper.add_unreadable("camera", "no z field");
  EXPECT_EQ(mapper.stats().scans, 1u);
  EXPECT_EQ(mapper.stats().unreadable, 1u);
  EXPECT_EQ(mapper.stats().dropped(), 1u);
  EXPECT_NE(mapper.last_drop().find("no z field"), std::string::npos);
}

TEST(MessageMapperOptions, BadValuesNameTheField) {
  MessageMapperOptions options;
  options.range_error_m = -1;
  try {
    options.validate();
    FAIL();
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("range_error_m"), std::string::npos);
  }
}

}  // namespace
}  // namespace stridemap::ros_adapter
