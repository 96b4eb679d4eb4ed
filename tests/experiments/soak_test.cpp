// The short soak of `make test` (the full one is `make soak`): the whole
// per-scan pipeline over a path many times the map's size, faults injected,
// a planner thread reading snapshots. Allocations between two checkpoints are
// counted by the program's operator new (operator_new_test.cpp).
#include "stridemap/experiments/soak.hpp"
#include "stridemap/experiments/walk_soak_motion.hpp"

#include <atomic>
#include <cmath>
#include <cstdlib>
#include <new>

#include <gtest/gtest.h>

#include "allocation_counting.hpp"
#include "live/test_folder.hpp"

#include "stridemap/config/scene_yaml.hpp"
#include "stridemap/core/error.hpp"
#include "stridemap/experiments/process_memory.hpp"
#include "test_paths.hpp"


namespace stridemap {
namespace soak_test {
namespace {

std::atomic<bool>& counting = test::allocation_counter().counting;
std::atomic<std::size_t>& allocations = test::allocation_counter().allocations;

const Scene& soak_scene() {
  static const Scene scene = load_scene_yaml(std::string(STRIDEMAP_SOURCE_DIR) + "/scenes/soak_circuit.yaml");
  return scene;
}

SoakOptions short_soak(std::uint64_t seed) {
  SoakOptions options;
  options.scans = 1500;
  options.seed = seed;
  options.checkpoint_every = 250;
  options.faults = {97, 101, 103};  // more often than in the long run, so that a short run has some
  return options;
}

TEST(Soak, ShortRunLosesNothingAndKeepsEveryCellValid) {
  CircuitOptions circuit;
  circuit.step_m = 0.02;  // 30 m in 1500 scans
  const CircuitMotion motion(soak_scene(), circuit);
  const SoakResult r = run_soak(soak_scene(), motion, short_soak(1));
  EXPECT_TRUE(r.failures().empty()) << r.failures().front();
  EXPECT_EQ(r.scans_simulated, 1500u);
  EXPECT_EQ(r.injected_nan_poses, 15u);
  EXPECT_GT(r.injected_duplicates, 10u);
  EXPECT_GT(r.injected_out_of_order, 10u);
  EXPECT_EQ(r.totals.scans_rejected_for_pose, r.injected_nan_poses);
  EXPECT_EQ(r.totals.scans_rejected_for_time, r.injected_duplicates + r.injected_out_of_order);
  EXPECT_EQ(r.invalid_cells, 0u);
  EXPECT_GT(r.integrity_checks, 1500u);
  EXPECT_GT(r.totals.integrated, 300000u);
  // A path many times the 1 m map, the window following it all the way.
  EXPECT_NEAR(r.path_length_m, 30.0, 0.1);
  EXPECT_GT(r.path_extent_x_m, 4.0);
  EXPECT_GT(r.cells_reset_by_moves, 100000u);
  EXPECT_EQ(r.checkpoints.size(), 6u);
  EXPECT_GT(r.checkpoints.back().measured_cells, 1000u);
  EXPECT_EQ(r.published, 150u);
  EXPECT_EQ(r.reader_invalid_cells, 0u);
}

TEST(Soak, TheWalkingRobotLosesNothingEither) {
  const WalkSoakMotion walk(soak_scene());
  SoakOptions options = short_soak(2);
  options.scans = 1200;
  const SoakResult r = run_soak(soak_scene(), walk, options);
  EXPECT_TRUE(r.failures().empty()) << r.failures().front();
  EXPECT_EQ(r.totals.scans_rejected_for_pose, r.injected_nan_poses);
  EXPECT_EQ(r.totals.scans_rejected_for_time, r.injected_duplicates + r.injected_out_of_order);
  EXPECT_EQ(r.invalid_cells, 0u);
  EXPECT_EQ(r.reader_invalid_cells, 0u);
  EXPECT_GT(r.path_length_m, 10.0);  // 0.1 m/s x 120 s
  EXPECT_GT(r.totals.integrated, 200000u);
}

TEST(Soak, SameSeedSameMapsBitForBitAndAnotherSeedDiffers) {
  const CircuitMotion motion(soak_scene(), CircuitOptions{});
  SoakOptions options = short_soak(5);
  options.scans = 600;
  options.checkpoint_every = 200;
  const SoakResult a = run_soak(soak_scene(), motion, options);
  const SoakResult b = run_soak(soak_scene(), motion, options);
  ASSERT_EQ(a.checkpoints.size(), b.checkpoints.size());
  for (std::size_t i = 0; i < a.checkpoints.size(); ++i) {
    EXPECT_EQ(a.checkpoints[i].map_hash, b.checkpoints[i].map_hash) << i;
    EXPECT_EQ(a.checkpoints[i].snapshot_hash, b.checkpoints[i].snapshot_hash) << i;
  }
  EXPECT_EQ(a.run_hash, b.run_hash);
  options.seed = 6;
  EXPECT_NE(run_soak(soak_scene(), motion, options).run_hash, a.run_hash);
}

TEST(Soak, NothingIsAllocatedPerScanAfterTheFirstCheckpoint) {
  STRIDEMAP_SKIP_UNLESS_COUNTING_ALLOCATIONS();
  const CircuitMotion motion(soak_scene(), CircuitOptions{});
  SoakOptions options = short_soak(2);
  options.scans = 900;
  options.checkpoint_every = 300;
  std::size_t counted = 0;
  int checkpoints = 0;
  const SoakResult r = run_soak(soak_scene(), motion, options, [&](const SoakCheckpoint& c) {
    if (++checkpoints == 1) {
      allocations = 0;
      counting = true;
    } else if (c.scan == 900) {
      counting = false;
      counted = allocations.load();
    }
  });
  counting = false;
  EXPECT_EQ(checkpoints, 3);
  EXPECT_EQ(counted, 0u) << "allocations between scan 300 and 900";
  EXPECT_TRUE(r.failures().empty());
}

// Writing and reading tiles frees blocks of many sizes; glibc keeps some of
// each size per thread, counted in use, and once held 2 kB more at one
// checkpoint than at another: a run whose only growth was the tile index
// (one set node per tile) failed its heap check.
TEST(Soak, WithTheGlobalMapOnlyTheTileIndexGrows) {
  test::TestFolder folder;
  const CircuitMotion motion(soak_scene(), CircuitOptions{});
  SoakOptions options;
  options.scans = 3000;  // the first lap's new tiles come after scan 1,000
  options.seed = 1;
  options.global_map.folder = folder / "tiles";
  const SoakResult r = run_soak(soak_scene(), motion, options);
  EXPECT_TRUE(r.failures().empty()) << r.failures().front();
  ASSERT_EQ(r.checkpoints.size(), 3u);
  EXPECT_GT(r.checkpoints.back().global_map_tiles, r.checkpoints.front().global_map_tiles);
  EXPECT_EQ(r.global_map.invalid_on_disk, 0u);
}

TEST(ProcessMemory, TwoReadingsOfTheSameHoldingsAgree) {
  const std::size_t before = process_memory().heap_in_use_bytes;
  if (before == 0) GTEST_SKIP() << "no heap figures here (not glibc, or a sanitizer's malloc)";
  // Through volatile pointers, so that no malloc and free pair is left out.
  static void* (*volatile const take)(std::size_t) = std::malloc;
  static void (*volatile const give_back)(void*) = std::free;
  for (const std::size_t size : {40u, 200u, 520u, 1000u}) {
    void* blocks[5];
    for (void*& block : blocks) block = take(size);
    for (void* block : blocks) give_back(block);
  }
  EXPECT_EQ(process_memory().heap_in_use_bytes, before);
}

// The motion is a plug-in: here a straight line far beyond the scene's
// sampled terrain, the kind of source a walking robot's gait will be.
class StraightLine final : public SoakMotion {
 public:
  void pose_at(std::uint64_t scan, TrunkPose& truth, TrunkPose& estimate) const override {
    truth = TrunkPose{};
    truth.x_m = -4.0 + 0.03 * static_cast<double>(scan);
    truth.y_m = 0.5;
    estimate = truth;
  }
  std::string describe() const override { return "straight line"; }
};

TEST(Soak, AnyMotionPlugsIn) {
  SoakOptions options = short_soak(3);
  options.scans = 300;  // 9 m
  options.reader_thread = false;
  const SoakResult r = run_soak(soak_scene(), StraightLine{}, options);
  EXPECT_TRUE(r.failures().empty());
  EXPECT_EQ(r.motion, "straight line");
  EXPECT_NEAR(r.path_extent_x_m, 0.03 * 299, 1e-9);
  EXPECT_EQ(r.reader_snapshots, 0u);
}

// Faults on neighbouring scans (a repeat of a scan whose pose was NaN, a
// NaN pose on a repeated scan) must each be counted once, by their rule.
TEST(Soak, FaultsOnNeighbouringScansAreEachCountedOnce) {
  const CircuitMotion motion(soak_scene(), CircuitOptions{});
  SoakOptions options = short_soak(4);
  options.scans = 300;
  options.reader_thread = false;
  options.faults = {5, 7, 6};
  const SoakResult r = run_soak(soak_scene(), motion, options);
  EXPECT_TRUE(r.failures().empty()) << r.failures().front();
  EXPECT_EQ(r.injected_nan_poses, 59u);  // the 60th, on the last scan, is still held by the scan-sequence filter
  EXPECT_GT(r.injected_out_of_order, 20u);
}

TEST(Soak, FailuresAreReportedNotHidden) {
  SoakResult r;
  r.scans_to_mapper = 10;
  r.totals.scans = 9;
  r.injected_nan_poses = 2;
  r.totals.scans_rejected_for_pose = 1;
  r.invalid_cells = 3;
  r.first_invalid = "cell (1, 2): measured but elevation nan, certainty 3";
  r.checkpoints = {SoakCheckpoint{100, 0, 0, 0, 1000, 0}, SoakCheckpoint{200, 0, 0, 0, 2000, 0}};
  const std::vector<std::string> failures = r.failures();
  ASSERT_EQ(failures.size(), 4u);
  EXPECT_EQ(failures[0], "the mapper counted 9 scans, 10 were given to it");
  EXPECT_NE(failures[2].find("cell (1, 2)"), std::string::npos);
  EXPECT_NE(failures[3].find("heap in use grew from 1000 bytes at scan 100 to 2000"), std::string::npos);
}

TEST(Soak, BadOptionsAreErrors) {
  const CircuitMotion motion(soak_scene(), CircuitOptions{});
  SoakOptions options;
  options.scans = 0;
  EXPECT_THROW(run_soak(soak_scene(), motion, options), InputError);
  options.scans = 10;
  options.checkpoint_every = 0;
  EXPECT_THROW(run_soak(soak_scene(), motion, options), InputError);
  CircuitOptions circuit;
  circuit.radius_m = -1;
  EXPECT_THROW(CircuitMotion(soak_scene(), circuit), InputError);
}

}  // namespace
}  // namespace soak_test
}  // namespace stridemap
