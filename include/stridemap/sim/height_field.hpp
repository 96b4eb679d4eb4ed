#pragma once
// Terrain of a simulated scene: z = height(x, y), bilinear between samples on
// a regular grid, flat at base_elevation_m outside the grid's extent (or
// everywhere when there are no samples). Ray casting on it is exact: inside a
// grid cell the bilinear surface restricted to a straight ray is a quadratic
// in the ray parameter, so the cast walks the cells the ray crosses (2D DDA)
// and brackets the first sign change of (ray height - surface height) in
// each cell from the quadratic itself. No crossing is ever stepped over,
// however thin the peak or however grazing the ray.
#include <cstdint>
#include <limits>
#include <optional>
#include <vector>

#include <Eigen/Core>

#include "stridemap/sim/rocks.hpp"
#include "stridemap/sim/scene_problem.hpp"

namespace stridemap {

/// The nearest surface a ray meets.
struct RayHit {
  double range_m = 0.0;              ///< distance from the ray origin [m]
  Eigen::Vector3d point_m = Eigen::Vector3d::Zero();  ///< hit point in the map frame
  Eigen::Vector3d normal = Eigen::Vector3d::UnitZ();  ///< unit outward surface normal
  double reflectance = 0.5;          ///< diffuse reflectance of the surface hit
  int object_index = -1;             ///< -1 terrain, then 0.. boxes, then cylinders
};

struct HeightField {
  /// Extent of the sampled area [m]; outside it the terrain is flat at
  /// base_elevation_m. With samples, max_x_m must equal
  /// min_x_m + (nx - 1) * resolution_m (and likewise for y).
  double min_x_m = -1, min_y_m = -1, max_x_m = 3, max_y_m = 1;
  double base_elevation_m = 0;  ///< elevation of the flat part [m]
  double resolution_m = 0.01;   ///< sample spacing [m]
  /// Heights [m], row-major: ny rows along y, nx columns along x; sample
  /// (i, j) sits at (min_x_m + i * resolution_m, min_y_m + j * resolution_m).
  /// Empty: the terrain is flat everywhere.
  std::vector<float> samples;
  int nx = 0, ny = 0;
  double reflectance = 0.5;  ///< diffuse reflectance at 785 nm, (0, 1]

  bool is_flat() const { return samples.empty(); }
  bool in_extent(double x_m, double y_m) const {
    return x_m >= min_x_m && x_m <= max_x_m && y_m >= min_y_m && y_m <= max_y_m;
  }
  /// Terrain height at a point (bilinear inside the extent); NaN for a
  /// non-finite point.
  double height_at(double x_m, double y_m) const;
  /// Upward unit normal of the terrain at a point.
  Eigen::Vector3d normal_at(double x_m, double y_m) const;
  /// Highest sample, or base_elevation_m when flat. O(samples).
  double max_sample_height_m() const;
  /// Exact maximum of the terrain over a closed axis-aligned rectangle. The
  /// bilinear patch is linear along every axis-parallel line, so its maximum
  /// over a rectangle lies at a corner of the rectangle clipped to a cell:
  /// the sample vertices inside, the rectangle's boundary where it crosses
  /// grid lines, and the rectangle's corners. Where the rectangle leaves the
  /// extent, base_elevation_m counts too. NaN for a non-finite corner.
  double max_height_in_rect(double min_x_m, double min_y_m, double max_x_m, double max_y_m) const;

  /// First point where the ray meets the terrain within max_range_m, with
  /// the terrain's reflectance and object_index -1. An origin on or below
  /// the surface hits at range 0. Where the sampled extent meets the flat
  /// outside at a different height, the step between them is a vertical
  /// wall. known_top_m: an upper bound of all samples (e.g. from
  /// max_sample_height_m(), computed once); it only lets the cast skip the
  /// part of the ray that is above every sample, never changes the answer.
  std::optional<RayHit> cast_ray(const Eigen::Vector3d& origin, const Eigen::Vector3d& unit_dir,
                                 double max_range_m,
                                 double known_top_m = std::numeric_limits<double>::infinity()) const;
};

/// Options of the procedural terrain: smooth value noise (random values on a
/// square lattice, quintic-smoothstep interpolation) summed over octaves of
/// halving wavelength and halving weight. The ground stays within
/// base_elevation_m +/- amplitude_m; rocks (if any) rise above it.
struct ProceduralTerrainOptions {
  double min_x_m = -1, min_y_m = -1, max_x_m = 3, max_y_m = 1;  ///< extent [m]
  double resolution_m = 0.01;  ///< sample spacing [m]
  double amplitude_m = 0.05;   ///< largest deviation from base_elevation_m [m], >= 0
  double wavelength_m = 0.3;   ///< lattice spacing of the coarsest octave [m]
  int octaves = 3;             ///< number of octaves, 1..8
  double base_elevation_m = 0.0;
  double reflectance = 0.5;    ///< diffuse reflectance at 785 nm, (0, 1]
  /// Boulders on the ground (sim/rocks.hpp); none by default. Their
  /// placement draws from its own generator, so adding rocks leaves the
  /// ground of a seed as it was.
  RockFieldOptions rocks{};

  /// First unusable option (field_path is the option's name), if any.
  std::optional<SceneProblem> first_problem() const;
};

/// Largest number of samples a procedural field may have (about 200 MB);
/// more means a resolution typo, not a terrain.
inline constexpr std::int64_t max_height_field_samples = 50'000'000;

/// Deterministic for a seed. Throws InputError "<option>: <problem>" when
/// the options are unusable.
HeightField make_procedural_height_field(const ProceduralTerrainOptions& options, std::uint64_t seed);

}  // namespace stridemap
