#include "stridemap/core/map_publisher.hpp"

#include <string>
#include <utility>

#include "stridemap/core/error.hpp"
#include "stridemap/core/terrain_mapper.hpp"

namespace stridemap {

PublishedMapHandle::PublishedMapHandle(PublishedMapHandle&& other) noexcept
    : publisher_(std::exchange(other.publisher_, nullptr)),
      buffer_(other.buffer_),
      snapshot_(std::exchange(other.snapshot_, nullptr)) {}

PublishedMapHandle& PublishedMapHandle::operator=(PublishedMapHandle&& other) noexcept {
  if (this != &other) {
    reset();
    publisher_ = std::exchange(other.publisher_, nullptr);
    buffer_ = other.buffer_;
    snapshot_ = std::exchange(other.snapshot_, nullptr);
  }
  return *this;
}

void PublishedMapHandle::reset() {
  if (publisher_ != nullptr) publisher_->release(buffer_);
  publisher_ = nullptr;
  snapshot_ = nullptr;
}

MapPublisher::MapPublisher(const GridOptions& grid, std::size_t buffers) {
  if (buffers < 2) {
    throw InputError("map publisher: needs at least 2 buffers, got " + std::to_string(buffers));
  }
  const ElevationMap prototype(grid);  // throws InputError for an unusable grid
  buffers_.reserve(buffers);
  for (std::size_t i = 0; i < buffers; ++i) {
    buffers_.push_back(std::make_unique<Buffer>(Buffer{PublishedMap{prototype}, 0}));
  }
}

// Handles must not outlive the publisher; reaching here with readers left
// is the caller's bug, and their handles would dangle either way.
MapPublisher::~MapPublisher() = default;

PublishedMap* MapPublisher::begin_publish() {
  if (writing_ != kNone) return &buffers_[writing_]->snapshot;
  const std::lock_guard<std::mutex> lock(mutex_);
  for (std::size_t i = 0; i < buffers_.size(); ++i) {
    if (i != latest_ && buffers_[i]->readers == 0) {
      // No reader holds it and none can take it (only the latest is handed
      // out), so it is the writer's until commit_publish().
      writing_ = i;
      return &buffers_[i]->snapshot;
    }
  }
  ++skipped_;
  return nullptr;
}

void MapPublisher::commit_publish() {
  if (writing_ == kNone) return;
  const std::lock_guard<std::mutex> lock(mutex_);
  buffers_[writing_]->snapshot.sequence = ++published_;
  latest_ = std::exchange(writing_, kNone);
}

bool MapPublisher::publish(const TerrainMapper& mapper) { return publish(mapper, mapper.map()); }

bool MapPublisher::publish(const TerrainMapper& mapper, const ElevationMap& map) {
  const ElevationMap& shape = buffers_.front()->snapshot.map;
  if (map.cells_per_side() != shape.cells_per_side()) {
    // Copying a map of another size would allocate and break the promise.
    throw InputError("map publisher: the map has " + std::to_string(map.cells_per_side()) +
                     " cells per side, the publisher's buffers " + std::to_string(shape.cells_per_side()));
  }
  PublishedMap* snapshot = begin_publish();
  if (snapshot == nullptr) return false;
  snapshot->map = map;  // same sizes: the vectors copy in place
  snapshot->scans = mapper.totals().scans;
  snapshot->time_s = mapper.last_scan_time_s().value_or(std::numeric_limits<double>::quiet_NaN());
  snapshot->pose = mapper.last_pose().value_or(TrunkPose{});
  commit_publish();
  return true;
}

PublishedMapHandle MapPublisher::latest() const {
  const std::lock_guard<std::mutex> lock(mutex_);
  if (latest_ == kNone) return {};
  Buffer& buffer = *buffers_[latest_];
  ++buffer.readers;
  return PublishedMapHandle(this, latest_, &buffer.snapshot);
}

void MapPublisher::release(std::size_t buffer) const {
  const std::lock_guard<std::mutex> lock(mutex_);
  --buffers_[buffer]->readers;
}

std::uint64_t MapPublisher::published() const {
  const std::lock_guard<std::mutex> lock(mutex_);
  return published_;
}

std::uint64_t MapPublisher::skipped() const {
  const std::lock_guard<std::mutex> lock(mutex_);
  return skipped_;
}

}  // namespace stridemap
