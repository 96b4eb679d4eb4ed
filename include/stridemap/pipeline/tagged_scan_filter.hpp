#pragma once
// The scan filter chain with each scan's payload carried through it: the
// pose the scan was taken at and any per-beam tags (e.g. the simulator's
// BeamLabel), so that what comes out of the scan-sequence filter's one-scan
// delay is the scan together with its own pose and tags, as a batch carries
// its time and origin through Cartographer's points pipeline. This is the
// only place where scans and poses are paired again after a delay.
#include <cstddef>
#include <cstdint>
#include <span>
#include <vector>

#include "stridemap/core/planar_scan.hpp"
#include "stridemap/core/pose.hpp"
#include "stridemap/preprocess/scan_filter_chain.hpp"

namespace stridemap {

/// What travels with a scan.
struct ScanPayload {
  TrunkPose pose{};
  /// One per beam, the caller's meaning (empty when not given). The
  /// filters never look at them.
  std::vector<std::uint8_t> beam_tags;
  /// Number of the scan among those pushed (0 for the first).
  std::size_t sequence = 0;
};

class TaggedScanFilter {
 public:
  /// Throws InputError as ScanFilterChain does.
  explicit TaggedScanFilter(std::vector<ScanFilterKind> stages, const ScanFilterChainOptions& options = {});

  /// Takes the next scan and its payload. Returns true with a filtered scan
  /// in `out` and that scan's payload in output() (the same scan without
  /// scan-sequence, the previous one with it). Throws InputError as
  /// ScanFilterChain::push does; the held scan is then dropped.
  bool push(const PlanarScan& scan, const TrunkPose& pose, std::span<const std::uint8_t> beam_tags,
            PlanarScan& out);
  /// A scan that an empty chain would hand back unchanged at once (no
  /// stages, so no delay): records its payload as push() would, so that a
  /// caller may skip the chain and its copies. Throws std::logic_error when
  /// the chain has stages.
  void pass(const TrunkPose& pose, std::span<const std::uint8_t> beam_tags);
  /// Ends the stream: the held scan, if any, with its payload.
  bool flush(PlanarScan& out);
  /// Drops any held scan.
  void reset();

  std::size_t delay_scans() const { return chain_.delay_scans(); }
  bool holding() const { return holding_; }
  /// The payload of the scan returned last.
  const ScanPayload& output() const { return output_; }
  /// Stage masks and stats of the scan returned last.
  const ScanFilterChain& chain() const { return chain_; }

 private:
  ScanFilterChain chain_;
  ScanPayload incoming_, held_, output_;
  std::size_t pushed_ = 0;
  bool holding_ = false;
};

}  // namespace stridemap
