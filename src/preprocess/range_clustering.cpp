#include "stridemap/preprocess/range_clustering.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>

#include "option_checks.hpp"
#include "range_breaks.hpp"

namespace stridemap {
namespace {

constexpr double half_pi = 1.57079632679489661923;
constexpr const char* clustering_filter_name = "range clustering";

}  // namespace

RangeRatioBand range_ratio_band(double angle_step_rad, double max_incidence_angle_rad,
                                bool messorsim_swapped_bounds) {
  const double step = std::abs(angle_step_rad);
  RangeRatioBand band;
  if (messorsim_swapped_bounds) {
    // MessorSim's formula with its angle of 180 deg - beta_max; cos of that
    // angle is negative, which is what swaps the two factors.
    const double theta = std::numbers::pi - max_incidence_angle_rad;
    band.lower_factor = std::cos(theta + step) / std::cos(theta);
    band.upper_factor = std::cos(theta - step) / std::cos(theta);
    return band;
  }
  const double beta = max_incidence_angle_rad;
  band.lower_factor = std::cos(beta) / std::cos(beta - step);
  // Past 90 deg the next beam can run along the surface: no upper limit.
  band.upper_factor = beta + step < half_pi ? std::cos(beta) / std::cos(beta + step)
                                            : std::numeric_limits<double>::infinity();
  return band;
}

void RangeClusteringOptions::validate() const {
  const char* owner = "RangeClusteringOptions";
  detail::require_angle_in_range(owner, "max_incidence_angle_rad", max_incidence_angle_rad, 0.0, false,
                                 90.0, false);
  detail::require_in_range(owner, "noise_sigmas", noise_sigmas, 0.0, true, 1e6, true);
  detail::require_in_range(owner, "min_cluster_extent_m", min_cluster_extent_m, 0.0, true, 1e6, true, " m");
  sigma.validate(owner);
}

RangeClusteringFilter::RangeClusteringFilter(const RangeClusteringOptions& options)
    : options_(options), bands_(options.max_incidence_angle_rad, options.messorsim_swapped_bounds) {
  options_.validate();
}

ScanFilterStats RangeClusteringFilter::apply(PlanarScan& scan, std::vector<std::uint8_t>& removed) {
  const ScanFilterStats prepared = prepare_scan_for_filter(scan, removed, clustering_filter_name);
  return apply_prepared(scan, removed, prepared.invalid_input);
}

ScanFilterStats RangeClusteringFilter::apply_prepared(PlanarScan& scan, std::vector<std::uint8_t>& removed,
                                                      std::size_t invalid_input) {
  ScanFilterStats stats;
  stats.beams = scan.size();
  stats.invalid_input = invalid_input;
  const std::size_t n = scan.size();
  removed.assign(n, 0);
  labels_.resize(n);
  std::vector<double>& range = scan.range_m;
  const std::vector<double>& angle = scan.angle_rad;
  RangeRatioBandCache bands(options_.max_incidence_angle_rad, options_.messorsim_swapped_bounds);

  // A cluster is [first, last] with `points` valid beams; invalid beams
  // inside it (bridged gaps) are skipped when it is judged and removed.
  const auto close_cluster = [&](std::size_t first, std::size_t last, std::size_t points) -> bool {
    bool reject = points < options_.min_cluster_points;
    if (!reject && options_.min_cluster_extent_m > 0.0) {
      const double r0 = range[first];
      const double r1 = range[last];
      const double chord_sq = r0 * r0 + r1 * r1 - 2.0 * r0 * r1 * std::cos(angle[last] - angle[first]);
      reject = chord_sq < options_.min_cluster_extent_m * options_.min_cluster_extent_m;
    }
    // Removed at once (apply_removal_mask's work): the loop reads only beams after `last`.
    if (reject) {
      for (std::size_t i = first; i <= last; ++i) {
        if (std::isnan(range[i])) continue;
        removed[i] = 1;
        range[i] = std::numeric_limits<double>::quiet_NaN();
        ++stats.removed;
      }
    }
    return reject;
  };

  // Without bridging a cluster is a run of joined neighbours: with one band
  // for the scan, the loop below's tests are made in one pass.
  const RangeRatioBand* band = nullptr;
  if (options_.max_bridged_invalid_beams == 0) {
    directions_.update(angle);
    band = detail::uniform_step_band(scan, directions_, bands_);
  }
  breaks_.valid = band != nullptr;
  if (band != nullptr) {
    detail::mark_range_breaks(scan, *band, options_.noise_sigmas, options_.sigma, breaks_.breaks);
    breaks_.band = *band;
    breaks_.noise_sigmas = options_.noise_sigmas;
    breaks_.sigma = options_.sigma;
    int run_label = -1;
    for (std::size_t i = 0; i < n;) {
      if (std::isnan(range[i])) {
        labels_[i] = -1;
        ++i;
        continue;
      }
      const std::size_t end = detail::run_end(breaks_.breaks, i);
      std::fill(labels_.begin() + static_cast<std::ptrdiff_t>(i), labels_.begin() + static_cast<std::ptrdiff_t>(end),
                ++run_label);
      // A run's beams are all usable: removed, each pair inside it breaks
      // (those at its ends already do).
      if (close_cluster(i, end - 1, end - i)) {
        std::fill(breaks_.breaks.begin() + static_cast<std::ptrdiff_t>(i) + 1,
                  breaks_.breaks.begin() + static_cast<std::ptrdiff_t>(end), std::uint8_t{1});
      }
      i = end;
    }
    return stats;
  }

  constexpr std::size_t none = static_cast<std::size_t>(-1);
  const std::size_t max_gap = options_.max_bridged_invalid_beams;
  std::size_t first = none;
  std::size_t last_valid = none;  // the cluster's last valid beam
  std::size_t points = 0;
  int label = -1;
  for (std::size_t i = 0; i < n; ++i) {
    if (std::isnan(range[i])) {
      labels_[i] = -1;
      if (first != none && i - last_valid > max_gap) {
        close_cluster(first, last_valid, points);
        first = none;
      }
      continue;
    }
    if (first != none) {
      const double tolerance =
          options_.noise_sigmas * options_.sigma.sigma_m(range[last_valid], scan.range_error_m[last_valid]);
      if (!ranges_on_one_surface(range[last_valid], range[i], tolerance,
                                 bands.band(angle[i] - angle[last_valid]))) {
        close_cluster(first, last_valid, points);
        first = none;
      }
    }
    if (first == none) {
      first = i;
      points = 0;
      ++label;
    }
    labels_[i] = label;
    last_valid = i;
    ++points;
  }
  if (first != none) close_cluster(first, last_valid, points);
  return stats;
}

}  // namespace stridemap
