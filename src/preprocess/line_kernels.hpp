#pragma once
// The passes over a cluster's points that the line extractor repeats
// (internal): its points, the farthest from a chord, a merge's residual
// test, a fitted line's residuals and extent. Four points a vector where
// the CPU has AVX2, chosen at run time; no FMA and no reordered sums, so
// each gives the bits of the plain loop it stands for.
#include <cstddef>

#include "stridemap/preprocess/range_sigma.hpp"

namespace stridemap::detail {

/// x = r cos, y = r sin of beams [first, last]; the largest sigma_r among
/// them, and the largest range (which bounds |x|, |y| and their means).
double cluster_points(const double* range, const double* range_error, const double* cos, const double* sin,
                      std::size_t first, std::size_t last, const RangeSigmaModel& sigma, double* x, double* y,
                      double& max_range_m);

struct ChordFarthest {
  std::size_t index = static_cast<std::size_t>(-1);  ///< none when no cross product exceeds -1
  double cross = -1.0;
  /// At least every other point's cross product: a larger value costs the
  /// caller a search for ties, never a wrong answer.
  double runner_up = -1.0;
};

/// Over i in [begin, end): the first point with the largest
/// |(x - ax) dy - (y - ay) dx|.
ChordFarthest farthest_from_chord(const double* x, const double* y, std::size_t begin, std::size_t end, double ax,
                                  double ay, double dx, double dy);

struct LineExtent {
  double max_residual_m = 0.0;
  double along_min_m = 0.0;
  double along_max_m = 0.0;
};

/// Largest |x nx + y ny - rho| and the range of -x ny + y nx over points
/// [first, last], as std::max and std::min taken in beam order; false as
/// soon as a residual exceeds `limit_m`.
bool line_extent(const double* x, const double* y, std::size_t first, std::size_t last, double nx, double ny,
                 double rho, double limit_m, LineExtent& extent);

enum class Verdict : unsigned char { inside, outside, unsure };

/// Whether every |x nx + y ny - rho| over points [first, last] is at most
/// `inside_m` (inside), one exceeds `outside_m` (outside), or neither.
Verdict residuals_within(const double* x, const double* y, std::size_t first, std::size_t last, double nx, double ny,
                         double rho, double inside_m, double outside_m);

}  // namespace stridemap::detail
