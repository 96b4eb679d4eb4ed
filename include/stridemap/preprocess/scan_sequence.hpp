#pragma once
// Scan-sequence analysis (paper section 5.3, Fig. 14, eq. 12; algorithms.md
// 2.6): when the downward-tilted scan plane crosses a sharp edge across the
// scan (the top edge of a box ahead), the phase-shift sensor returns a large
// group of mixed points that extends the real structure, too big for range
// clustering. Three consecutive scans decide: edges found as co-linear groups
// in scan k-1 define angular sectors; in each sector the spread of scan k along
// the line of sight is compared with the spread of scan k+1, and if scan k is
// much more scattered, all its points in the sector are dropped.
//
// The filter is a stream with ONE SCAN OF DELAY: scan k can only be judged
// once scan k+1 has arrived, so push(scan k+1) returns scan k.
#include <cstddef>
#include <cstdint>
#include <vector>

#include "stridemap/core/planar_scan.hpp"
#include "stridemap/preprocess/line_extraction.hpp"
#include "stridemap/preprocess/scan_checks.hpp"

namespace stridemap {

/// The axis of the scan plane along which eq. 12 measures the spread.
enum class SpreadAxis : std::uint8_t {
  /// Normal of the edge line found in scan k-1. The scan plane meets every
  /// horizontal surface in lines parallel to that edge, so a clean scan k+1
  /// (the floor behind, or the top again) has almost no spread along it
  /// whatever the edge's bearing, while mixed points strewn between the
  /// edge and the background do.
  edge_normal,
  /// The sensor's forward axis: eq. 12 as printed (the paper's y_s, which
  /// points forward in its Fig. 14). The same as edge_normal for an edge
  /// square to the boresight; off to the side, an edge seen obliquely
  /// spreads along it even when clean.
  sensor_forward,
  /// The line of sight through the segment's centroid: a clean line across
  /// a sector off the boresight spreads along it by its length times the
  /// sine of its bearing.
  line_of_sight,
};

/// The between-scans test (ours): a phase-shift sensor whose
/// footprint straddles two surfaces reads a range between them. When the
/// scan line crosses an edge between one scan and the next (the top of a
/// box, then the floor behind it), the same beam reads the near surface in
/// scan k-1, the far one in scan k+1, and, if its footprint straddled the
/// edge in scan k, something in between. So a beam of scan k is mixed when
/// its readings in scans k-1 and k+1 differ by a depth jump and its own
/// reading lies between them, clear of both. Unlike eq. 12 this does not
/// need the mixed row to scatter: a co-linear row of in-between readings
/// along an edge square to the scan line is caught as well.
struct BetweenScansOptions {
  /// Off: the paper's scan-sequence analysis only.
  bool enabled = false;
  /// The readings of the beam in scans k-1 and k+1 must differ by more
  /// than this [m]. 0.04 m: above what a clean vertical face ahead gives
  /// over two scans (the range shrinks by about 1.2-1.7 times the travel
  /// per scan at the paper's mount: 2.4-3.4 cm at the rail's 1 cm), below
  /// the jump at any box top edge worth mapping (a 3 cm step seen at 35-55
  /// deg depression gives 4-5 cm). Chosen on seed 1's random scenes
  /// (docs/experiments.md).
  double min_jump_m = 0.04;
  /// The reading of scan k must lie more than this many sigma_r (the
  /// scan-sequence filter's `lines.sigma`) inside the interval, from both
  /// ends: 3 sigma_r = Delta r, the range accuracy (10 mm below 1 m), with
  /// the default sigma model. Chosen on seed 1's random scenes from 3, 4
  /// and 6 (docs/experiments.md).
  double margin_sigmas = 3.0;

  /// Throws InputError naming the field when an option is out of range.
  void validate(const char* owner) const;
};

struct ScanSequenceOptions {
  /// Co-linear groups in scan k-1 (split-and-merge); its sigma model is also
  /// the one used for sigma_0 below.
  LineExtractionOptions lines;
  /// A segment looks like an edge across the scan when it meets the beams
  /// through both of its end points at 90 deg +- this [rad] (so a long floor
  /// line reaching grazing angles at its ends does not qualify). 60 deg: a
  /// step 0.4 m wide seen 0.35 m away in the scan plane meets the beams at
  /// its ends 33 deg off square, and the occluding-end test below already
  /// keeps plain floor out (algorithms.md 2.6 proposed 30 deg).
  double max_edge_tilt_rad = 60.0 * 3.14159265358979323846 / 180.0;
  /// Also require a range jump at one end of the segment with the segment in
  /// front (it occludes something): without it a plain floor counts as an edge.
  bool require_occluding_end = true;
  /// Beams added on each side of the segment's index range to form the
  /// sector whose points are removed (algorithms.md 2.6: 5), so that mixed
  /// points trailing just past the structure's ends go too.
  std::size_t sector_margin_beams = 5;
  /// Beams added on each side of the segment's index range for the spreads of
  /// eq. 12. 0 by default: with a margin, a clean scan k+1 whose sector reaches
  /// past the structure's ends picks up the range jump to the background, its
  /// spread then measures that jump instead of the structure, and the test
  /// goes blind exactly at box edges.
  std::size_t spread_margin_beams = 0;
  /// Axis of eq. 12's spread.
  SpreadAxis spread_axis = SpreadAxis::edge_normal;
  /// kappa: scan k is "much more scattered" when sigma_k > kappa * sigma_{k+1} + sigma_0.
  double spread_ratio = 3.0;
  /// sigma_0 = spread_floor_sigmas * sigma_r (mean sigma_r of the sector in
  /// scan k+1); keeps the test quiet on flat sectors.
  double spread_floor_sigmas = 2.0;
  /// Both sectors need at least this many valid points for a decision.
  std::size_t min_sector_points = 5;
  /// Eq. 12's test (the paper's). Off leaves only the between-scans test
  /// (ScanFilterChain turns it off for a chain with "between-scans" but
  /// without "scan-sequence").
  bool spread_test = true;
  /// The between-scans test, off by default (the paper's filter).
  BetweenScansOptions between_scans{};

  /// Throws InputError naming the field when an option is out of range.
  void validate() const;
};

/// A sector that the last judged scan was tested on (for inspection/plots).
struct ScanSequenceSector {
  std::size_t first_beam = 0;         ///< removal sector, inclusive (sector_margin_beams included)
  std::size_t last_beam = 0;          ///< inclusive
  std::size_t spread_first_beam = 0;  ///< beams of the spreads (spread_margin_beams included)
  std::size_t spread_last_beam = 0;   ///< inclusive
  std::size_t points_k = 0;    ///< valid points of scan k in the sector
  std::size_t points_next = 0; ///< valid points of scan k+1 in the sector
  double spread_k_m = 0.0;     ///< eq. 12 in scan k [m]
  double spread_next_m = 0.0;  ///< eq. 12 in scan k+1 [m]
  double threshold_m = 0.0;    ///< kappa * spread_next + sigma_0 [m]
  bool removed = false;        ///< scan k's sector points were dropped
};

/// Streaming filter. Keeps copies of up to three scans (k-1, k, k+1) in
/// buffers that are reused, so the per-scan path allocates nothing once they
/// have grown.
///
/// - push(s): the first scan of a stream is only stored (returns false).
///   Every later push returns the previous scan, filtered, in `out`.
/// - The first scan of a stream has no scan k-1 and is returned unfiltered
///   (only unusable ranges are set to NaN).
/// - flush(out): returns the held last scan (true) or nothing (false). It has
///   no scan k+1 to compare with, so it is returned unfiltered; the stream then
///   ends and the next push starts a new one.
/// - All scans of a stream must have the same beam count: a scan of another
///   length throws InputError naming both lengths and the scan's index in the
///   stream; the stream is left as it was (flush() or reset() to start over).
/// - Empty and all-invalid scans pass through (nothing to judge).
/// - `out` may be the same object as the pushed scan.
class ScanSequenceFilter {
 public:
  explicit ScanSequenceFilter(const ScanSequenceOptions& options = {});

  const ScanSequenceOptions& options() const { return options_; }

  /// Takes scan k+1; returns true and writes scan k (filtered) to `out`, with
  /// removed[i] = 1 for the beams this filter dropped, once there is a scan k.
  bool push(const PlanarScan& next_scan, PlanarScan& out, std::vector<std::uint8_t>& removed);
  bool push(const PlanarScan& next_scan, PlanarScan& out);
  /// push() for a scan that prepare_scan_for_filter has already passed, its
  /// only invalid ranges `invalid_input` NaNs (a chain's work scan): the
  /// same result without checking, copying and rewriting it again. Takes
  /// the scan's contents, leaving it another scan's buffers. `breaks`, when
  /// given, is range clustering's test on this scan before its removals,
  /// kept for the line extraction two pushes later (LineExtractor::extract).
  bool push_prepared(PlanarScan& next_scan, std::size_t invalid_input, PlanarScan& out,
                     std::vector<std::uint8_t>& removed, const RangeBreaks* breaks = nullptr);

  /// Ends the stream: returns the held scan (unfiltered) if there is one.
  bool flush(PlanarScan& out, std::vector<std::uint8_t>& removed);
  bool flush(PlanarScan& out);

  /// Forgets all held scans (starts a new stream).
  void reset();

  /// Number of scans the output lags behind the input.
  static constexpr std::size_t delay_scans = 1;

  /// Statistics and sectors of the scan returned last.
  const ScanFilterStats& last_stats() const { return last_stats_; }
  const std::vector<ScanSequenceSector>& last_sectors() const { return sectors_; }
  /// Of the scan returned last, 1 where the between-scans test removed the
  /// beam and eq. 12 did not (a subset of the push's `removed`).
  const std::vector<std::uint8_t>& last_removed_between_scans() const { return between_removed_; }

 private:
  void check_length(const PlanarScan& next_scan) const;
  bool take_incoming(std::size_t incoming_invalid, PlanarScan& out, std::vector<std::uint8_t>& removed);
  void judge_held_scan(std::vector<std::uint8_t>& removed);
  void judge_spread(std::vector<std::uint8_t>& removed);
  void judge_between_scans(std::vector<std::uint8_t>& removed);
  void emit_held_scan(PlanarScan& out);

  ScanSequenceOptions options_;
  LineExtractor lines_;
  BeamDirections directions_k_;     // of held_
  BeamDirections directions_next_;  // of incoming_
  PlanarScan previous_;  // k-1, as returned (filtered)
  PlanarScan held_;      // k, waiting for k+1
  PlanarScan incoming_;  // k+1
  RangeBreaks previous_breaks_;  // what push_prepared was given with each
  RangeBreaks held_breaks_;
  RangeBreaks incoming_breaks_;
  bool has_previous_ = false;
  bool has_held_ = false;
  std::size_t scans_in_stream_ = 0;
  std::size_t held_invalid_input_ = 0;
  std::size_t removed_count_ = 0;  // beams the last judgement marked
  ScanFilterStats last_stats_;
  std::vector<LineSegment> segments_;
  std::vector<ScanSequenceSector> sectors_;
  std::vector<std::uint8_t> between_removed_;
  std::vector<std::uint8_t> jumps_;  // the between-scans test's candidates
  std::vector<std::uint8_t> scratch_removed_;  // mask of the push/flush overloads without one
  std::vector<std::uint8_t> normalize_mask_;   // unused output of prepare_scan_for_filter
};

}  // namespace stridemap
