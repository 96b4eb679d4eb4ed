// Poses at scan times: exact at the samples, linear between them, yaw the
// short way round, nothing made up outside the samples or across gaps.
#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <numbers>

#include "stridemap/core/error.hpp"
#include "stridemap/core/pose_track.hpp"

namespace stridemap {
namespace {

TimedPose at(double t, double x, double yaw = 0.0) {
  TimedPose p;
  p.time_s = t;
  p.pose.x_m = x;
  p.pose.y_m = -x;
  p.pose.yaw_rad = yaw;
  p.pose.pitch_rad = 0.1 * x;
  p.pose.height_change_m = 0.01 * x;
  return p;
}

TEST(PoseTrack, SamplesComeBackBitForBitAndMidpointsInterpolate) {
  PoseTrack track;
  track.append(at(0.1, 0.3));
  track.append(at(0.2, 0.7));
  track.append(at(0.3, 1.1));
  TrunkPose p;
  ASSERT_EQ(track.interpolate(0.2, p), PoseLookup::ok);
  EXPECT_EQ(p.x_m, 0.7);
  ASSERT_EQ(track.interpolate(0.3, p), PoseLookup::ok);
  EXPECT_EQ(p.x_m, 1.1);  // the last sample too, not 0.7 + 1 * (1.1 - 0.7)
  ASSERT_EQ(track.interpolate(0.25, p), PoseLookup::ok);
  EXPECT_NEAR(p.x_m, 0.9, 1e-12);
  EXPECT_NEAR(p.y_m, -0.9, 1e-12);
  EXPECT_NEAR(p.pitch_rad, 0.09, 1e-12);
  EXPECT_NEAR(p.height_change_m, 0.009, 1e-12);
}

TEST(PoseTrack, YawTakesTheShortWayAcrossPi) {
  PoseTrack track;
  track.append(at(0.0, 0.0, std::numbers::pi - 0.1));
  track.append(at(1.0, 0.0, -std::numbers::pi + 0.1));
  TrunkPose p;
  ASSERT_EQ(track.interpolate(0.5, p), PoseLookup::ok);
  EXPECT_NEAR(std::cos(p.yaw_rad), -1.0, 1e-12);  // through pi, not through 0
}

TEST(PoseTrack, NoPoseOutsideTheSamplesOrAcrossAGap) {
  PoseTrack track(0.5);
  TrunkPose p;
  EXPECT_EQ(track.interpolate(1.0, p), PoseLookup::empty);
  track.append(at(1.0, 0.0));
  track.append(at(1.2, 0.1));
  track.append(at(2.0, 0.2));
  EXPECT_EQ(track.interpolate(0.9, p), PoseLookup::before_first);
  EXPECT_EQ(track.interpolate(2.1, p), PoseLookup::after_last);
  EXPECT_EQ(track.interpolate(1.5, p), PoseLookup::gap_too_large);
  EXPECT_EQ(track.interpolate(1.1, p), PoseLookup::ok);
}

TEST(PoseTrack, OutOfOrderOrNonFinitePosesAreRefused) {
  PoseTrack track;
  track.append(at(1.0, 0.0));
  EXPECT_THROW(track.append(at(1.0, 0.1)), InputError);
  EXPECT_THROW(track.append(at(0.5, 0.1)), InputError);
  TimedPose bad = at(2.0, 0.0);
  bad.pose.roll_rad = std::numeric_limits<double>::infinity();
  EXPECT_THROW(track.append(bad), InputError);
  EXPECT_THROW(PoseTrack(0.0), InputError);
  try {
    track.append(at(0.5, 0.1));
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("not later than the previous pose's 1 s"), std::string::npos) << e.what();
  }
}

TEST(PoseTrack, ZInterpolatesWhenEveryPoseHasIt) {
  PoseTrack track;
  TimedPose a = at(0.0, 0.0), b = at(1.0, 1.0);
  a.pose.z_m = 0.30;
  b.pose.z_m = 0.40;
  track.append(a);
  track.append(b);
  TrunkPose p;
  ASSERT_EQ(track.interpolate(0.25, p), PoseLookup::ok);
  ASSERT_TRUE(p.z_m.has_value());
  EXPECT_NEAR(*p.z_m, 0.325, 1e-12);
  ASSERT_EQ(track.interpolate(1.0, p), PoseLookup::ok);
  EXPECT_EQ(*p.z_m, 0.40);
  // Poses without z stay without z.
  EXPECT_FALSE(interpolate_pose(at(0, 0).pose, at(1, 1).pose, 0.5).z_m.has_value());
}

TEST(PoseTrack, ATrackMixingPosesWithAndWithoutZOrANonFiniteZIsRefused) {
  PoseTrack track;
  TimedPose with_z = at(0.0, 0.0);
  with_z.pose.z_m = 0.3;
  track.append(with_z);
  try {
    track.append(at(1.0, 0.1));
    ADD_FAILURE() << "a pose without z after one with z was accepted";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("has no z but the previous pose has one"), std::string::npos) << e.what();
  }
  TimedPose nan_z = at(2.0, 0.0);
  nan_z.pose.z_m = std::numeric_limits<double>::quiet_NaN();
  EXPECT_THROW(track.append(nan_z), InputError);
  PoseTrack without;
  without.append(at(0.0, 0.0));
  TimedPose late = at(1.0, 0.0);
  late.pose.z_m = 0.2;
  EXPECT_THROW(without.append(late), InputError);
  EXPECT_EQ(without.size(), 1u);
}

TEST(PoseTrack, DropBeforeKeepsWhatLaterTimesNeed) {
  PoseTrack track;
  for (int i = 0; i < 10; ++i) track.append(at(0.1 * i, i));
  track.drop_before(0.45);
  EXPECT_EQ(track.size(), 6u);  // 0.4 .. 0.9
  TrunkPose p;
  EXPECT_EQ(track.interpolate(0.45, p), PoseLookup::ok);
}

// Finite poses as far apart as doubles go (a pose file may say 1e308 m):
// the differences overflow, the interpolated pose must not.
TEST(PoseTrack, FarApartFinitePosesInterpolateToFinitePoses) {
  PoseTrack track(std::numeric_limits<double>::infinity());
  TimedPose a = at(-1e308, 0.0), b = at(1e308, 0.0);
  a.pose.x_m = -1e308;
  b.pose.x_m = 1e308;
  a.pose.yaw_rad = -1e308;
  b.pose.yaw_rad = 1e308;
  track.append(a);
  track.append(b);
  TrunkPose p;
  ASSERT_EQ(track.interpolate(0.0, p), PoseLookup::ok);
  EXPECT_TRUE(std::isfinite(p.x_m) && std::isfinite(p.yaw_rad)) << p.x_m << " " << p.yaw_rad;
  EXPECT_NEAR(p.x_m, 0.0, 1e292);
  ASSERT_EQ(track.interpolate(1e308, p), PoseLookup::ok);
  EXPECT_EQ(p.x_m, 1e308);
}

}  // namespace
}  // namespace stridemap
