#include "stridemap/pipeline/tagged_scan_filter.hpp"

#include <stdexcept>
#include <utility>

#include "stridemap/core/error.hpp"

namespace stridemap {

TaggedScanFilter::TaggedScanFilter(std::vector<ScanFilterKind> stages, const ScanFilterChainOptions& options)
    : chain_(std::move(stages), options) {}

bool TaggedScanFilter::push(const PlanarScan& scan, const TrunkPose& pose, std::span<const std::uint8_t> beam_tags,
                            PlanarScan& out) {
  incoming_.pose = pose;
  incoming_.beam_tags.assign(beam_tags.begin(), beam_tags.end());  // in place once grown
  incoming_.sequence = pushed_++;
  bool ready = false;
  try {
    ready = chain_.push(scan, out);
  } catch (const InputError&) {
    reset();
    throw;
  }
  if (chain_.delay_scans() == 0) {
    std::swap(output_, incoming_);
    return ready;
  }
  if (ready) std::swap(output_, held_);
  std::swap(held_, incoming_);
  holding_ = true;
  return ready;
}

void TaggedScanFilter::pass(const TrunkPose& pose, std::span<const std::uint8_t> beam_tags) {
  if (chain_.stage_count() != 0) throw std::logic_error("TaggedScanFilter::pass: the chain has stages");
  output_.pose = pose;
  output_.beam_tags.assign(beam_tags.begin(), beam_tags.end());  // in place once grown
  output_.sequence = pushed_++;
}

bool TaggedScanFilter::flush(PlanarScan& out) {
  if (!holding_) return false;
  holding_ = false;
  if (!chain_.flush(out)) return false;
  std::swap(output_, held_);
  return true;
}

void TaggedScanFilter::reset() {
  chain_.reset();
  holding_ = false;
}

}  // namespace stridemap
