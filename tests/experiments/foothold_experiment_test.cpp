// The foothold experiment's scoring: truth layers from true heights, the
// confusion counts of "safe", precision and recall.
#include <cmath>
#include <limits>

#include <gtest/gtest.h>

#include "stridemap/core/error.hpp"
#include "stridemap/experiments/foothold.hpp"

namespace stridemap {
namespace {

constexpr int kN = 40;

// Flat ground with a 10 cm block on the cells x >= 0.
Eigen::MatrixXf block_truth(const ElevationMap& map) {
  Eigen::MatrixXf truth(kN, kN);
  for (int i = 0; i < kN; ++i)
    for (int j = 0; j < kN; ++j) truth(i, j) = map.cell_at_local(i, j).x >= 0 ? 0.1f : 0.0f;
  return truth;
}

TEST(FootholdExperiment, AMapEqualToTheTruthIsScoredPerfectly) {
  const ElevationMap geometry(GridOptions{kN, 0.01});
  const Eigen::MatrixXf heights = block_truth(geometry);
  const FootholdOptions options;
  const ElevationMap truth = truth_foothold_map(geometry, heights, options);
  const CellMask area = CellMask::Ones(kN, kN);
  const FootholdRun run = score_footholds(truth, truth, area, options);
  // Every cell but the window's four corners, whose footprints hold 6 of
  // 13 cells: too few, so the truth there is unknown and not scored.
  EXPECT_EQ(run.all.scored_cells, static_cast<std::size_t>(kN * kN - 4));
  EXPECT_EQ(run.all.false_safe, 0u);
  EXPECT_EQ(run.all.false_unsafe, 0u);
  EXPECT_GT(run.all.true_safe, 0u);
  EXPECT_GT(run.all.true_unsafe, 0u);  // the block's edge
  EXPECT_DOUBLE_EQ(run.all.precision(), 1.0);
  EXPECT_DOUBLE_EQ(run.all.recall(), 1.0);
  EXPECT_DOUBLE_EQ(run.mean_slope_error_deg, 0.0);
}

TEST(FootholdExperiment, AMapThatMissesTheBlockCallsItsEdgeSafe) {
  const ElevationMap geometry(GridOptions{kN, 0.01});
  const FootholdOptions options;
  const ElevationMap truth = truth_foothold_map(geometry, block_truth(geometry), options);
  // The map saw flat ground everywhere, and nothing at all in one column.
  Eigen::MatrixXf flat = Eigen::MatrixXf::Zero(kN, kN);
  flat.col(5).setConstant(std::numeric_limits<float>::quiet_NaN());
  const ElevationMap map = truth_foothold_map(geometry, flat, options);
  const FootholdRun run = score_footholds(map, truth, CellMask::Ones(kN, kN), options);
  // The unknown column is not mapped; the corners' truth is unknown.
  EXPECT_EQ(run.all.scored_cells, static_cast<std::size_t>(kN * (kN - 1) - 4));
  EXPECT_GT(run.all.false_safe, 0u);
  EXPECT_LT(run.all.precision(), 1.0);
  EXPECT_EQ(run.all.false_unsafe, 0u);
  EXPECT_DOUBLE_EQ(run.all.recall(), 1.0);
  // Half the area scored: only the masked cells count.
  CellMask half = CellMask::Zero(kN, kN);
  half.topRows(kN / 2).setOnes();
  EXPECT_LT(score_footholds(map, truth, half, options).all.scored_cells, run.all.scored_cells);
}

TEST(FootholdExperiment, MismatchedInputsAreRefused) {
  const ElevationMap geometry(GridOptions{kN, 0.01});
  EXPECT_THROW(truth_foothold_map(geometry, Eigen::MatrixXf::Zero(3, 3), FootholdOptions{}), InputError);
  const ElevationMap truth = truth_foothold_map(geometry, Eigen::MatrixXf::Zero(kN, kN), FootholdOptions{});
  EXPECT_THROW(score_footholds(truth, truth, CellMask::Ones(2, 2), FootholdOptions{}), InputError);
  FootholdExperimentOptions bad;
  bad.foothold.max_step_m = -1.0;
  EXPECT_THROW(bad.validate(), InputError);
}

TEST(FootholdExperiment, EmptyCountsGiveNaNNotAFakeScore) {
  const FootholdConfusion none;
  EXPECT_TRUE(std::isnan(none.precision()));
  EXPECT_TRUE(std::isnan(none.recall()));
}

}  // namespace
}  // namespace stridemap
