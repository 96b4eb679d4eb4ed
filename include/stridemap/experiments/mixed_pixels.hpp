#pragma once
// The mixed-pixel experiment (paper section 5.3, Figs. 12-15 and 18): the
// cart-rail run with the footprint beam model, once per filter, scored
// against the simulator's beam labels and the scene's ground truth.
// Results are from the simulator, not from a real sensor.
#include <string>
#include <vector>

#include "stridemap/experiments/cart_rail.hpp"

namespace stridemap {

struct MixedPixelsCase {
  std::string name;
  bool mixed_pixels = true;
  std::vector<ScanFilterKind> filters;
  MapFilter map_filter = MapFilter::fill;
  /// The ideal filter (CartRailOptions::drop_labelled_mixed): reference only.
  bool drop_labelled_mixed = false;
};

/// The cases the experiment compares: no filtering, each filter alone (a
/// registered one too, scan_filter_registry.hpp), the paper's combination,
/// the CAS filter on the map, and two references: a run
/// without mixed pixels and the ideal filter that drops exactly the beams
/// labelled mixed.
std::vector<MixedPixelsCase> default_mixed_pixels_cases();

struct MixedPixelsRow {
  MixedPixelsCase config;
  BeamTally beams;
  MapScore score;
  std::size_t cas_removed_cells = 0;
};

struct MixedPixelsResult {
  std::vector<MixedPixelsRow> rows;
  CartRailResult unfiltered;  ///< "none": the map before filtering
  CartRailResult paper;       ///< "paper": after the paper's combination
  CartRailResult cas;         ///< "cas": the CAS filter instead
};

/// Runs every case with `base` (seed, mount, map...) on the scene.
MixedPixelsResult run_mixed_pixels(const Scene& scene, const CartRailOptions& base,
                                   const std::vector<MixedPixelsCase>& cases = default_mixed_pixels_cases());

/// Share of the mixed-pixel artifacts a case removes: artifact cells of
/// "none" minus the case's, over "none" minus the ideal filter's (the cells
/// the ideal filter leaves wrong are not the mixed pixels' doing). 0 when
/// either reference is missing or the ideal filter removes nothing.
double mixed_artifact_reduction(const MixedPixelsResult& result, const MixedPixelsRow& row);

std::string mixed_pixels_table(const MixedPixelsResult& result);
std::string mixed_pixels_summary_json(const MixedPixelsResult& result, const CartRailOptions& base,
                                      const std::string& scene_path);
/// Maps before/after as PNG, summary.json; throws InputError naming the file
/// that cannot be written.
void write_mixed_pixels_outputs(const MixedPixelsResult& result, const CartRailOptions& base,
                                const std::string& scene_path, const std::string& directory);

}  // namespace stridemap
