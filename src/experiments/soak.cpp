#include "stridemap/experiments/soak.hpp"

#include <algorithm>
#include <atomic>
#include <chrono>
#include <utility>
#include <filesystem>
#include <memory>
#include <cmath>
#include <limits>
#include <optional>
#include <thread>

#include "stridemap/core/error.hpp"
#include "stridemap/core/map_integrity.hpp"
#include "stridemap/core/map_publisher.hpp"
#include "stridemap/experiments/process_memory.hpp"
#include "stridemap/mapfile/tile_store.hpp"
#include "stridemap/pipeline/mapping_pipeline.hpp"

namespace stridemap {
namespace {

constexpr double kSoakNaN = std::numeric_limits<double>::quiet_NaN();

void validate(const SoakOptions& o) {
  if (o.scans == 0) throw InputError("soak: scans must be at least 1");
  if (o.publish_every == 0 || o.check_every == 0 || o.checkpoint_every == 0) {
    throw InputError("soak: publish_every, check_every and checkpoint_every must be at least 1");
  }
}

bool due(std::uint64_t index, std::uint64_t every) { return every != 0 && index % every == every - 1; }

// The planner's side: takes the latest snapshot, checks every cell, again
// and again until told to stop. Allocates nothing while the snapshots are
// valid.
class PlannerThread {
 public:
  PlannerThread(const MapPublisher& publisher, double certainty_max)
      : publisher_(publisher), certainty_max_(certainty_max), thread_([this] { run(); }) {}
  ~PlannerThread() { stop(); }
  void stop() {
    done_ = true;
    if (thread_.joinable()) thread_.join();
  }
  std::uint64_t snapshots() const { return snapshots_; }
  std::uint64_t invalid_cells() const { return invalid_; }

 private:
  void run() {
    std::uint64_t last_sequence = 0;
    while (!done_.load()) {
      const PublishedMapHandle snapshot = publisher_.latest();
      if (snapshot && snapshot->sequence != last_sequence) {
        last_sequence = snapshot->sequence;
        invalid_ += check_map_integrity(snapshot->map, certainty_max_).invalid;
        ++snapshots_;
      }
      std::this_thread::sleep_for(std::chrono::microseconds(200));
    }
  }
  const MapPublisher& publisher_;
  double certainty_max_;
  std::atomic<bool> done_{false};
  std::atomic<std::uint64_t> snapshots_{0}, invalid_{0};
  std::thread thread_;
};

// The publisher's buffers get every layer the pipeline's map holds, those
// it adds itself (the foothold layers) too: copying a snapshot into a buffer
// then never allocates, however late the run first uses that buffer.
GridOptions grid_with_every_layer(const ElevationMap& map, GridOptions grid) {
  const ElevationMap declared(grid);
  for (std::size_t k = 0; k < map.layer_count(); ++k) {
    if (!declared.find_layer(map.layer_spec(k).name)) grid.extra_layers.push_back(map.layer_spec(k));
  }
  return grid;
}

class SoakRun {
 public:
  SoakRun(const Scene& scene, const SoakMotion& motion, const SoakOptions& options)
      : options_(options),
        motion_(motion),
        simulator_(scene, options.urg, options.sim, options.seed),
        pipeline_(pipeline_options(options)),
        publisher_(grid_with_every_layer(pipeline_.mapper().map(), options.mapper.grid)),
        fill_(options.fill) {
    result_.motion = motion.describe();
    // The only growth of the run, up front: one record per checkpoint.
    result_.checkpoints.reserve(options.scans / options.checkpoint_every + 2);
    if (!options.global_map.folder.empty()) {
      io::MapFileMetadata metadata;
      metadata.created_by = "soak (simulated)";
      tiles_ = std::make_unique<io::TileStore>(options.global_map, pipeline_.mapper().map(), metadata);
      pipeline_.set_window_listener(tiles_.get());
    }
  }

  SoakResult run(const std::function<void(const SoakCheckpoint&)>& on_checkpoint) {
    const auto start = std::chrono::steady_clock::now();
    std::optional<PlannerThread> planner;
    if (options_.reader_thread) planner.emplace(publisher_, options_.mapper.update.certainty_max);
    for (std::uint64_t k = 0; k < options_.scans; ++k) {
      step(k);
      if (due(k, options_.checkpoint_every) || k + 1 == options_.scans) checkpoint(k + 1, on_checkpoint);
      if (options_.progress) options_.progress(k + 1, options_.scans);
    }
    if (planner) {
      planner->stop();
      result_.reader_snapshots = planner->snapshots();
      result_.reader_invalid_cells = planner->invalid_cells();
    }
    result_.scans_simulated = options_.scans;
    result_.totals = pipeline_.mapper().totals();
    result_.published = publisher_.published();
    result_.publishes_skipped = publisher_.skipped();
    result_.path_extent_x_m = max_x_ - min_x_;
    result_.path_extent_y_m = max_y_ - min_y_;
    if (tiles_) check_global_map();
    result_.wall_time_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    return std::move(result_);
  }

 private:
  void step(std::uint64_t k) {
    TrunkPose truth, estimate;
    motion_.pose_at(k, truth, estimate);
    track_path(truth);
    if (due(k, options_.faults.nan_pose_every)) estimate.roll_rad = kSoakNaN;
    simulator_.scan(truth, options_.mount, static_cast<double>(k) * options_.urg.scan_period_s, raw_);
    const ScanOutcome out = pipeline_.add(raw_, estimate);
    if (!out.integrated) return;  // the scan-sequence filter holds the first scan
    // The scan that reached the map and the pose it was taken at.
    const PlanarScan& scan = pipeline_.integrator().last_scan();
    const TrunkPose pose = pipeline_.integrator().filters().output().pose;
    // Counted when handed over: the filters may still hold the last scan.
    if (!pose_is_finite(pose)) ++result_.injected_nan_poses;
    const bool accepted = count(out.stats);
    // Faults only on scans that went in, so that each is counted once, by
    // the rule meant to catch it.
    if (accepted && due(k, options_.faults.duplicate_every)) {
      count(pipeline_.mapper().integrate(scan, pose));
      ++result_.injected_duplicates;
    }
    if (accepted && previous_accepted_ && due(k, options_.faults.out_of_order_every)) {
      count(pipeline_.mapper().integrate(previous_, previous_pose_));
      ++result_.injected_out_of_order;
    }
    previous_ = scan;  // same sizes: copies in place
    previous_pose_ = pose;
    previous_accepted_ = accepted;
    if (due(k, options_.check_every)) check(pipeline_.map());
    if (due(k, options_.publish_every)) publish();
  }

  static PipelineOptions pipeline_options(const SoakOptions& o) {
    PipelineOptions p;
    p.sensor = SensorKind::urg;
    p.urg = o.urg;
    p.filters = o.filters;
    p.mapper = o.mapper;
    p.map_filter = {MapFilter::fill, o.fill, {}};
    p.mount = o.mount;
    return p;
  }

  // Writes the window into the tiles and reads every tile back.
  void check_global_map() {
    tiles_->flush(pipeline_.map());
    SoakGlobalMap& g = result_.global_map;
    g.enabled = true;
    for (const io::TileIndex& t : tiles_->tiles_on_disk()) {
      const std::string path = tiles_->tile_path(t);
      const io::MapFile tile = io::load_map_file(path);
      const MapIntegrity integrity = check_map_integrity(tile.map, options_.mapper.update.certainty_max);
      if (!integrity.ok() && g.invalid_on_disk == 0) g.first_invalid = path + ": " + integrity.first_problem;
      g.invalid_on_disk += integrity.invalid;
      g.measured_on_disk += integrity.measured;
      g.bytes_on_disk += static_cast<std::uint64_t>(std::filesystem::file_size(path));
    }
    const io::TileStoreStats& s = tiles_->stats();
    g.tiles_on_disk = tiles_->tiles_on_disk().size();
    g.tiles_written = s.tiles_written;
    g.tiles_read = s.tiles_read;
    g.cells_restored = s.cells_restored;
    g.first_measured = first_measured_;
  }

  // Accounts for one scan the mapper was given; true when it went in.
  bool count(const ScanStats& stats) {
    ++result_.scans_to_mapper;
    first_measured_ += stats.first;
    result_.cells_reset_by_moves += stats.cells_reset_by_move;
    const bool rejected = stats.pose_rejected || stats.time_rejected;
    if (rejected) result_.beams_of_rejected_scans += stats.beams;
    return !rejected;
  }

  void publish() {
    PublishedMap* snapshot = publisher_.begin_publish();
    if (snapshot == nullptr) return;  // counted by the publisher
    snapshot->map = pipeline_.map();
    snapshot->scans = pipeline_.mapper().totals().scans;
    snapshot->time_s = pipeline_.mapper().last_scan_time_s().value_or(kSoakNaN);
    snapshot->pose = pipeline_.mapper().last_pose().value_or(TrunkPose{});
    fill_.apply(snapshot->map);
    check(snapshot->map);
    publisher_.commit_publish();
  }

  void check(const ElevationMap& map) {
    const MapIntegrity integrity = check_map_integrity(map, options_.mapper.update.certainty_max);
    ++result_.integrity_checks;
    if (!integrity.ok() && result_.invalid_cells == 0) result_.first_invalid = integrity.first_problem;
    result_.invalid_cells += integrity.invalid;
    measured_cells_ = integrity.measured;
  }

  void track_path(const TrunkPose& truth) {
    if (have_truth_) result_.path_length_m += std::hypot(truth.x_m - last_x_, truth.y_m - last_y_);
    last_x_ = truth.x_m;
    last_y_ = truth.y_m;
    min_x_ = have_truth_ ? std::min(min_x_, truth.x_m) : truth.x_m;
    max_x_ = have_truth_ ? std::max(max_x_, truth.x_m) : truth.x_m;
    min_y_ = have_truth_ ? std::min(min_y_, truth.y_m) : truth.y_m;
    max_y_ = have_truth_ ? std::max(max_y_, truth.y_m) : truth.y_m;
    have_truth_ = true;
  }

  void checkpoint(std::uint64_t scans, const std::function<void(const SoakCheckpoint&)>& on_checkpoint) {
    SoakCheckpoint c;
    c.scan = scans;
    c.map_hash = map_layers_hash(pipeline_.map());
    if (const PublishedMapHandle snapshot = publisher_.latest()) c.snapshot_hash = map_layers_hash(snapshot->map);
    c.measured_cells = measured_cells_;
    const ProcessMemory memory = process_memory();
    c.heap_in_use_bytes = memory.heap_in_use_bytes;
    c.resident_bytes = memory.resident_bytes;
    if (tiles_) c.global_map_tiles = tiles_->tiles_on_disk().size();
    result_.checkpoints.push_back(c);
    // FNV-1a step over both hashes.
    for (std::uint64_t h : {c.map_hash, c.snapshot_hash}) {
      result_.run_hash = (result_.run_hash ^ h) * 1099511628211ULL;
    }
    if (on_checkpoint) on_checkpoint(c);
  }

  const SoakOptions& options_;
  const SoakMotion& motion_;
  UrgSimulator simulator_;
  MappingPipeline pipeline_;
  MapPublisher publisher_;
  WeightedMedianFill fill_;
  UrgRawScan raw_;
  PlanarScan previous_;
  TrunkPose previous_pose_{};
  bool previous_accepted_ = false;  // the previous scan went in (so its pose is finite)
  std::size_t measured_cells_ = 0;
  std::uint64_t first_measured_ = 0;
  std::unique_ptr<io::TileStore> tiles_;  // on the heap: the mapper points at it
  bool have_truth_ = false;
  double last_x_ = 0, last_y_ = 0, min_x_ = 0, max_x_ = 0, min_y_ = 0, max_y_ = 0;
  SoakResult result_;
};

}  // namespace

std::vector<std::string> SoakResult::failures() const {
  std::vector<std::string> out;
  const auto expect = [&](bool ok, const std::string& what) {
    if (!ok) out.push_back(what);
  };
  const auto n = [](auto v) { return std::to_string(v); };
  expect(totals.scans == scans_to_mapper,
         "the mapper counted " + n(totals.scans) + " scans, " + n(scans_to_mapper) + " were given to it");
  expect(totals.scans_rejected_for_pose == injected_nan_poses,
         n(totals.scans_rejected_for_pose) + " scans rejected for their pose, " + n(injected_nan_poses) + " injected");
  expect(totals.scans_rejected_for_time == injected_duplicates + injected_out_of_order,
         n(totals.scans_rejected_for_time) + " scans rejected for their time, " +
             n(injected_duplicates + injected_out_of_order) + " injected");
  const std::size_t accounted = totals.integrated + totals.invalid_range + totals.invalid_beam + totals.outside_map;
  expect(totals.beams == accounted + beams_of_rejected_scans,
         n(totals.beams - beams_of_rejected_scans) + " beams in accepted scans, " + n(accounted) +
             " used or counted as rejected");
  expect(invalid_cells == 0, n(invalid_cells) + " invalid cells in " + n(integrity_checks) +
                                 " checks, the first: " + first_invalid);
  expect(reader_invalid_cells == 0, "the planner thread saw " + n(reader_invalid_cells) + " invalid cells");
  expect(publishes_skipped == 0, n(publishes_skipped) + " snapshots not published for want of a free buffer");
  if (global_map.enabled) {
    expect(global_map.invalid_on_disk == 0, n(global_map.invalid_on_disk) +
                                                " invalid cells in the global map's tiles, the first: " +
                                                global_map.first_invalid);
    expect(global_map.measured_on_disk == global_map.first_measured,
           "the global map holds " + n(global_map.measured_on_disk) + " measured cells, the mapper measured " +
               n(global_map.first_measured) + " cells for the first time");
  }
  if (checkpoints.size() >= 2) {
    const SoakCheckpoint& first = checkpoints.front();
    const SoakCheckpoint& last = checkpoints.back();
    // The one thing allowed to grow: the global map's index of the tiles
    // it wrote (a set node per tile, 64 B with malloc's header; 73 B a tile
    // measured over the 1 km soak), bounded by what is on disk.
    constexpr std::size_t kBytesPerTileOnDisk = 128;
    const std::size_t index_growth = kBytesPerTileOnDisk * (last.global_map_tiles - first.global_map_tiles);
    expect(last.heap_in_use_bytes <= first.heap_in_use_bytes + index_growth,
           "heap in use grew from " + n(first.heap_in_use_bytes) + " bytes at scan " + n(first.scan) + " to " +
               n(last.heap_in_use_bytes) + " at scan " + n(last.scan) +
               (index_growth ? " (" + n(index_growth) + " bytes allowed for new tiles)" : ""));
  }
  return out;
}

SoakResult run_soak(const Scene& scene, const SoakMotion& motion, const SoakOptions& options,
                    const std::function<void(const SoakCheckpoint&)>& on_checkpoint) {
  validate(options);
  SoakRun run(scene, motion, options);
  return run.run(on_checkpoint);
}

}  // namespace stridemap
