// The per-scan path of every filter and of a full chain allocates nothing once
// its buffers have grown. Global operator new is replaced in this test binary
// to count allocations while a flag is set.
#include <gtest/gtest.h>

#include "allocation_counting.hpp"

#include <atomic>
#include <cstdlib>
#include <new>

#include "stridemap/preprocess/scan_filter_chain.hpp"
#include "test_scans.hpp"

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

PlanarScan sequence_scan(int index) {
  // A box approached scan by scan, every third scan with a veil at its edge,
  // and a few isolated points: every filter has work to do.
  PlanarScan scan = test::centred_scan(683);
  const double box_x = 0.47 - 0.01 * static_cast<double>(index % 5);
  test::put_box_scene(scan, 0.60, box_x, 0.10);
  if (index % 3 == 1) {
    std::size_t first = 0;
    std::size_t last = 0;
    test::box_beams(scan, box_x, 0.10, first, last);
    test::put_wavy_veil(scan, first, last, 0.43, 0.55, static_cast<double>(index));
  }
  scan.range_m[100 + static_cast<std::size_t>(index)] -= 0.1;
  scan.range_m[500] = test::nan;
  test::add_noise(scan, 0.002, static_cast<std::uint64_t>(index));
  scan.time_s = 0.1 * index;
  return scan;
}

TEST(Allocation, ChainOfAllFiltersAllocatesNothingOnceWarm) {
  STRIDEMAP_SKIP_UNLESS_COUNTING_ALLOCATIONS();
  ScanFilterChain chain(parse_scan_filter_list("range-clustering,speckle,scan-sequence,between-scans,shadow"));
  std::vector<PlanarScan> scans;
  for (int i = 0; i < 12; ++i) scans.push_back(sequence_scan(i));
  PlanarScan out;
  for (int i = 0; i < 6; ++i) chain.push(scans[static_cast<std::size_t>(i)], out);  // warm up
  std::size_t removed = 0;
  allocations = 0;
  counting = true;
  for (std::size_t i = 6; i < scans.size(); ++i) {
    chain.push(scans[i], out);
    removed += test::count_marked(chain.removed_by_any());
  }
  chain.flush(out);
  counting = false;
  EXPECT_EQ(allocations.load(), 0u);
  EXPECT_GT(removed, 0u);
}

TEST(Allocation, SingleFiltersAllocateNothingOnceWarm) {
  STRIDEMAP_SKIP_UNLESS_COUNTING_ALLOCATIONS();
  RangeClusteringFilter clustering;
  ShadowFilter shadow;
  SpeckleFilterOptions radius;
  radius.mode = SpeckleMode::radius_outlier;
  SpeckleFilter speckle(radius);
  std::vector<std::uint8_t> removed;
  const PlanarScan input = sequence_scan(1);
  PlanarScan scan = input;
  clustering.apply(scan, removed);
  scan = input;
  shadow.apply(scan, removed);
  scan = input;
  speckle.apply(scan, removed);
  allocations = 0;
  counting = true;
  scan = input;
  clustering.apply(scan, removed);
  scan = input;
  shadow.apply(scan, removed);
  scan = input;
  speckle.apply(scan, removed);
  counting = false;
  EXPECT_EQ(allocations.load(), 0u);
}

}  // namespace
}  // namespace stridemap
