// The per-scan path of the mapper allocates nothing once its buffers have
// grown (the window moving, the pose turning, bad samples included). Global
// operator new is replaced in this test binary to count allocations while a
// flag is set.
#include <atomic>
#include <cmath>
#include <cstdlib>
#include <new>

#include <gtest/gtest.h>

#include "stridemap/core/terrain_mapper.hpp"

namespace {
std::atomic<bool> counting{false};
std::atomic<std::size_t> allocations{0};
}  // namespace

void* operator new(std::size_t size) {
  if (counting.load(std::memory_order_relaxed)) allocations.fetch_add(1, std::memory_order_relaxed);
  if (void* memory = std::malloc(size == 0 ? 1 : size)) return memory;
  throw std::bad_alloc();
}
void operator delete(void* memory) noexcept { std::free(memory); }
void operator delete(void* memory, std::size_t) noexcept { std::free(memory); }

namespace stridemap {
namespace {

TEST(MapperAllocation, IntegratingScansAllocatesNothing) {
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
    mapper.integrate(scan, pose);
  }
  TrunkPose bad = pose;
  bad.roll_rad = NAN;
  mapper.integrate(scan, bad);
  counting = false;
  EXPECT_EQ(allocations.load(), 0u);
}

}  // namespace
}  // namespace stridemap
