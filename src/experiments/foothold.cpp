#include "stridemap/experiments/foothold.hpp"

#include <cmath>
#include <limits>
#include <utility>

#include "stridemap/core/error.hpp"

namespace stridemap {
namespace {

constexpr double kFootholdNaN = std::numeric_limits<double>::quiet_NaN();

void count(FootholdConfusion& c, float map_score, bool truth_safe, double threshold) {
  ++c.scored_cells;
  if (std::isnan(map_score)) ++c.unknown_score;
  const bool map_safe = map_score >= threshold;  // NaN: not safe
  if (map_safe && truth_safe) ++c.true_safe;
  if (map_safe && !truth_safe) ++c.false_safe;
  if (!map_safe && truth_safe) ++c.false_unsafe;
  if (!map_safe && !truth_safe) ++c.true_unsafe;
}

}  // namespace

double FootholdConfusion::precision() const {
  const std::size_t called = true_safe + false_safe;
  return called ? static_cast<double>(true_safe) / static_cast<double>(called) : kFootholdNaN;
}

double FootholdConfusion::recall() const {
  const std::size_t safe = true_safe + false_unsafe;
  return safe ? static_cast<double>(true_safe) / static_cast<double>(safe) : kFootholdNaN;
}

FootholdConfusion& FootholdConfusion::operator+=(const FootholdConfusion& o) {
  scored_cells += o.scored_cells;
  true_safe += o.true_safe;
  false_safe += o.false_safe;
  false_unsafe += o.false_unsafe;
  true_unsafe += o.true_unsafe;
  unknown_score += o.unknown_score;
  return *this;
}

void FootholdExperimentOptions::validate() const { validate_foothold_options(foothold); }

ElevationMap truth_foothold_map(const ElevationMap& map, const Eigen::MatrixXf& truth_m, const FootholdOptions& options) {
  const int n = map.cells_per_side();
  if (truth_m.rows() != n || truth_m.cols() != n) {
    throw InputError("foothold truth: a " + std::to_string(truth_m.rows()) + " x " + std::to_string(truth_m.cols()) +
                     " truth for a map of " + std::to_string(n) + " x " + std::to_string(n) + " cells");
  }
  ElevationMap truth(GridOptions{n, map.cell_size_m()});
  truth.move_corner_to(map.min_cell());
  for (int i = 0; i < n; ++i) {
    for (int j = 0; j < n; ++j) {
      const std::size_t s = truth.slot(truth.cell_at_local(i, j));
      const float z = truth_m(i, j);
      if (!std::isfinite(z)) continue;  // no scene there: unknown
      truth.elevation_data()[s] = z;
      truth.certainty_data()[s] = static_cast<float>(options.full_certainty);
      truth.state_data()[s] = static_cast<std::uint8_t>(CellState::measured);
    }
  }
  FootholdLayers(truth, options).recompute_all(truth);
  return truth;
}

FootholdRun score_footholds(const ElevationMap& map, const ElevationMap& truth, const CellMask& area,
                            const FootholdOptions& options) {
  const int n = map.cells_per_side();
  if (truth.cells_per_side() != n || !(truth.min_cell() == map.min_cell()) || area.rows() != n || area.cols() != n) {
    throw InputError("foothold scoring: the map, its truth and the scored area must cover the same window");
  }
  const auto score = map.layer<float>("foothold_score"), truth_score = truth.layer<float>("foothold_score");
  const auto slope = map.layer<float>("slope_deg"), truth_slope = truth.layer<float>("slope_deg");
  const auto step = map.layer<float>("step_height_m"), truth_step = truth.layer<float>("step_height_m");
  FootholdRun run;
  double slope_error = 0.0, step_error = 0.0, score_error = 0.0;
  std::size_t compared = 0;
  for (int i = 0; i < n; ++i) {
    for (int j = 0; j < n; ++j) {
      if (!area(i, j)) continue;
      const CellIndex c = map.cell_at_local(i, j);
      const auto state = map.state(c);
      if (state == CellState::unknown) continue;
      const std::size_t s = map.slot(c), t = truth.slot(c);
      const float truth_value = truth.data(truth_score)[t];
      if (std::isnan(truth_value)) continue;  // off the scene: nothing to compare with
      const bool truth_safe = truth_value >= options.safe_score;
      run.truth_safe_cells += truth_safe;
      const float value = map.data(score)[s];
      count(run.all, value, truth_safe, options.safe_score);
      if (state == CellState::measured) count(run.measured, value, truth_safe, options.safe_score);
      if (std::isnan(value)) continue;
      slope_error += std::abs(map.data(slope)[s] - truth.data(truth_slope)[t]);
      step_error += std::abs(map.data(step)[s] - truth.data(truth_step)[t]);
      score_error += std::abs(value - truth_value);
      ++compared;
    }
  }
  if (compared) {
    const auto k = static_cast<double>(compared);
    run.mean_slope_error_deg = slope_error / k;
    run.mean_step_error_m = step_error / k;
    run.mean_score_error = score_error / k;
  } else {
    run.mean_slope_error_deg = run.mean_step_error_m = run.mean_score_error = kFootholdNaN;
  }
  return run;
}

FootholdRun run_foothold_walk(const Scene& scene, const WalkPath& path, WalkSensor& sensor,
                              const FootholdExperimentOptions& options, FootholdExperimentResult* keep) {
  options.validate();
  WalkOptions walk = options.walk;
  walk.build_mosaic = true;
  walk.score_against_truth = true;
  WalkResult result = run_walk(scene, path, sensor, walk);
  FootholdLayers(result.map, options.foothold).recompute_all(result.map);
  ElevationMap truth = truth_foothold_map(result.map, result.mosaic.truth_m, options.foothold);
  FootholdRun run = score_footholds(result.map, truth, result.mosaic_swept, options.foothold);
  run.seed = walk.seed;
  if (keep) {
    keep->first_map = std::move(result.map);
    keep->first_truth = std::move(truth);
    keep->first_swept = std::move(result.mosaic_swept);
  }
  return run;
}

}  // namespace stridemap
