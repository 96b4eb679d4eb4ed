// What stridemap.Pipeline's add_* calls run per scan once the binding has
// checked the arrays (python/src/feed, linked into the module as is)
// allocates nothing after warm-up: URG scans in millimetres and in metres,
// a batch past row 100 (where a beam's name, "ranges[100][5]", no longer
// fits a short string), point and stripe frames. The NumPy arrays and
// pybind11's call objects around it are the caller's. Global operator new is
// replaced in this test binary to count allocations while a flag is set.
#include <gtest/gtest.h>

#include "allocation_counting.hpp"

#include <cmath>
#include <cstdint>
#include <cstring>
#include <string>
#include <vector>

#include "feed/scan_feed.hpp"
#include "pipeline/pipeline_test_support.hpp"
#include "stridemap/core/error.hpp"

STRIDEMAP_REPLACE_OPERATOR_NEW()

namespace stridemap::python {
namespace {

using test::allocation_counter;
using test::floor_scan;
using test::pose_at;

using test::Counting;

// Scan k of a floor seen while walking, as the float64 millimetres NumPy
// hands over: every scan's values differ.
std::vector<double> floor_values_mm(int k) {
  const UrgRawScan raw = floor_scan(0.0);
  std::vector<double> values(raw.values_mm.begin(), raw.values_mm.end());
  for (std::size_t i = 0; i < values.size(); ++i) {
    if (values[i] > 0.0) values[i] += static_cast<double>((k * 7 + static_cast<int>(i) * 13) % 5);
  }
  return values;
}

std::vector<double> in_metres(std::vector<double> mm) {
  for (double& v : mm) v *= 0.001;
  return mm;
}

TEST(PythonScanFeedAllocation, UrgScansInMillimetresAndMetresAllocateNothing) {
  STRIDEMAP_SKIP_UNLESS_COUNTING_ALLOCATIONS();
  MappingPipeline pipeline{PipelineOptions{}};
  ScanFeed feed(pipeline);
  constexpr int kWarmUp = 5, kScans = 200;
  std::vector<std::vector<double>> mm, m;
  for (int k = 0; k < kWarmUp + kScans; ++k) {
    mm.push_back(floor_values_mm(k));
    m.push_back(in_metres(mm.back()));
  }
  const auto step = [&](int k) {
    const std::vector<double>& values = k % 2 == 0 ? mm[k] : m[k];
    const RangeUnits units = k % 2 == 0 ? RangeUnits::mm : RangeUnits::m;
    feed.add_urg(values.data(), values.size(), units, 0.1 * (k + 1), std::nullopt, 1, pose_at(0.004 * k, 0.001 * k));
  };
  for (int k = 0; k < kWarmUp; ++k) step(k);
  std::size_t allocations = 0;
  {
    Counting counting;
    for (int k = kWarmUp; k < kWarmUp + kScans; ++k) step(k);
    allocations = counting.allocations();
  }
  EXPECT_EQ(allocations, 0u) << "over " << kScans << " scans";
  EXPECT_EQ(pipeline.stats().integrated, static_cast<std::size_t>(kWarmUp + kScans));
}

// add_urg_scans' arrays: K rows of ranges, times, poses (5 values) and
// per-scan reference elevations.
struct BatchArrays {
  std::vector<double> ranges, times_s, poses, reference_elevation_m;
  std::size_t values_per_scan = 0;

  BatchArrays(int first, int scans) {
    for (int k = first; k < first + scans; ++k) {
      const std::vector<double> row = floor_values_mm(k);
      values_per_scan = row.size();
      ranges.insert(ranges.end(), row.begin(), row.end());
      times_s.push_back(0.1 * (k + 1));
      poses.insert(poses.end(), {0.004 * k, 0.0, 0.0, 0.0, 0.001 * k});
      reference_elevation_m.push_back(0.0001 * k);
    }
  }
  UrgBatch batch() const {
    UrgBatch b;
    b.scans = times_s.size();
    b.ranges = ranges.data();
    b.values_per_scan = values_per_scan;
    b.times_s = times_s.data();
    b.poses = poses.data();
    b.reference_elevation_m = reference_elevation_m.data();
    return b;
  }
};

TEST(PythonScanFeedAllocation, ABatchPastRowOneHundredAllocatesNothing) {
  STRIDEMAP_SKIP_UNLESS_COUNTING_ALLOCATIONS();
  MappingPipeline pipeline{PipelineOptions{}};
  ScanFeed feed(pipeline);
  constexpr int kWarmUp = 5, kScans = 300;
  const BatchArrays warm_up(0, kWarmUp), counted(kWarmUp, kScans);
  ASSERT_EQ(feed.add_urg_batch(warm_up.batch()).mapped, static_cast<std::size_t>(kWarmUp));
  std::size_t allocations = 0;
  UrgBatchCounts counts;
  {
    Counting counting;
    counts = feed.add_urg_batch(counted.batch());
    allocations = counting.allocations();
  }
  EXPECT_EQ(allocations, 0u) << "over " << kScans << " scans";
  EXPECT_EQ(counts.mapped, static_cast<std::size_t>(kScans));
  EXPECT_EQ(counts.stale + counts.bad_pose + counts.unfit, 0u);
}

TEST(PythonScanFeedAllocation, PointAndStripeFramesAllocateNothing) {
  STRIDEMAP_SKIP_UNLESS_COUNTING_ALLOCATIONS();
  PipelineOptions sl_options;
  sl_options.sensor = SensorKind::structured_light;
  sl_options.mount = sl_options.structured_light.mount;
  MappingPipeline stripes(sl_options);
  ScanFeed stripe_feed(stripes);
  std::vector<double> uv;
  for (int u = 0; u < sl_options.structured_light.image_width_px; ++u) uv.insert(uv.end(), {u + 0.5, 300.0});

  PipelineOptions point_options;
  point_options.sensor = SensorKind::points;
  MappingPipeline points(point_options);
  ScanFeed point_feed(points);
  std::vector<double> xyz, sigma_m;
  for (int i = 0; i < 200; ++i) {
    xyz.insert(xyz.end(), {0.3 + 0.002 * i, 0.001 * i, -0.25});
    sigma_m.push_back(0.005);
  }
  const double one_sigma_m = 0.004;
  const auto step = [&](int k) {
    const double time_s = 0.04 * (k + 1);
    stripe_feed.add_stripe(uv.data(), uv.size() / 2, time_s, pose_at(0.004 * k));
    if (k % 2 == 0) {
      point_feed.add_points(xyz.data(), sigma_m.size(), sigma_m.data(), false, time_s, pose_at(0.004 * k));
    } else {
      point_feed.add_points(xyz.data(), sigma_m.size(), &one_sigma_m, true, time_s, pose_at(0.004 * k));
    }
  };
  for (int k = 0; k < 3; ++k) step(k);
  std::size_t allocations = 0;
  {
    Counting counting;
    for (int k = 3; k < 60; ++k) step(k);
    allocations = counting.allocations();
  }
  EXPECT_EQ(allocations, 0u);
  EXPECT_GT(stripes.mapper().totals().integrated, 0u);
  EXPECT_GT(points.mapper().totals().integrated, 0u);
}

using test::same_maps;

// The feed is the pipeline fed the raw scan the sensor would have sent:
// the same map bit for bit, whichever units the values came in.
TEST(PythonScanFeed, MapsAsThePipelineFedTheRawScans) {
  const PipelineOptions options;
  MappingPipeline direct(options), fed_mm(options), fed_m(options), fed_batch(options);
  ScanFeed feed_mm(fed_mm), feed_m(fed_m), feed_batch(fed_batch);
  constexpr int kScans = 40;
  for (int k = 0; k < kScans; ++k) {
    const std::vector<double> mm = floor_values_mm(k), m = in_metres(mm);
    UrgRawScan raw = floor_scan(0.1 * (k + 1));
    for (std::size_t i = 0; i < mm.size(); ++i) raw.values_mm[i] = static_cast<std::uint32_t>(mm[i]);
    TrunkPose pose = pose_at(0.004 * k, 0.001 * k);
    pose.reference_elevation_m = 0.0001 * k;
    direct.add(raw, pose);
    feed_mm.add_urg(mm.data(), mm.size(), RangeUnits::mm, raw.time_s, std::nullopt, 1, pose);
    feed_m.add_urg(m.data(), m.size(), RangeUnits::m, raw.time_s, std::nullopt, 1, pose);
  }
  feed_batch.add_urg_batch(BatchArrays(0, kScans).batch());
  const ElevationMap& expected = direct.mapper().map();
  EXPECT_TRUE(same_maps(fed_mm.mapper().map(), expected));
  EXPECT_TRUE(same_maps(fed_m.mapper().map(), expected));
  EXPECT_TRUE(same_maps(fed_batch.mapper().map(), expected));
}

// A bad value far into a batch is named by row and beam, the rows before
// it mapped; a scan the sensor cannot have sent is refused in its words.
TEST(PythonScanFeed, ErrorsNameTheRowAndTheBeam) {
  MappingPipeline pipeline{PipelineOptions{}};
  ScanFeed feed(pipeline);
  BatchArrays arrays(0, 160);
  arrays.ranges[150 * arrays.values_per_scan + 3] = -1.0;
  try {
    feed.add_urg_batch(arrays.batch());
    FAIL() << "no error";
  } catch (const InputError& e) {
    EXPECT_EQ(std::string(e.what()).rfind("ranges[150][3]: a raw URG value is 0..4294967295 mm, got -1", 0), 0u)
        << e.what();
  }
  EXPECT_EQ(pipeline.stats().integrated, 150u);
  arrays.times_s[155] = std::nan("");
  arrays.ranges[150 * arrays.values_per_scan + 3] = 400.0;
  EXPECT_THROW(
      {
        try {
          feed.add_urg_batch(arrays.batch());
        } catch (const InputError& e) {
          EXPECT_STREQ(e.what(), "times_s[155]: expected a finite number, got nan");
          throw;
        }
      },
      InputError);
  const std::vector<double> too_long(683, 1000.0);
  EXPECT_THROW(feed.add_urg(too_long.data(), too_long.size(), RangeUnits::mm, 100.0, std::nullopt, 1, pose_at(0.0)),
               InputError);
  EXPECT_THROW(range_units("cm"), InputError);
}

}  // namespace
}  // namespace stridemap::python
