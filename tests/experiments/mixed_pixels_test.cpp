#include "stridemap/experiments/mixed_pixels.hpp"

#include <string>

#include <gtest/gtest.h>

#include "stridemap/config/scene_yaml.hpp"
#include "test_paths.hpp"

namespace stridemap {
namespace {

// A shorter rail over the large box keeps the test quick.
Scene short_scene() {
  Scene scene = load_scene_yaml(std::string(STRIDEMAP_SOURCE_DIR) + "/scenes/cart_rail_boxes.yaml");
  scene.cart_rail = CartRailPath{0.15, 0.65, 0.0, 0.01, 0.0};
  return scene;
}

TEST(MixedPixelsExperiment, MixedPixelsAppearAndThePaperChainRemovesSome) {
  // One bar over all cases: it only moves forward and ends full.
  CartRailOptions options;
  double last_share = 0.0;
  bool went_back = false;
  options.progress = [&](std::size_t done, std::size_t total) {
    const double share = total ? static_cast<double>(done) / static_cast<double>(total) : 0.0;
    went_back |= share + 1e-12 < last_share;
    last_share = share;
  };
  const MixedPixelsResult r = run_mixed_pixels(short_scene(), options);
  ASSERT_EQ(r.rows.size(), default_mixed_pixels_cases().size());
  EXPECT_FALSE(went_back);
  EXPECT_DOUBLE_EQ(last_share, 1.0);
  const auto row_named = [&](const std::string& prefix) -> const MixedPixelsRow& {
    for (const MixedPixelsRow& row : r.rows)
      if (row.config.name.rfind(prefix, 0) == 0) return row;
    ADD_FAILURE() << "no case " << prefix;
    return r.rows.front();
  };
  const MixedPixelsRow& reference = row_named("no mixed pixels");
  const MixedPixelsRow& none = row_named("none");
  const MixedPixelsRow& ideal = row_named("ideal");
  EXPECT_EQ(reference.beams.mixed, 0u);  // one ray per beam cannot mix
  EXPECT_GT(none.beams.mixed, 20u);
  EXPECT_GT(none.score.artifact_cells, reference.score.artifact_cells);
  EXPECT_EQ(none.beams.mixed_removed + none.beams.clean_removed, 0u);
  // The ideal filter removes exactly the labelled beams, and its map is the
  // yardstick of the mixed-pixel artifact reduction.
  EXPECT_EQ(ideal.beams.mixed_removed, ideal.beams.mixed);
  EXPECT_EQ(ideal.beams.clean_removed, 0u);
  EXPECT_LT(ideal.score.artifact_cells, none.score.artifact_cells);
  EXPECT_DOUBLE_EQ(mixed_artifact_reduction(r, ideal), 1.0);
  EXPECT_DOUBLE_EQ(mixed_artifact_reduction(r, none), 0.0);
  for (const MixedPixelsRow& row : r.rows) {
    if (row.config.name.rfind("paper", 0) != 0) continue;
    EXPECT_GT(row.beams.mixed_recall(), 0.3);
    EXPECT_LT(row.score.artifact_cells, none.score.artifact_cells);
    EXPECT_LT(row.beams.clean_drop_rate(), 0.03);
    EXPECT_GT(mixed_artifact_reduction(r, row), 0.5);
  }
  EXPECT_GT(r.paper.snapshot.elevation_m().size(), 0);
  EXPECT_GT(r.unfiltered.snapshot.elevation_m().size(), 0);
}

TEST(MixedPixelsExperiment, FilterRemovalsAreCountedAgainstTheLabels) {
  CartRailOptions options;
  options.mixed_pixels = true;
  options.filters = {ScanFilterKind::shadow};
  const CartRailResult r = run_cart_rail(short_scene(), options);
  EXPECT_GT(r.beams.mixed_removed + r.beams.clean_removed, 0u);
  EXPECT_LE(r.beams.mixed_removed, r.beams.mixed);
  EXPECT_LE(r.beams.clean_removed, r.beams.clean);
  EXPECT_GE(r.beams.f1(), 0.0);
  EXPECT_LE(r.beams.f1(), 1.0);
}

TEST(MixedPixelsExperiment, CleanBeamsEndingInsideTheMapAreCountedApart) {
  CartRailOptions options;
  options.mixed_pixels = true;
  const CartRailResult none = run_cart_rail(short_scene(), options);
  options.filters = {ScanFilterKind::range_clustering, ScanFilterKind::scan_sequence};
  const CartRailResult paper = run_cart_rail(short_scene(), options);
  // The fixed window holds what the rail sweeps within 0.9 m; the far
  // floor at the scan's sides lies beyond it.
  EXPECT_GT(none.beams.clean_in_window, 0u);
  EXPECT_LT(none.beams.clean_in_window, none.beams.clean);
  EXPECT_EQ(none.beams.clean_in_window_removed, 0u);
  // The same scans, whether the filters hold one back or not: each scan's
  // beams are matched with their own ends.
  EXPECT_EQ(paper.beams.clean, none.beams.clean);
  EXPECT_EQ(paper.beams.clean_in_window, none.beams.clean_in_window);
  EXPECT_GT(paper.beams.clean_removed, 0u);
  EXPECT_LE(paper.beams.clean_in_window_removed, paper.beams.clean_removed);
  EXPECT_LE(paper.beams.clean_in_window_drop_rate(), 1.0);
}

}  // namespace
}  // namespace stridemap
