#pragma once
// Run any of the scan filters, alone or as a chain, chosen by name, so that an
// experiment or the CLI can compare them. The chain is a stream like the
// scan-sequence filter: with scan-sequence in it, the output lags the input by
// one scan; without it, push() returns each scan at once.
#include <cstddef>
#include <cstdint>
#include <functional>
#include <map>
#include <memory>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "stridemap/core/planar_scan.hpp"
#include "stridemap/preprocess/range_clustering.hpp"
#include "stridemap/preprocess/scan_checks.hpp"
#include "stridemap/preprocess/scan_sequence.hpp"
#include "stridemap/preprocess/shadow_filter.hpp"
#include "stridemap/preprocess/speckle_filter.hpp"

namespace stridemap {

/// The built-in filters. Names and every other filter (registered at run
/// time, scan_filter_registry.hpp) come from the registry; a registered
/// filter's kind is a value past these. between_scans is the between-scans
/// test of the scan-sequence filter (BetweenScansOptions): a stream with one
/// scan of delay like scan_sequence.
enum class ScanFilterKind : std::uint8_t { range_clustering, scan_sequence, shadow, speckle, between_scans };

/// The registered name: "range-clustering", "scan-sequence", "shadow",
/// "speckle", "between-scans", or a registered filter's.
std::string_view scan_filter_name(ScanFilterKind kind);

/// One registered name; throws InputError listing the valid names.
ScanFilterKind parse_scan_filter_kind(std::string_view name);

/// A comma-separated list of names in order of application, spaces allowed.
/// A registered set's name stands for its filters: "paper" for
/// "range-clustering,scan-sequence" (the paper's combination) and "urg" for
/// "range-clustering,scan-sequence,between-scans" (ours, docs/preprocess.md);
/// "none" alone gives an empty list (no filtering). Throws InputError on an
/// unknown or repeated name or an empty list.
std::vector<ScanFilterKind> parse_scan_filter_list(std::string_view names);
/// The same for names given as separate words (each may hold commas).
std::vector<ScanFilterKind> parse_scan_filter_list(const std::vector<std::string>& names);

/// The list back as text, e.g. "range-clustering,scan-sequence" ("none" if empty).
std::string scan_filter_list_name(const std::vector<ScanFilterKind>& kinds);

/// A registered filter's own options by name (ScanFilterRegistration::parameters).
using ScanFilterParameters = std::map<std::string, double, std::less<>>;

class ScanFilterStage;

struct ScanFilterChainOptions {
  RangeClusteringOptions range_clustering;
  /// Used by the scan-sequence and between-scans stages. The stage list
  /// decides which of its tests run: spread_test is on when "scan-sequence"
  /// is a stage, between_scans.enabled when "between-scans" is; the other
  /// between_scans fields apply.
  ScanSequenceOptions scan_sequence;
  ShadowFilterOptions shadow;
  SpeckleFilterOptions speckle;
  /// Options of registered filters without a struct here, by filter name;
  /// unset ones take the registration's defaults.
  std::map<std::string, ScanFilterParameters, std::less<>> parameters;
};

class ScanFilterChain {
 public:
  /// Stages apply in the order given. Throws InputError on a repeated or
  /// unregistered kind, scan-sequence and between-scans not next to each
  /// other (they judge the same three scans in one pass), invalid options
  /// (the built-in filters' always, a registered filter's when it is a
  /// stage) or a parameter its filter does not have.
  explicit ScanFilterChain(std::vector<ScanFilterKind> stages, const ScanFilterChainOptions& options = {});
  ~ScanFilterChain();
  ScanFilterChain(ScanFilterChain&&) noexcept;
  ScanFilterChain& operator=(ScanFilterChain&&) noexcept;

  std::size_t stage_count() const { return stages_.size(); }
  ScanFilterKind stage(std::size_t index) const { return stages_.at(index); }
  /// 1 when scan-sequence or between-scans is a stage, else 0.
  std::size_t delay_scans() const { return has_scan_sequence_ ? 1 : 0; }

  /// Takes the next scan; returns true with a filtered scan in `out` (the same
  /// scan without scan-sequence, the previous one with it). Throws InputError
  /// on a malformed scan, or a length change within a stream with scan-sequence.
  bool push(const PlanarScan& scan, PlanarScan& out);
  /// Ends the stream: returns the held scan if any (see ScanSequenceFilter).
  bool flush(PlanarScan& out);
  /// Drops any held scan.
  void reset();

  /// For the scan returned last: removed_by_stage(s)[i] = 1 when stage s
  /// removed beam i (each removed beam is marked by exactly one stage).
  const std::vector<std::uint8_t>& removed_by_stage(std::size_t stage) const;
  /// For the scan returned last: what each stage did.
  const ScanFilterStats& stats_of_stage(std::size_t stage) const;
  /// For the scan returned last: 1 where any stage removed the beam.
  const std::vector<std::uint8_t>& removed_by_any() const { return removed_any_; }

 private:
  static constexpr std::size_t absent = static_cast<std::size_t>(-1);
  struct StageMasks {
    std::vector<std::vector<std::uint8_t>> removed;  // one per stage
    std::vector<ScanFilterStats> stats;
  };
  void run_stateless(std::size_t stage, PlanarScan& scan, StageMasks& masks);
  // run_stateless on work_; while `prepared`, work_'s only invalid ranges are
  // its `invalid` NaNs and the built-in stages skip their checks.
  void run_on_work(std::size_t stage, bool& prepared, std::size_t& invalid);
  void finish_output(PlanarScan& out);
  void take_sequence_masks();

  std::vector<ScanFilterKind> stages_;
  bool has_scan_sequence_ = false;
  std::size_t scan_sequence_stage_ = 0;  // the first of scan-sequence and between-scans
  std::size_t after_sequence_stage_ = 0;    // the first stage after both
  std::size_t spread_stage_ = absent;   // scan-sequence's stage
  std::size_t between_stage_ = absent;  // between-scans' stage
  ScanSequenceFilter scan_sequence_;
  // The range-clustering stage's filter, held here (not in stateless_) for its checked-scan entry.
  std::optional<RangeClusteringFilter> range_clustering_;
  // One per stage, built by its registration; empty for the scan-sequence stages.
  std::vector<std::unique_ptr<ScanFilterStage>> stateless_;
  PlanarScan work_;
  StageMasks incoming_;  // stages before scan-sequence, for the scan just pushed
  StageMasks held_;      // the same for the scan scan-sequence holds
  StageMasks output_;    // for the scan returned last
  std::vector<std::uint8_t> sequence_removed_;
  std::vector<std::uint8_t> normalize_mask_;
  std::vector<std::uint8_t> removed_any_;
};

}  // namespace stridemap
