#include "stridemap/experiments/map_evaluation.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

#include "stridemap/core/error.hpp"

namespace stridemap {

SurfaceSpan surface_span(const Scene& scene, double min_x_m, double min_y_m, double max_x_m, double max_y_m,
                         int samples_per_side) {
  SurfaceSpan span;
  span.high_m = scene.max_height_in_rect(min_x_m, min_y_m, max_x_m, max_y_m);
  span.low_m = std::numeric_limits<double>::infinity();
  const double width = max_x_m - min_x_m, depth = max_y_m - min_y_m;
  for (int a = 0; a < samples_per_side; ++a) {
    for (int b = 0; b < samples_per_side; ++b) {
      const double fx = (a + 0.5) / samples_per_side, fy = (b + 0.5) / samples_per_side;
      span.low_m = std::min(span.low_m, scene.surface_height_at(min_x_m + fx * width, min_y_m + fy * depth));
    }
  }
  return span;
}

MapSnapshot snapshot_with_truth(const ElevationMap& map, const Scene& scene, double object_margin_m) {
  if (!(object_margin_m >= 0.0) || !std::isfinite(object_margin_m)) {
    throw InputError("map evaluation: the object margin must be finite and >= 0 m");
  }
  MapSnapshot snapshot{export_map(map), {}, {}, {}, {}};
  const int n = map.cells_per_side();
  snapshot.truth_m.resize(n, n);
  snapshot.span_low_m.resize(n, n);
  snapshot.span_high_m.resize(n, n);
  snapshot.clear_of_objects.resize(n, n);
  Scene bare;
  bare.terrain = scene.terrain;
  const double s = map.cell_size_m();
  const double m = object_margin_m;
  for (int i = 0; i < n; ++i) {
    for (int j = 0; j < n; ++j) {
      const CellIndex c = map.cell_at_local(i, j);
      const double x0 = static_cast<double>(c.x) * s;
      const double y0 = static_cast<double>(c.y) * s;
      snapshot.truth_m(i, j) = static_cast<float>(scene.max_height_in_rect(x0, y0, x0 + s, y0 + s));
      // An object raises the grown cell's highest point above the bare
      // terrain's; one flush with the ground does not, and is floor.
      const SurfaceSpan span = surface_span(scene, x0 - m, y0 - m, x0 + s + m, y0 + s + m);
      const double without = bare.max_height_in_rect(x0 - m, y0 - m, x0 + s + m, y0 + s + m);
      snapshot.clear_of_objects(i, j) = span.high_m <= without ? 1 : 0;
      snapshot.span_high_m(i, j) = static_cast<float>(span.high_m);
      // Sampled points are never below the lowest, but keep the ends ordered.
      snapshot.span_low_m(i, j) = std::min(static_cast<float>(span.low_m), snapshot.span_high_m(i, j));
    }
  }
  return snapshot;
}

MapScore score_map(const MapSnapshot& snapshot, const CellMask& area, const MapScoreOptions& options) {
  MapScore score;
  score.artifact_threshold_m = options.artifact_threshold_m;
  score.level_relief_m = options.level_relief_m;
  if (!(options.level_relief_m >= 0.0) || !std::isfinite(options.level_relief_m)) {
    throw InputError("map evaluation: level_relief_m must be finite and >= 0 m");
  }
  double sum_sq = 0.0, sum = 0.0, sum_sq_measured = 0.0, sum_sq_filled = 0.0, sum_sq_level = 0.0, sum_sq_span = 0.0;
  const Eigen::MatrixXf& elevation = snapshot.elevation_m();
  const CellMask& states = snapshot.state();
  const bool clear = snapshot.clear_of_objects.rows() == elevation.rows() &&
                     snapshot.clear_of_objects.cols() == elevation.cols();
  const bool span = snapshot.span_low_m.rows() == elevation.rows() && snapshot.span_low_m.cols() == elevation.cols() &&
                    snapshot.span_high_m.rows() == elevation.rows() && snapshot.span_high_m.cols() == elevation.cols();
  for (Eigen::Index i = 0; i < elevation.rows(); ++i) {
    for (Eigen::Index j = 0; j < elevation.cols(); ++j) {
      if (!area(i, j)) continue;
      ++score.scored_area_cells;
      const auto state = static_cast<CellState>(states(i, j));
      if (state == CellState::unknown) continue;
      const double error = static_cast<double>(elevation(i, j)) - snapshot.truth_m(i, j);
      ++score.known_cells;
      sum += error;
      sum_sq += error * error;
      if (state == CellState::measured) {
        ++score.measured_cells;
        sum_sq_measured += error * error;
      } else {
        ++score.filled_cells;
        sum_sq_filled += error * error;
      }
      score.max_error_m = std::max(score.max_error_m, std::abs(error));
      if (std::abs(error) > options.artifact_threshold_m) ++score.artifact_cells;
      if (span) {
        const double low = snapshot.span_low_m(i, j), high = snapshot.span_high_m(i, j);
        const double height = elevation(i, j);
        const double beyond = height > high ? height - high : height < low ? low - height : 0.0;
        sum_sq_span += beyond * beyond;
        score.max_beyond_span_m = std::max(score.max_beyond_span_m, beyond);
        if (beyond > options.artifact_threshold_m) ++score.beyond_span_artifact_cells;
        if (high - low <= options.level_relief_m) {
          ++score.level_cells;
          sum_sq_level += error * error;
        }
      }
      if (clear && snapshot.clear_of_objects(i, j)) {
        ++score.clear_cells;
        score.clear_max_error_m = std::max(score.clear_max_error_m, std::abs(error));
        if (std::abs(error) > options.artifact_threshold_m) ++score.clear_artifact_cells;
      }
    }
  }
  const auto rms = [](double total, std::size_t count) {
    return count ? std::sqrt(total / static_cast<double>(count)) : 0.0;
  };
  score.rms_error_m = rms(sum_sq, score.known_cells);
  score.rms_error_measured_m = rms(sum_sq_measured, score.measured_cells);
  score.rms_error_filled_m = rms(sum_sq_filled, score.filled_cells);
  score.rms_error_level_m = rms(sum_sq_level, score.level_cells);
  score.rms_beyond_span_m = span ? rms(sum_sq_span, score.known_cells) : 0.0;
  score.mean_error_m = score.known_cells ? sum / static_cast<double>(score.known_cells) : 0.0;
  score.coverage =
      score.scored_area_cells ? static_cast<double>(score.known_cells) / static_cast<double>(score.scored_area_cells) : 0.0;
  return score;
}

}  // namespace stridemap
