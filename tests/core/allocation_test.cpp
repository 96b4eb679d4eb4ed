// The per-scan path of the mapper allocates nothing once its buffers have
// grown (the window moving, the pose turning, bad samples included). Global
// operator new is replaced in this test binary to count allocations while a
// flag is set.
#include <atomic>
#include <cmath>
#include <cstdlib>
#include <new>

#include <gtest/gtest.h>

#include "allocation_counting.hpp"

#include "stridemap/core/map_publisher.hpp"
#include "stridemap/core/terrain_mapper.hpp"
#include "stridemap/core/weighted_median_fill.hpp"

namespace {
std::atomic<bool> counting{false};
std::atomic<std::size_t> allocations{0};
}  // namespace

#if STRIDEMAP_ALLOCATION_COUNTING
void* operator new(std::size_t size) {
  if (counting.load(std::memory_order_relaxed)) allocations.fetch_add(1, std::memory_order_relaxed);
  if (void* memory = std::malloc(size == 0 ? 1 : size)) return memory;
  throw std::bad_alloc();
}
void operator delete(void* memory) noexcept { std::free(memory); }
void operator delete(void* memory, std::size_t) noexcept { std::free(memory); }
#endif

namespace stridemap {
namespace {

TEST(MapperAllocation, IntegratingScansAllocatesNothing) {
  STRIDEMAP_SKIP_UNLESS_COUNTING_ALLOCATIONS();
  SensorMount mount;
  TerrainMapper mapper(MapperOptions{}, mount);
  PlanarScan scan;
  scan.resize(682);
  for (std::size_t i = 0; i < scan.size(); ++i) {
    const double t = (static_cast<double>(i) - 340.0) * 2.0 * M_PI / 1024.0;
    scan.angle_rad[i] = t;
    const double down = std::cos(t) * std::sin(mount.pitch_rad);
    scan.range_m[i] = down > 0.1 ? mount.height_m / down : NAN;
    scan.range_error_m[i] = 0.01;
  }
  scan.range_m[5] = INFINITY;
  TrunkPose pose;
  mapper.integrate(scan, pose);  // first scan: the beam cache grows here
  allocations = 0;
  counting = true;
  for (int k = 0; k < 200; ++k) {
    pose.x_m += 0.02;
    pose.yaw_rad += 0.01;
    pose.pitch_rad = 0.02 * std::sin(k);
    scan.time_s += 0.1;
    ASSERT_FALSE(mapper.integrate(scan, pose).time_rejected);
  }
  TrunkPose bad = pose;
  bad.roll_rad = NAN;
  mapper.integrate(scan, bad);
  mapper.integrate(scan, pose);  // the same time again: rejected as a duplicate
  counting = false;
  EXPECT_EQ(allocations.load(), 0u);
  EXPECT_EQ(mapper.totals().scans, 203u);
  EXPECT_EQ(mapper.totals().scans_rejected_for_time, 1u);
}

// Publishing a snapshot for readers copies into buffers allocated up front,
// and the fill-in of eq. (11) run on the snapshot reuses its own buffers.
TEST(MapperAllocation, PublishingSnapshotsAllocatesNothing) {
  STRIDEMAP_SKIP_UNLESS_COUNTING_ALLOCATIONS();
  SensorMount mount;
  TerrainMapper mapper(MapperOptions{}, mount);
  MapPublisher publisher(mapper.options().grid);
  WeightedMedianFill fill;
  PlanarScan scan;
  scan.resize(300);
  for (std::size_t i = 0; i < scan.size(); ++i) {
    scan.angle_rad[i] = -0.7 + 1.4 * static_cast<double>(i) / 299.0;
    scan.range_m[i] = mount.height_m / (std::cos(scan.angle_rad[i]) * std::sin(mount.pitch_rad));
    scan.range_error_m[i] = 0.01;
  }
  TrunkPose pose;
  const auto step = [&] {
    pose.x_m += 0.01;
    scan.time_s += 0.1;
    mapper.integrate(scan, pose);
    PublishedMap* snapshot = publisher.begin_publish();
    ASSERT_NE(snapshot, nullptr);
    snapshot->map = mapper.map();
    fill.apply(snapshot->map);
    publisher.commit_publish();
    publisher.publish(mapper);
  };
  step();
  step();  // every buffer has been written once
  allocations = 0;
  counting = true;
  for (int k = 0; k < 50; ++k) {
    step();
    const PublishedMapHandle held = publisher.latest();
  }
  counting = false;
  EXPECT_EQ(allocations.load(), 0u);
}

}  // namespace
}  // namespace stridemap
