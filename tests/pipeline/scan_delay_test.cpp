// A scan held back by the scan-sequence filter comes out with the pose and
// the beam tags it went in with, however many scans follow it.
#include <cstdint>
#include <vector>

#include <gtest/gtest.h>

#include "pipeline_test_support.hpp"
#include "stridemap/core/error.hpp"
#include "stridemap/pipeline/mapping_pipeline.hpp"
#include "stridemap/pipeline/tagged_scan_filter.hpp"

namespace stridemap {
namespace {

using test::floor_scan;
using test::pose_at;

PlanarScan planar(double time_s) {
  PlanarScan scan;
  UrgModel().to_planar_scan(floor_scan(time_s), scan);
  return scan;
}

TEST(TaggedScanFilter, TheHeldScanComesOutWithItsOwnPoseAndTags) {
  TaggedScanFilter filter({ScanFilterKind::range_clustering, ScanFilterKind::scan_sequence});
  ASSERT_EQ(filter.delay_scans(), 1u);
  PlanarScan out;
  std::vector<std::uint8_t> tags(682);
  for (int k = 0; k < 4; ++k) {
    tags.assign(tags.size(), static_cast<std::uint8_t>(10 + k));
    const bool ready = filter.push(planar(0.1 * k), pose_at(k), tags, out);
    EXPECT_EQ(ready, k > 0);
    if (!ready) continue;
    EXPECT_DOUBLE_EQ(out.time_s, 0.1 * (k - 1));
    EXPECT_DOUBLE_EQ(filter.output().pose.x_m, k - 1.0);
    ASSERT_EQ(filter.output().beam_tags.size(), tags.size());
    EXPECT_EQ(filter.output().beam_tags.front(), 10 + k - 1);
    EXPECT_EQ(filter.output().sequence, static_cast<std::size_t>(k - 1));
  }
  ASSERT_TRUE(filter.flush(out));
  EXPECT_DOUBLE_EQ(out.time_s, 0.3);
  EXPECT_DOUBLE_EQ(filter.output().pose.x_m, 3.0);
  EXPECT_EQ(filter.output().beam_tags.front(), 13);
  EXPECT_FALSE(filter.flush(out));
}

TEST(TaggedScanFilter, WithoutScanSequenceEachScanComesOutAtOnce) {
  TaggedScanFilter filter({ScanFilterKind::speckle});
  PlanarScan out;
  const std::vector<std::uint8_t> tags{7};
  ASSERT_TRUE(filter.push(planar(1.0), pose_at(2.0), tags, out));
  EXPECT_DOUBLE_EQ(filter.output().pose.x_m, 2.0);
  EXPECT_EQ(filter.output().beam_tags, tags);
  EXPECT_FALSE(filter.flush(out));
}

TEST(TaggedScanFilter, AScanOfAnotherLengthDropsTheHeldOneAndStartsAnew) {
  TaggedScanFilter filter({ScanFilterKind::scan_sequence});
  PlanarScan out, short_scan = planar(0.2);
  short_scan.resize(100);
  EXPECT_FALSE(filter.push(planar(0.1), pose_at(1.0), {}, out));
  EXPECT_THROW(filter.push(short_scan, pose_at(2.0), {}, out), InputError);
  EXPECT_FALSE(filter.holding());
  EXPECT_FALSE(filter.flush(out));
  EXPECT_FALSE(filter.push(planar(0.3), pose_at(3.0), {}, out));
  ASSERT_TRUE(filter.flush(out));
  EXPECT_DOUBLE_EQ(filter.output().pose.x_m, 3.0);
}

// Through the whole pipeline: the map gets each scan at the pose it was
// taken at, as if the filter had no delay.
class PoseRecorder final : public PipelineObserver {
 public:
  void on_scan(const ScanReport& report) override {
    xs.push_back(report.payload.pose.x_m);
    times.push_back(report.time_s.value_or(-1.0));
    first_tags.push_back(report.payload.beam_tags.empty() ? 0 : report.payload.beam_tags.front());
  }
  std::vector<double> xs, times;
  std::vector<std::uint8_t> first_tags;
};

TEST(PipelineDelay, ScansReachTheMapAtThePoseTheyWereTakenAt) {
  PipelineOptions options;
  options.filters = {ScanFilterKind::scan_sequence};
  MappingPipeline pipeline(options);
  PoseRecorder recorder;
  pipeline.integrator().add_observer(recorder);
  for (int k = 0; k < 3; ++k) {
    const std::vector<std::uint8_t> tags(682, static_cast<std::uint8_t>(k + 1));
    pipeline.add(floor_scan(0.1 * k), pose_at(0.01 * k), tags);
  }
  EXPECT_EQ(recorder.xs.size(), 2u);
  pipeline.finish();
  EXPECT_EQ(recorder.xs, (std::vector<double>{0.0, 0.01, 0.02}));
  EXPECT_EQ(recorder.times, (std::vector<double>{0.0, 0.1, 0.2}));
  EXPECT_EQ(recorder.first_tags, (std::vector<std::uint8_t>{1, 2, 3}));
  EXPECT_DOUBLE_EQ(pipeline.mapper().last_pose()->x_m, 0.02);
}

}  // namespace
}  // namespace stridemap
