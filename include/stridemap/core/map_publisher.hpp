#pragma once
// Hands the map from the mapping thread to readers (a foothold planner, a
// viewer) without tearing: after each scan the writer copies the map into a
// snapshot buffer no reader holds and publishes it; a reader takes the latest
// snapshot and reads it for as long as it likes while the writer goes on.
// A snapshot never changes while a reader holds it.
//
// Mechanism (docs/reliability.md, "Threads"): a fixed pool of buffers
// allocated up front, a reader count per buffer and the index of the latest
// buffer, all guarded by one mutex that is held only to pick or release a
// buffer (never while copying or reading a map). The writer copies into a
// buffer that is neither the latest nor held, outside the lock, then makes it
// the latest. Publishing therefore allocates nothing, and readers never
// block the writer for longer than a pointer update. With R readers that each
// hold at most one snapshot at a time, R + 2 buffers guarantee that a free
// buffer always exists; with fewer, a publish that finds none is skipped and
// counted (the readers keep seeing the previous snapshot, still consistent).
//
// One writer thread; any number of reader threads.
#include <cstddef>
#include <cstdint>
#include <limits>
#include <memory>
#include <mutex>
#include <vector>

#include "stridemap/core/grid_map.hpp"
#include "stridemap/core/pose.hpp"

namespace stridemap {

class TerrainMapper;

/// The map as it was after one scan, with where and when that scan was.
struct PublishedMap {
  ElevationMap map;
  /// 1 for the first snapshot published, then +1 per publish.
  std::uint64_t sequence = 0;
  /// Scans the mapper had been given (accepted or not) at publication.
  std::size_t scans = 0;
  /// Time and pose of the last accepted scan; NaN time when none carried one.
  double time_s = std::numeric_limits<double>::quiet_NaN();
  TrunkPose pose{};
};

class MapPublisher;

/// A reader's hold on one snapshot: the writer does not reuse its buffer
/// until the handle is destroyed or reset. Movable, not copyable; empty
/// (false) before the first publish.
class PublishedMapHandle {
 public:
  PublishedMapHandle() = default;
  PublishedMapHandle(PublishedMapHandle&& other) noexcept;
  PublishedMapHandle& operator=(PublishedMapHandle&& other) noexcept;
  PublishedMapHandle(const PublishedMapHandle&) = delete;
  PublishedMapHandle& operator=(const PublishedMapHandle&) = delete;
  ~PublishedMapHandle() { reset(); }

  explicit operator bool() const { return snapshot_ != nullptr; }
  const PublishedMap& operator*() const { return *snapshot_; }
  const PublishedMap* operator->() const { return snapshot_; }
  const PublishedMap* get() const { return snapshot_; }
  /// Lets the buffer go (the handle becomes empty).
  void reset();

 private:
  friend class MapPublisher;
  PublishedMapHandle(const MapPublisher* publisher, std::size_t buffer, const PublishedMap* snapshot)
      : publisher_(publisher), buffer_(buffer), snapshot_(snapshot) {}

  const MapPublisher* publisher_ = nullptr;
  std::size_t buffer_ = 0;
  const PublishedMap* snapshot_ = nullptr;
};

class MapPublisher {
 public:
  /// Allocates `buffers` maps of the grid's size. Throws InputError for an
  /// unusable grid or fewer than 2 buffers.
  explicit MapPublisher(const GridOptions& grid, std::size_t buffers = 3);
  ~MapPublisher();
  MapPublisher(const MapPublisher&) = delete;
  MapPublisher& operator=(const MapPublisher&) = delete;

  // Writer side (one thread).

  /// Copies the mapper's map, totals, last time and pose into a free buffer
  /// and publishes it. Returns false (and counts it) when every buffer but
  /// the latest is held by readers. Allocates nothing. Throws InputError when
  /// the map's size differs from the buffers'.
  bool publish(const TerrainMapper& mapper);
  /// The same with the map as its reader gets it (MappingPipeline::map(),
  /// whose derived layers mapper.map() may hold as of an earlier scan).
  bool publish(const TerrainMapper& mapper, const ElevationMap& map);
  /// Two steps, for a writer that prepares the snapshot further (e.g. runs
  /// the fill-in of eq. 11 on it, so that the mapper's own map stays
  /// unfilled): begin_publish() returns a free buffer to write (nullptr,
  /// counted as skipped, when there is none), commit_publish() publishes it.
  /// The buffer still holds an older snapshot: overwrite every member.
  PublishedMap* begin_publish();
  void commit_publish();

  // Reader side (any thread).

  /// The latest snapshot, held until the handle goes (empty before the
  /// first publish). Takes the lock for a few instructions.
  PublishedMapHandle latest() const;

  /// Snapshots published / publishes skipped for want of a free buffer.
  std::uint64_t published() const;
  std::uint64_t skipped() const;
  std::size_t buffer_count() const { return buffers_.size(); }

 private:
  friend class PublishedMapHandle;
  struct Buffer {
    PublishedMap snapshot;
    std::size_t readers = 0;  // guarded by mutex_
  };
  void release(std::size_t buffer) const;

  mutable std::mutex mutex_;
  std::vector<std::unique_ptr<Buffer>> buffers_;  // fixed after construction
  static constexpr std::size_t kNone = std::numeric_limits<std::size_t>::max();
  std::size_t latest_ = kNone;   // guarded by mutex_
  std::size_t writing_ = kNone;  // writer thread only
  std::uint64_t published_ = 0;  // guarded by mutex_
  std::uint64_t skipped_ = 0;    // guarded by mutex_
};

}  // namespace stridemap
