#pragma once
// An unbiased height per cell for the robot's own height reference: each
// reading is fused into the cell by its variance (a one-dimensional Kalman
// update), and a reading that lies too many standard deviations from the
// cell (a Mahalanobis gate) is not fused but widens the cell's variance, so
// that a cell contradicted again and again lets the new surface in. The
// idea is that of the elevation_mapping package (Fankhauser et al.); this is
// our own formulation.
//
// Eq. (10)'s highest reading stays the planner's layer: it lies above the
// surface by the range noise, and a robot that reads its h_ref from it
// climbs by that bias at every look-ahead distance it walks
// (docs/experiments.md). The fused layer has no such bias. Its two layers
// are ordinary declared layers (map_layer.hpp), so they move, reset and
// copy with the map.
#include <cmath>
#include <cstddef>

#include "stridemap/core/grid_map.hpp"
#include "stridemap/core/map_layer.hpp"

namespace stridemap {

struct HeightFusionOptions {
  /// Keep the fused layers in a MappingPipeline (and so in `map`, `live`,
  /// Python and the ROS node): off by default, since fusing a scan's points
  /// costs about as much as the update (docs/performance.md). The rocky
  /// walk keeps them whenever its h_ref reads them, whatever this says.
  bool enabled = false;
  /// A reading further than this many standard deviations (of cell and
  /// reading together) from the cell is not fused. 2.5, as elevation_mapping.
  double mahalanobis_gate = 2.5;
  /// What a gated-out reading adds to the cell's variance [m^2]: (4 mm)^2,
  /// so that about ten contradictions in a row open the gate to a 2 cm
  /// change (a rock the cell had not seen) while a lone mixed pixel does not.
  double outlier_variance_m2 = 0.004 * 0.004;
  /// The cell's variance never falls below this [m^2]: (1.5 mm)^2. Without
  /// a floor a cell seen a hundred times would gate out the small shifts a
  /// pose error gives the same surface from the next step.
  double min_variance_m2 = 0.0015 * 0.0015;
  /// A point's height standard deviation is its predicted uncertainty (the
  /// error part of Delta z_max, eq. 6 or 8, a worst-case sum) times this.
  double sigma_per_uncertainty = 1.0 / 3.0;

  /// Throws InputError naming the field for a non-positive or non-finite value.
  void validate() const;
};

/// The fused layers' declarations: "fused_elevation" [m] and
/// "fused_variance" [m^2], NaN until a reading arrives. Not in the planner's
/// default export.
LayerSpec fused_elevation_layer();
LayerSpec fused_variance_layer();

/// Fuses one reading of height `h_m` and variance `variance_m2` into a cell
/// holding `elevation`/`variance` (NaN: no reading yet). Returns true when
/// the reading was fused, false when the gate kept it out.
inline bool fuse_height(float& elevation, float& variance, double h_m, double variance_m2,
                        const HeightFusionOptions& o) {
  if (!(variance == variance)) {
    elevation = static_cast<float>(h_m);
    variance = static_cast<float>(variance_m2 > o.min_variance_m2 ? variance_m2 : o.min_variance_m2);
    return true;
  }
  const double cell_variance = variance, difference = h_m - elevation;
  if (difference * difference > o.mahalanobis_gate * o.mahalanobis_gate * (cell_variance + variance_m2)) {
    variance = static_cast<float>(cell_variance + o.outlier_variance_m2);
    return false;
  }
  const double gain = cell_variance / (cell_variance + variance_m2);
  elevation = static_cast<float>(elevation + gain * difference);
  const double fused = cell_variance * variance_m2 / (cell_variance + variance_m2);
  variance = static_cast<float>(fused > o.min_variance_m2 ? fused : o.min_variance_m2);
  return true;
}

/// The fused layers of one map, found once; then a point costs a slot
/// look-up and fuse_height().
class HeightFusion {
 public:
  /// Declares the two layers in `map` when it does not have them yet
  /// (allocates: call before mapping). Validates the options.
  HeightFusion(ElevationMap& map, const HeightFusionOptions& options = {});

  /// Fuses a point at (x, y) of height h with predicted uncertainty
  /// `height_uncertainty_m`; false when outside the window or gated out.
  bool add(ElevationMap& map, double x_m, double y_m, double h_m, double height_uncertainty_m) const {
    return add(map, layers(map), x_m, y_m, h_m, height_uncertainty_m);
  }

  /// The two layers' cells in `map`, found once for a scan's points.
  struct Layers {
    float* elevation;
    float* variance;
  };
  Layers layers(ElevationMap& map) const { return {map.data(elevation_), map.data(variance_)}; }
  /// add() with the layers already found (layers(map) of the same map, its
  /// layers not added to since).
  bool add(const ElevationMap& map, const Layers& cells, double x_m, double y_m, double h_m,
           double height_uncertainty_m) const {
    std::size_t slot = 0;
    if (!(std::isfinite(h_m) && std::isfinite(height_uncertainty_m)) || !map.slot_at(x_m, y_m, slot)) return false;
    const double sigma = height_uncertainty_m * options_.sigma_per_uncertainty;
    return fuse_height(cells.elevation[slot], cells.variance[slot], h_m, sigma * sigma, options_);
  }

  LayerId<float> elevation_layer() const { return elevation_; }
  LayerId<float> variance_layer() const { return variance_; }
  const HeightFusionOptions& options() const { return options_; }

 private:
  HeightFusionOptions options_;
  LayerId<float> elevation_;
  LayerId<float> variance_;
};

}  // namespace stridemap
