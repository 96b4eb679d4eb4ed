// Snapshots for readers on other threads (map_publisher.hpp). The threaded
// tests are the ones `make test-tsan` runs under ThreadSanitizer; here they
// also check that no reader ever sees a half-written map.
#include "stridemap/core/map_publisher.hpp"

#include <atomic>
#include <cmath>
#include <thread>
#include <vector>

#include <gtest/gtest.h>

#include "stridemap/core/error.hpp"
#include "stridemap/core/terrain_mapper.hpp"

namespace stridemap {
namespace {

PlanarScan ground_scan(const SensorMount& mount, double time_s) {
  PlanarScan scan;
  scan.time_s = time_s;
  scan.resize(200);
  for (std::size_t i = 0; i < scan.size(); ++i) {
    const double t = -0.8 + 1.6 * static_cast<double>(i) / 199.0;
    scan.angle_rad[i] = t;
    scan.range_m[i] = mount.height_m / (std::cos(t) * std::sin(mount.pitch_rad));
    scan.range_error_m[i] = 0.01;
  }
  return scan;
}

// Every cell of the map set from one number, so that a snapshot mixing two
// publishes shows as cells that disagree.
void stamp(ElevationMap& map, std::uint64_t value) {
  const std::size_t cells = static_cast<std::size_t>(map.cells_per_side()) * map.cells_per_side();
  for (std::size_t s = 0; s < cells; ++s) {
    map.elevation_data()[s] = static_cast<float>(value);
    map.certainty_data()[s] = static_cast<float>(value % 97);
  }
}

bool stamped_consistently(const PublishedMap& snapshot, std::uint64_t value) {
  const ElevationMap& map = snapshot.map;
  const std::size_t cells = static_cast<std::size_t>(map.cells_per_side()) * map.cells_per_side();
  for (std::size_t s = 0; s < cells; ++s) {
    if (map.elevation_data()[s] != static_cast<float>(value)) return false;
    if (map.certainty_data()[s] != static_cast<float>(value % 97)) return false;
  }
  return true;
}

TEST(MapPublisher, LatestIsEmptyUntilTheFirstPublishThenCopiesTheMapper) {
  SensorMount mount;
  MapperOptions options;
  options.follow_robot = false;
  TerrainMapper mapper(options, mount);
  MapPublisher publisher(options.grid);
  EXPECT_FALSE(publisher.latest());
  TrunkPose pose;
  pose.yaw_rad = 0.01;
  mapper.integrate(ground_scan(mount, 2.5), pose);
  ASSERT_TRUE(publisher.publish(mapper));
  const PublishedMapHandle snapshot = publisher.latest();
  ASSERT_TRUE(snapshot);
  EXPECT_EQ(snapshot->sequence, 1u);
  EXPECT_EQ(snapshot->scans, 1u);
  EXPECT_EQ(snapshot->time_s, 2.5);
  EXPECT_EQ(snapshot->pose.yaw_rad, 0.01);
  const CellIndex ahead = mapper.map().cell_of(0.37, 0.0);
  EXPECT_EQ(snapshot->map.state(ahead), CellState::measured);
  EXPECT_EQ(snapshot->map.elevation(ahead), mapper.map().elevation(ahead));
  EXPECT_EQ(publisher.published(), 1u);
}

TEST(MapPublisher, AHeldSnapshotNeverChanges) {
  ElevationMap source(GridOptions{20, 0.01});
  PublishedMap* buffer = nullptr;
  MapPublisher publisher(GridOptions{20, 0.01});
  stamp(source, 1);
  buffer = publisher.begin_publish();
  buffer->map = source;
  publisher.commit_publish();
  const PublishedMapHandle held = publisher.latest();
  for (std::uint64_t k = 2; k < 50; ++k) {
    stamp(source, k);
    buffer = publisher.begin_publish();
    ASSERT_NE(buffer, nullptr) << "3 buffers, one reader: never full";
    ASSERT_NE(buffer, held.get());
    buffer->map = source;
    publisher.commit_publish();
  }
  EXPECT_TRUE(stamped_consistently(*held, 1));
  EXPECT_EQ(held->sequence, 1u);
  EXPECT_EQ(publisher.latest()->sequence, 49u);
  EXPECT_TRUE(stamped_consistently(*publisher.latest(), 49));
  EXPECT_EQ(publisher.skipped(), 0u);
}

TEST(MapPublisher, PublishWithoutAFreeBufferIsSkippedAndCounted) {
  SensorMount mount;
  MapperOptions options;
  TerrainMapper mapper(options, mount);
  MapPublisher publisher(options.grid, 2);
  mapper.integrate(ground_scan(mount, 0.1), TrunkPose{});
  ASSERT_TRUE(publisher.publish(mapper));
  PublishedMapHandle first = publisher.latest();
  ASSERT_TRUE(publisher.publish(mapper));   // the other buffer
  EXPECT_FALSE(publisher.publish(mapper));  // one latest, one held: none free
  EXPECT_EQ(publisher.skipped(), 1u);
  EXPECT_EQ(publisher.latest()->sequence, 2u);  // readers still get a whole map
  first.reset();
  EXPECT_TRUE(publisher.publish(mapper));
  EXPECT_EQ(publisher.latest()->sequence, 3u);
  PublishedMapHandle moved = publisher.latest();
  PublishedMapHandle target = std::move(moved);
  EXPECT_FALSE(moved);
  EXPECT_EQ(target->sequence, 3u);
}

TEST(MapPublisher, BadSetUpIsAnError) {
  EXPECT_THROW(MapPublisher(GridOptions{}, 1), InputError);
  EXPECT_THROW(MapPublisher(GridOptions{0, 0.01}), InputError);
  MapPublisher publisher(GridOptions{50, 0.01});
  TerrainMapper mapper(MapperOptions{}, SensorMount{});  // 100 x 100
  EXPECT_THROW(publisher.publish(mapper), InputError);
}

// One writer stamping and publishing as fast as it can, three readers
// checking every snapshot they get: none may be torn, sequences only grow.
TEST(MapPublisherThreads, ReadersNeverSeeATornSnapshot) {
  constexpr std::uint64_t kPublishes = 3000;
  MapPublisher publisher(GridOptions{40, 0.01}, 5);  // 3 readers + 2
  std::atomic<bool> done{false};
  std::atomic<int> torn{0};
  std::atomic<std::uint64_t> reads{0};
  std::vector<std::thread> readers;
  for (int r = 0; r < 3; ++r) {
    readers.emplace_back([&] {
      std::uint64_t last = 0;
      while (!done.load()) {
        const PublishedMapHandle snapshot = publisher.latest();
        if (!snapshot) continue;
        if (snapshot->sequence < last || !stamped_consistently(*snapshot, snapshot->sequence)) ++torn;
        last = snapshot->sequence;
        ++reads;
      }
    });
  }
  ElevationMap source(GridOptions{40, 0.01});
  // Go on until the readers have overlapped the writing many times (threads
  // may start late).
  for (std::uint64_t k = 1; k <= kPublishes || reads.load() < 3000; ++k) {
    stamp(source, k);
    PublishedMap* buffer = publisher.begin_publish();
    ASSERT_NE(buffer, nullptr);
    buffer->map = source;
    publisher.commit_publish();  // sets sequence k
  }
  done = true;
  for (std::thread& t : readers) t.join();
  EXPECT_EQ(torn.load(), 0);
  EXPECT_GE(publisher.published(), kPublishes);
  EXPECT_EQ(publisher.skipped(), 0u);
}

// The real pipeline: scans integrated and published on one thread while a
// planner thread reads cells of the latest snapshot.
TEST(MapPublisherThreads, PlannerReadsWhileTheMapperWalks) {
  SensorMount mount;
  MapperOptions options;
  TerrainMapper mapper(options, mount);
  MapPublisher publisher(options.grid);
  std::atomic<bool> done{false};
  std::atomic<int> bad{0};
  std::atomic<int> reads{0};
  std::thread planner([&] {
    while (!done.load()) {
      const PublishedMapHandle snapshot = publisher.latest();
      if (!snapshot) continue;
      ++reads;
      const ElevationMap& map = snapshot->map;
      for (int i = 0; i < map.cells_per_side(); ++i) {
        const CellIndex c = map.cell_at_local(i, map.cells_per_side() / 2);
        if (map.state(c) == CellState::measured && !(std::abs(map.elevation(c)) < 0.01)) ++bad;
        if (map.state(c) == CellState::unknown && map.certainty(c) != 0.0f) ++bad;
      }
    }
  });
  TrunkPose pose;
  for (int k = 0; k < 400 || reads.load() < 200; ++k) {
    pose.x_m = 0.01 * k;
    mapper.integrate(ground_scan(mount, 0.1 * k), pose);
    publisher.publish(mapper);
  }
  done = true;
  planner.join();
  EXPECT_EQ(bad.load(), 0);
  EXPECT_GE(publisher.latest()->scans, 400u);
}

}  // namespace
}  // namespace stridemap
