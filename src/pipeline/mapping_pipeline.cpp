#include "stridemap/pipeline/mapping_pipeline.hpp"

#include <utility>

#include "stridemap/core/cas_filter.hpp"
#include "stridemap/core/weighted_median_fill.hpp"
#include "stridemap/pipeline/height_fusion_observer.hpp"

namespace stridemap {
namespace {

double time_of(const UrgRawScan& s) { return s.time_s; }
double time_of(const StripeFrame& s) { return s.time_s; }
double time_of(const PointFrame& s) { return s.time_s; }

// Copies into the variant, into the vectors it already holds when it holds
// the same kind (their capacity is reused).
template <typename T, typename Variant>
void assign(Variant& slot, const T& value) {
  if (T* held = std::get_if<T>(&slot)) {
    *held = value;
  } else {
    slot = value;
  }
}

// The fused layers declared in the map options, so that the map is made
// with them and mapping allocates nothing for them.
PipelineOptions with_fused_layers(PipelineOptions options) {
  if (options.height_fusion.enabled) declare_height_fusion_layers(options.mapper.grid);
  return options;
}

}  // namespace

MappingPipeline::MappingPipeline(const PipelineOptions& options)
    : options_(with_fused_layers(options)), mapper_(options_.mapper, options_.mount), integrator_(options_) {
  // Invalid map-filter options fail now, not at the first save.
  switch (options_.map_filter.filter) {
    case MapFilter::none: break;
    case MapFilter::fill: (void)WeightedMedianFill(options_.map_filter.fill); break;
    case MapFilter::cas: (void)CasFilter(options_.map_filter.cas); break;
  }
  if (options_.foothold.enabled) {
    foothold_.emplace(mapper_.map(), options_.foothold);
    foothold_->recompute_all(mapper_.map());
  }
  if (options_.height_fusion.enabled) fusion_ = std::make_unique<HeightFusionObserver>(*this, options_.height_fusion);
}

MappingPipeline::~MappingPipeline() = default;

const HeightFusion* MappingPipeline::height_fusion() const { return fusion_ ? &fusion_->fusion() : nullptr; }

ScanOutcome MappingPipeline::updated(ScanOutcome outcome) {
  if (foothold_) {
    // The layers only read the elevation: not a change the mapper counts
    // (TerrainMapper::changes(), which the visibility clean-up follows).
    foothold_->note(std::as_const(mapper_).map(), mapper_.changed_rows());
    if (options_.foothold.update_every_scan) foothold_->refresh(mapper_.map_without_raising());
  }
  mapper_.clear_changed_cells();
  return outcome;
}

ScanStats MappingPipeline::add_planar(const PlanarScan& scan, const TrunkPose& pose) {
  ++stream_.scans;
  return updated(integrator_.push_planar(scan, pose, mapper_)).stats;
}

void MappingPipeline::refresh_foothold() { refresh_layers(); }

void MappingPipeline::refresh_layers() const {
  // The layers are written, never the elevation: no change the mapper
  // counts. The cast is sound as no pipeline is made const (a const
  // reference to one is what map() is called through).
  if (foothold_) foothold_->refresh(const_cast<TerrainMapper&>(mapper_).map_without_raising());
}

const ElevationMap& MappingPipeline::map() const {
  refresh_layers();
  return mapper_.map();
}

void MappingPipeline::set_window_listener(WindowMoveListener* listener) {
  window_relay_.next = listener;
  // No relay without a listener: a listener makes every window move a
  // change the mapper cannot account for (TerrainMapper::changes()).
  mapper_.set_window_listener(listener ? &window_relay_ : nullptr);
}

void MappingPipeline::LayersBeforeLeaving::window_leaving(const ElevationMap& map, CellIndex new_min) {
  // Every scan before this one is noted (updated()), none of this one's
  // readings is applied yet: the refresh gives the values an eager
  // pipeline left after the previous scan.
  pipeline_.refresh_layers();
  if (next) next->window_leaving(map, new_min);
}

void MappingPipeline::LayersBeforeLeaving::window_entered(ElevationMap& map, CellIndex old_min) {
  if (next) next->window_entered(map, old_min);
}

void MappingPipeline::recompute_foothold() {
  mapper_.clear_changed_cells();
  if (foothold_) foothold_->recompute_all(mapper_.map());
}

ScanOutcome MappingPipeline::add(const UrgRawScan& raw, const TrunkPose& pose,
                                 std::span<const std::uint8_t> beam_tags) {
  ++stream_.scans;
  return updated(integrator_.push(raw, pose, mapper_, beam_tags));
}

ScanOutcome MappingPipeline::add(const StripeFrame& frame, const TrunkPose& pose) {
  ++stream_.scans;
  return updated(integrator_.push(frame.pixels, frame.time_s, pose, mapper_));
}

ScanOutcome MappingPipeline::add(std::span<const StripePixel> pixels, std::optional<double> time_s,
                                 const TrunkPose& pose) {
  ++stream_.scans;
  return updated(integrator_.push(pixels, time_s, pose, mapper_));
}

ScanOutcome MappingPipeline::add(const PointFrame& frame, const TrunkPose& pose) {
  ++stream_.scans;
  return updated(integrator_.push(frame.points_m, frame.height_sigma_m, frame.time_s, pose, mapper_));
}

ScanOutcome MappingPipeline::add(SensorModel& model, double time_s, const TrunkPose& pose) {
  ++stream_.scans;
  return updated(integrator_.push(model, time_s, pose, mapper_));
}

void MappingPipeline::queue(const UrgRawScan& raw, double arrival_s) {
  ++stream_.scans;
  Waiting& slot = queue_.push_slot();
  assign(slot.scan, raw);
  slot.arrival_s = arrival_s;
}

void MappingPipeline::queue(const StripeFrame& frame, double arrival_s) {
  ++stream_.scans;
  Waiting& slot = queue_.push_slot();
  assign(slot.scan, frame);
  slot.arrival_s = arrival_s;
}

void MappingPipeline::queue(const PointFrame& frame, double arrival_s) {
  ++stream_.scans;
  Waiting& slot = queue_.push_slot();
  assign(slot.scan, frame);
  slot.arrival_s = arrival_s;
}

void MappingPipeline::reserve_queue(std::size_t scans, std::size_t values) {
  queue_.reserve(scans, [values](Waiting& slot) {
    if (!std::holds_alternative<UrgRawScan>(slot.scan)) slot.scan = UrgRawScan{};
    std::get<UrgRawScan>(slot.scan).values_mm.reserve(values);
  });
}

ScanOutcome MappingPipeline::integrate(const Scan& scan, const TrunkPose& pose) {
  if (const auto* raw = std::get_if<UrgRawScan>(&scan)) return updated(integrator_.push(*raw, pose, mapper_));
  if (const auto* stripe = std::get_if<StripeFrame>(&scan)) {
    return updated(integrator_.push(stripe->pixels, stripe->time_s, pose, mapper_));
  }
  const auto& points = std::get<PointFrame>(scan);
  return updated(integrator_.push(points.points_m, points.height_sigma_m, points.time_s, pose, mapper_));
}

std::size_t MappingPipeline::process(PoseTrack& poses, bool poses_complete) {
  std::size_t integrated = 0;
  TrunkPose pose;
  while (!queue_.empty()) {
    const Scan& scan = queue_.front().scan;
    const double time_s = std::visit([](const auto& s) { return time_of(s); }, scan);
    switch (poses.interpolate(time_s, pose)) {
      case PoseLookup::ok:
        integrate(scan, pose);
        ++integrated;
        poses.drop_before(time_s);
        break;
      case PoseLookup::before_first: ++stream_.before_first_pose; break;
      case PoseLookup::gap_too_large:
        ++stream_.pose_gap;
        poses.drop_before(time_s);
        break;
      case PoseLookup::empty:
      case PoseLookup::after_last:
        if (!poses_complete) return integrated;
        ++stream_.after_last_pose;
        poses.drop_before(time_s);
        break;
    }
    queue_.pop_front();
  }
  return integrated;
}

std::size_t MappingPipeline::expire(double before_s) {
  std::size_t skipped = 0;
  while (!queue_.empty() && queue_.front().arrival_s <= before_s) {
    queue_.pop_front();
    ++stream_.after_last_pose;
    ++skipped;
  }
  return skipped;
}

ScanOutcome MappingPipeline::finish() { return updated(integrator_.flush(mapper_)); }

MapFilterResult MappingPipeline::apply_map_filter() {
  const MapFilterResult result = stridemap::apply_map_filter(options_.map_filter, mapper_.map());
  recompute_foothold();
  return result;
}

ElevationMap MappingPipeline::filtered_map() const {
  ElevationMap copy = mapper_.map();
  stridemap::apply_map_filter(options_.map_filter, copy);
  if (foothold_) FootholdLayers(copy, options_.foothold).recompute_all(copy);
  return copy;
}

PipelineStats MappingPipeline::stats() const {
  PipelineStats total = integrator_.stats();
  total += stream_;
  return total;
}

}  // namespace stridemap
