// Poses as a stream: each scan waits for the poses around its time and is
// integrated at the pose interpolated there; scans that can never get one
// are skipped and counted by reason.
#include <gtest/gtest.h>

#include "pipeline_test_support.hpp"
#include "stridemap/core/error.hpp"
#include "stridemap/pipeline/mapping_pipeline.hpp"

namespace stridemap {
namespace {

using test::floor_scan;
using test::pose_at;

TEST(PipelinePoseStream, AScanIsIntegratedAtThePoseInterpolatedToItsTime) {
  PipelineOptions options;
  MappingPipeline pipeline(options);
  PoseTrack poses(1.0);
  poses.append({1.0, pose_at(0.0)});
  pipeline.queue(floor_scan(1.5));
  EXPECT_EQ(pipeline.process(poses, false), 0u);  // the pose after 1.5 s has not come yet
  EXPECT_EQ(pipeline.waiting(), 1u);
  TrunkPose later = pose_at(0.2, 0.1);
  later.pitch_rad = 0.02;
  poses.append({2.0, later});
  EXPECT_EQ(pipeline.process(poses, false), 1u);
  ASSERT_TRUE(pipeline.mapper().last_pose().has_value());
  const TrunkPose used = *pipeline.mapper().last_pose();
  EXPECT_NEAR(used.x_m, 0.1, 1e-12);
  EXPECT_NEAR(used.yaw_rad, 0.05, 1e-12);
  EXPECT_NEAR(used.pitch_rad, 0.01, 1e-12);
  EXPECT_EQ(pipeline.mapper().last_scan_time_s(), 1.5);

  // The same scan at the interpolated pose, by hand, gives the same map.
  TerrainMapper by_hand(options.mapper, options.mount);
  PlanarScan scan;
  UrgModel(options.urg).to_planar_scan(floor_scan(1.5), scan);
  by_hand.integrate(scan, used);
  EXPECT_EQ(by_hand.totals().integrated, pipeline.mapper().totals().integrated);
}

TEST(PipelinePoseStream, ScansWithoutAPoseAreSkippedAndCountedByReason) {
  MappingPipeline pipeline(PipelineOptions{});
  PoseTrack poses(0.5);
  poses.append({1.0, pose_at(0.0)});
  poses.append({1.2, pose_at(0.01)});
  poses.append({3.0, pose_at(0.2)});  // 1.8 s after the previous one: a gap
  pipeline.queue(floor_scan(0.5));    // before the first pose
  pipeline.queue(floor_scan(1.1));    // fine
  pipeline.queue(floor_scan(2.0));    // in the gap
  pipeline.queue(floor_scan(3.5), 10.0);  // after the last pose
  EXPECT_EQ(pipeline.process(poses, false), 1u);
  EXPECT_EQ(pipeline.waiting(), 1u);  // the poses may still come
  EXPECT_EQ(pipeline.expire(9.0), 0u);
  EXPECT_EQ(pipeline.expire(10.0), 1u);  // overdue
  pipeline.queue(floor_scan(4.0));
  EXPECT_EQ(pipeline.process(poses, true), 0u);
  const PipelineStats stats = pipeline.stats();
  EXPECT_EQ(stats.scans, 5u);
  EXPECT_EQ(stats.integrated, 1u);
  EXPECT_EQ(stats.before_first_pose, 1u);
  EXPECT_EQ(stats.pose_gap, 1u);
  EXPECT_EQ(stats.after_last_pose, 2u);
}

TEST(PipelinePoseStream, OtherSensorsWaitForTheirPosesToo) {
  PipelineOptions options;
  options.sensor = SensorKind::points;
  MappingPipeline pipeline(options);
  PointFrame frame;
  frame.time_s = 0.5;
  frame.points_m = {{0.5, 0.0, -0.2}};
  frame.height_sigma_m = {0.01};
  pipeline.queue(frame);
  PoseTrack poses(1.0);
  poses.append({0.0, pose_at(0.0)});
  poses.append({1.0, pose_at(0.1)});
  EXPECT_EQ(pipeline.process(poses, true), 1u);
  EXPECT_DOUBLE_EQ(pipeline.mapper().last_pose()->x_m, 0.05);
}

}  // namespace
}  // namespace stridemap
