// The extension story, told from outside src/: a new sensor is one class
// (a SensorModel) and a new consumer of per-scan results one class (a
// PipelineObserver); neither needs a change to the library.
#include <vector>

#include <gtest/gtest.h>

#include "stridemap/core/error.hpp"
#include "stridemap/core/sensor_transform.hpp"
#include "stridemap/pipeline/mapping_pipeline.hpp"

namespace stridemap {
namespace {

// Feet as a terrain sensor: leg kinematics tells where each foot in stance
// touches the ground, in the sensor (here: trunk) frame, to within the
// joint encoders' error. A foot is one point whose height error is that
// error; the pose errors do not add to it (the foot is measured relative
// to the ground it stands on).
class FootContactSensor final : public SensorModel {
 public:
  explicit FootContactSensor(double kinematic_error_m) : kinematic_error_m_(kinematic_error_m) {}
  std::string_view name() const override { return "feet"; }
  void set_contacts(std::vector<Eigen::Vector3d> feet_in_trunk) { feet_ = std::move(feet_in_trunk); }
  void to_points(const TrunkPose& pose, const SensorMount& mount, const UpdateOptions&, PointBatch& batch) override {
    batch.clear();
    batch.gamma_rad = 0.0;  // a foot does not sweep a face as the robot walks
    const Eigen::Matrix3d rotation = sensor_to_map_rotation(pose, mount);
    for (const Eigen::Vector3d& foot : feet_) {
      SensorPoint& p = batch.points.emplace_back();
      p.offset_m = rotation * foot;
      p.height_error_m = kinematic_error_m_;
      p.range_m = foot.norm();
    }
  }

 private:
  double kinematic_error_m_;
  std::vector<Eigen::Vector3d> feet_;
};

// A new consumer: sums the mapper's per-scan statistics.
class ScanTotals final : public PipelineObserver {
 public:
  void on_scan(const ScanReport& report) override {
    total += report.stats;
    ++scans;
  }
  ScanStats total;
  std::size_t scans = 0;
};

TEST(PipelineExtension, ANewSensorAndANewConsumerPlugInFromOutsideTheLibrary) {
  PipelineOptions options;
  options.sensor = SensorKind::custom;
  options.mount.pitch_rad = 0.0;
  options.mount.height_m = 0.0;  // the trunk frame: feet are below it
  MappingPipeline pipeline(options);
  ScanTotals totals;
  pipeline.integrator().add_observer(totals);
  pipeline.integrator().set_collect_points(true);

  FootContactSensor feet(0.005);
  TrunkPose pose;
  pose.reference_elevation_m = 0.0;
  feet.set_contacts({{0.2, 0.15, -0.1}, {0.2, -0.15, -0.1}, {-0.2, 0.15, -0.1}});
  ScanOutcome out = pipeline.add(feet, 0.0, pose);
  EXPECT_EQ(out.stats.first, 3u);
  ASSERT_EQ(pipeline.integrator().last_points().size(), 3u);
  EXPECT_NEAR(pipeline.integrator().last_points()[0].map_m.z(), -0.1, 1e-12);
  EXPECT_DOUBLE_EQ(pipeline.integrator().last_points()[0].height_uncertainty_m, 0.005);

  // The same feet a step later, one of them 3 mm lower (within the error)
  // and one 3 cm higher (a stone: outside it).
  feet.set_contacts({{0.2, 0.15, -0.103}, {0.2, -0.15, -0.07}});
  out = pipeline.add(feet, 0.1, pose);
  EXPECT_EQ(out.stats.plausible, 1u);
  EXPECT_EQ(out.stats.implausible, 1u);

  EXPECT_EQ(totals.scans, 2u);
  EXPECT_EQ(totals.total.beams, 5u);
  EXPECT_EQ(totals.total.integrated, 5u);
  EXPECT_EQ(totals.total.first, 3u);
  EXPECT_EQ(pipeline.mapper().totals().integrated, 5u);

  EXPECT_FALSE(totals.total.time_rejected);

  // Out of order: the mapper's time check applies to every sensor alike,
  // and the consumer hears of it.
  out = pipeline.add(feet, 0.05, pose);
  EXPECT_TRUE(out.stats.time_rejected);
  EXPECT_EQ(totals.scans, 3u);
  EXPECT_TRUE(totals.total.time_rejected);
  EXPECT_EQ(pipeline.mapper().totals().scans_rejected_for_time, 1u);
}

TEST(PipelineExtension, ACustomSensorNeedsAPipelineConfiguredForOne) {
  MappingPipeline pipeline(PipelineOptions{});
  FootContactSensor feet(0.005);
  EXPECT_THROW(pipeline.add(feet, 0.0, TrunkPose{}), InputError);
}

}  // namespace
}  // namespace stridemap
