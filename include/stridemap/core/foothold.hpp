#pragma once
// Foothold layers: where a foot can go, derived from the elevation map and
// kept up to date incrementally (only around the cells a scan changed).
// Beyond the paper, which stops at elevation and certainty; docs/foothold.md.
// Each scan is noted (cheap); the values are computed at refresh(), for
// all the scans noted since (MappingPipeline: when the map is read, by default).
//
// Definitions, for a cell p with centre c_p. The footprint F(p) is every
// known cell (finite elevation, state not unknown) of the window whose
// centre lies within foot_radius_m of c_p (p included).
//   slope_deg        angle between the horizontal and the least-squares
//                    plane z = a + b x + c y through the footprint's cell
//                    centres at their elevations: atan(sqrt(b^2 + c^2)) [deg]
//   roughness_m      root mean square of that fit's residuals [m]
//   step_height_m    max minus min elevation over the footprint [m]
//   edge_distance_m  distance between c_p and the nearest cell centre whose
//                    step_height_m exceeds max_step_m (an edge), searched up
//                    to edge_search_radius_m; beyond it, that radius [m]
//   foothold_score   in [0, 1]: the product of
//                      (1 - slope/max_slope), (1 - step/max_step),
//                      (1 - roughness/max_roughness), each clamped to [0, 1],
//                      min(1, edge_distance / edge_clearance) and
//                      min(1, certainty / full_certainty).
// A cell whose own elevation is unknown, or whose footprint holds fewer
// known cells than min_known_fraction of the full disc (and fewer than 3),
// has NaN in every foothold layer: unknown, not unsafe. Cells outside the
// window count as unknown, so a value depends only on the window's cells.
#include <array>
#include <cstddef>
#include <cstdint>
#include <vector>

#include <Eigen/Core>

#include "stridemap/core/cell_box.hpp"
#include "stridemap/core/changed_rows.hpp"
#include "stridemap/core/foothold_changes.hpp"
#include "stridemap/core/foothold_edge_search.hpp"
#include "stridemap/core/foothold_stencil.hpp"
#include "stridemap/core/grid_map.hpp"
#include "stridemap/core/map_layer.hpp"

namespace stridemap {

struct FootholdOptions {
  /// Compute the layers at all.
  bool enabled = true;
  /// MappingPipeline: bring the layers up to date after every scan (true),
  /// or only note what each scan changed and compute when the map is read
  /// (false, the default: MappingPipeline::map(), and before the window's
  /// cells leave for a tile store). Both give the same values bit for bit;
  /// false costs less when the map is read less often than scans arrive (a
  /// planner at 1 Hz, a URG at 10 Hz), true spreads the cost evenly.
  bool update_every_scan = false;
  /// Radius of the foot's footprint [m]: a small hexapod's foot (2 cm);
  /// the paper gives none.
  double foot_radius_m = 0.02;
  /// Steepest plane the foot stands on [deg].
  double max_slope_deg = 30.0;
  /// Highest step within a footprint the foot tolerates; a cell with a
  /// larger step is an edge [m].
  double max_step_m = 0.05;
  /// Plane-fit RMS residual at which the score reaches 0 [m].
  double max_roughness_m = 0.01;
  /// How far the search for the nearest edge reaches [m].
  double edge_search_radius_m = 0.10;
  /// Distance from an edge beyond which it no longer lowers the score [m].
  double edge_clearance_m = 0.04;
  /// Certainty (eq. 9) at which the score stops growing with it: three
  /// plausible readings at the paper's increment a = 3.
  double full_certainty = 9.0;
  /// Share of the footprint's cells that must be known for any value.
  double min_known_fraction = 0.5;
  /// Score at or above which a cell counts as safe (the foothold experiment).
  double safe_score = 0.5;
};

/// Throws InputError naming the field for a non-finite, negative or
/// otherwise unusable option.
void validate_foothold_options(const FootholdOptions& options);

/// The five layers' declarations (f32, reset NaN), in this order.
std::array<LayerSpec, 5> foothold_layer_specs();

/// Keeps a map's foothold layers current. Owns scratch space sized for the
/// map's window (allocated here, never per update).
///
/// Two steps, so that a reader slower than the scans pays once: note() what
/// a scan changed (cheap: row spans merged, window moves tracked), then
/// refresh() recomputes what all the noted changes can have changed. The
/// values after refresh() are those of recompute_all(), bit for bit,
/// however many notes came before it.
///
/// This class orders the steps of a refresh and computes the score; the
/// rest is in parts of their own: the footprint and edge search discs
/// (core/foothold_stencil.hpp), what changed since the last refresh
/// (core/foothold_changes.hpp), the plane fits (src/core/foothold_plane_fit)
/// and the edge search (core/foothold_edge_search.hpp).
class FootholdLayers {
 public:
  /// Adds the layers to `map` unless it has them (a loaded map file may);
  /// throws InputError for bad options or a same-named layer of another type.
  /// The values are computed by the first refresh() or recompute_all().
  FootholdLayers(ElevationMap& map, const FootholdOptions& options);

  /// Records cells a scan changed (global indices; any part outside the
  /// window is ignored) and any move of the window since the last note or
  /// refresh. Allocates nothing, computes nothing.
  void note(const ElevationMap& map, const ChangedRows& changed);
  void note(const ElevationMap& map, const CellBox& changed);
  /// Recomputes what the noted changes can have changed; nothing when
  /// current(). Allocates nothing.
  void refresh(ElevationMap& map);
  /// Nothing noted since the last refresh (a window move not yet noted is
  /// found by refresh(), not here).
  bool current() const { return changes_.computed && changes_.pending.empty() && changes_.stable == changes_.window; }
  /// note() then refresh().
  void update(ElevationMap& map, const CellBox& changed);
  void update(ElevationMap& map, const ChangedRows& changed);
  /// Every cell from scratch (after a map filter, a resume, or edits that
  /// did not report their cells).
  void recompute_all(ElevationMap& map);

  const FootholdOptions& options() const { return options_; }
  LayerId<float> slope() const { return slope_; }
  LayerId<float> roughness() const { return roughness_; }
  LayerId<float> step_height() const { return step_; }
  LayerId<float> edge_distance() const { return edge_distance_; }
  LayerId<float> score() const { return score_; }
  /// Cells whose geometry (slope, roughness, step) the last refresh
  /// recomputed: the cost measure of the benchmark.
  std::size_t last_geometry_cells() const { return last_geometry_cells_; }
  /// Cells whose edge distance and score the last refresh recomputed.
  std::size_t last_score_cells() const { return last_score_cells_; }
  /// Cells whose distance to the nearest edge the last refresh searched for.
  std::size_t last_edge_cells() const { return last_edge_cells_; }

 private:
  void compute(ElevationMap& map);
  bool compute_without_known_cells(ElevationMap& map);
  void geometry_rows(ElevationMap& map);
  void score_rows(ElevationMap& map);
  double edge_distance_m_of(std::int64_t squared_cells, std::int64_t none2) const;
  double edge_factor_of_distance(double distance_m) const;

  FootholdOptions options_;
  LayerId<float> slope_, roughness_, step_, edge_distance_, score_;
  int n_ = 0;
  double cell_size_m_ = 0.0;
  FootholdStencil stencil_;
  PartialInverses inverses_;
  PaddedElevations padded_;
  FootholdChanges changes_;
  FootholdEdgeSearch edges_;
  // Per squared edge distance 0..r*r+1 (r*r+1: none within the radius):
  // the distance [m] and the score's edge factor, as the score computes them.
  std::vector<double> edge_distance_of_, edge_factor_of_;
  // score_rows()'s scratch: a batch of the cells it scores, with their
  // edge factors.
  std::vector<std::size_t> score_slots_;
  std::vector<double> score_edge_factors_;
  std::size_t last_geometry_cells_ = 0;
  std::size_t last_score_cells_ = 0;
  std::size_t last_edge_cells_ = 0;
};

}  // namespace stridemap
