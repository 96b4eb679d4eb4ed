#pragma once
// Range clustering (paper section 5.3, Fig. 12; algorithms.md 2.2): split a
// scan wherever two consecutive ranges could not come from one surface seen at
// an incidence angle up to beta_max, allowing for range noise, and drop the
// clusters too small or too short to be real. Removes the isolated single
// points and small groups that mixed pixels form at thin objects and at edges
// nearly parallel to the beams.
#include <array>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <cstring>
#include <limits>
#include <vector>

#include "stridemap/core/planar_scan.hpp"
#include "stridemap/preprocess/beam_directions.hpp"
#include "stridemap/preprocess/range_sigma.hpp"
#include "stridemap/preprocess/scan_checks.hpp"

namespace stridemap {

/// Bounds on r_{i+1} / r_i for two consecutive beams on one plane.
struct RangeRatioBand {
  double lower_factor = 1.0;  ///< k_lo
  double upper_factor = 1.0;  ///< k_hi (+inf when beta_max + step reaches 90 deg)
};

/// The band for an angular step between two beams (absolute value used).
/// Intended rule: k_lo = cos b / cos(b - step), k_hi = cos b / cos(b + step)
/// with b = beta_max. With `messorsim_swapped_bounds` the factors are computed
/// as MessorSim does (angle 180 deg - beta_max in its formula), which swaps
/// them: the accepted band then shrinks with range instead of growing.
RangeRatioBand range_ratio_band(double angle_step_rad, double max_incidence_angle_rad,
                                bool messorsim_swapped_bounds = false);

/// range_ratio_band for a stream of steps; consecutive steps of a scan are
/// equal up to rounding, so the band is recomputed only when the step changes
/// by more than angle_tolerance_rad (its effect on the band is of that order).
class RangeRatioBandCache {
 public:
  RangeRatioBandCache(double max_incidence_angle_rad, bool messorsim_swapped_bounds)
      : max_incidence_angle_rad_(max_incidence_angle_rad), swapped_(messorsim_swapped_bounds) {}
  static constexpr double angle_tolerance_rad = 1e-9;

  const RangeRatioBand& band(double angle_step_rad) {
    const double step = angle_step_rad < 0.0 ? -angle_step_rad : angle_step_rad;
    if (!(std::abs(step - step_) <= angle_tolerance_rad)) {
      step_ = step;
      band_ = range_ratio_band(step, max_incidence_angle_rad_, swapped_);
    }
    return band_;
  }

 private:
  double max_incidence_angle_rad_;
  bool swapped_;
  double step_ = -1.0;
  RangeRatioBand band_;
};

/// range_ratio_band of exact steps, remembered across scans: the steps
/// between a sensor's beams (one beam, two across a dropout, ...) take a few
/// values, rounded alike scan after scan, so the cosines are computed once.
/// Keyed on the step's bits, it returns what range_ratio_band would, bit for bit.
class RangeRatioBandMemo {
 public:
  RangeRatioBandMemo(double max_incidence_angle_rad, bool messorsim_swapped_bounds)
      : max_incidence_angle_rad_(max_incidence_angle_rad), swapped_(messorsim_swapped_bounds) {
    for (Slot& slot : slots_) slot.step = std::numeric_limits<double>::quiet_NaN();  // matches no step
  }

  const RangeRatioBand& band(double angle_step_rad) {
    const double step = std::abs(angle_step_rad);
    std::uint64_t bits;
    std::memcpy(&bits, &step, sizeof bits);
    Slot& slot = slots_[(bits ^ (bits >> 17) ^ (bits >> 31)) % kSlots];
    if (!(slot.step == step)) {
      slot.step = step;
      slot.band = range_ratio_band(step, max_incidence_angle_rad_, swapped_);
    }
    return slot.band;
  }

 private:
  struct Slot {
    double step;
    RangeRatioBand band;
  };
  static constexpr std::size_t kSlots = 64;
  double max_incidence_angle_rad_;
  bool swapped_;
  std::array<Slot, kSlots> slots_;
};

/// The clustering test: k_lo r - n sigma < r_next < k_hi r + n sigma.
inline bool ranges_on_one_surface(double range_m, double next_range_m, double tolerance_m,
                                  const RangeRatioBand& band) {
  return next_range_m > band.lower_factor * range_m - tolerance_m &&
         next_range_m < band.upper_factor * range_m + tolerance_m;
}

struct RangeClusteringOptions {
  /// beta_max: the most oblique incidence (angle between beam and surface
  /// normal) at which a surface still counts as one surface [rad]. 75 deg is
  /// the value the authors' implementation intends (algorithms.md 2.2); it
  /// equals Borges & Aldon's lambda = 15 deg.
  double max_incidence_angle_rad = 75.0 * 3.14159265358979323846 / 180.0;
  /// Range noise allowance in standard deviations (the "3 sigma" of the test).
  double noise_sigmas = 3.0;
  /// Turns a beam's Delta r into sigma_r.
  RangeSigmaModel sigma;
  /// Clusters with fewer valid points are removed. 3: a vertical edge or a
  /// thin object gives one or two mixed beams (the footprint straddles it for
  /// about one step of the mirror), so clusters of one or two go. The
  /// authors' implementation removes clusters of up to 4 (5 here); on the
  /// simulated rail that also removes 3.9 % of the clean beams (grazing floor
  /// far to the sides, broken into short runs) for one point more of mixed
  /// recall (docs/experiments.md, the sweep under "Mixed pixels").
  std::size_t min_cluster_points = 3;
  /// Clusters whose first and last points are closer than this are removed
  /// too [m]; 0 disables the test.
  double min_cluster_extent_m = 0.0;
  /// A cluster runs on over up to this many consecutive invalid beams when
  /// the valid beams either side pass the clustering test for the angle
  /// between them; sizes then count valid beams only. 0 (the default) is the
  /// published rule: any invalid beam ends a cluster. A dark floor far from
  /// the sensor returns runs of a few valid beams between dropouts, which
  /// that rule removes as if they were mixed pixels; 2 keeps them
  /// (docs/preprocess.md). Mixed pixels sit at a jump in range, which
  /// bridging does not cross.
  std::size_t max_bridged_invalid_beams = 0;
  /// Reproduce MessorSim's swapped bounds (for comparison only; see
  /// range_ratio_band).
  bool messorsim_swapped_bounds = false;

  /// Throws InputError naming the field when an option is out of range.
  void validate() const;
};

/// The clustering test between every pair of neighbouring beams of one scan
/// and what decided it, so that a later filter running the same test on the
/// same scan need not run it again. A filter that turns beams NaN breaks
/// their pairs here too (a pair with an unusable beam is never joined), so
/// that the mask stays the test of the scan it hands on.
struct RangeBreaks {
  /// breaks[i] = 1 unless beams i - 1 and i are joined; breaks[0] = 1.
  std::vector<std::uint8_t> breaks;
  RangeRatioBand band;  ///< the one band of every pair
  double noise_sigmas = 0.0;
  RangeSigmaModel sigma;
  /// False when no single band decided the scan: `breaks` is not set.
  bool valid = false;
};

/// Stateless apart from scratch buffers; one object per thread.
class RangeClusteringFilter {
 public:
  explicit RangeClusteringFilter(const RangeClusteringOptions& options = {});

  const RangeClusteringOptions& options() const { return options_; }

  /// Filters `scan` in place: beams of rejected clusters become NaN and get
  /// removed[i] = 1 (the mask is resized to the scan; 0 elsewhere). Invalid
  /// beams (NaN, inf, <= 0) end clusters unless bridged (see
  /// max_bridged_invalid_beams); they are never marked removed. Throws
  /// InputError on a malformed scan.
  ScanFilterStats apply(PlanarScan& scan, std::vector<std::uint8_t>& removed);
  /// apply() for a scan that prepare_scan_for_filter has already passed, its
  /// only invalid ranges `invalid_input` NaNs (a chain's work scan): the same
  /// result without checking and rewriting the scan again.
  ScanFilterStats apply_prepared(PlanarScan& scan, std::vector<std::uint8_t>& removed, std::size_t invalid_input);

  /// Cluster label of each beam from the last apply(): -1 for invalid beams,
  /// otherwise 0, 1, 2, ... in scan order (removed clusters keep their label).
  const std::vector<int>& cluster_labels() const { return labels_; }
  /// Of the last apply(), on the scan it returned (valid only without
  /// bridging, with evenly spaced beams).
  const RangeBreaks& last_breaks() const { return breaks_; }

 private:
  RangeClusteringOptions options_;
  std::vector<int> labels_;
  BeamDirections directions_;  // for its step spread
  RangeRatioBandMemo bands_;
  RangeBreaks breaks_;
};

}  // namespace stridemap
